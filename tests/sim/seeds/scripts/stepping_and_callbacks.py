"""Time stepping and callbacks: physics at 120 Hz rendered at 30 Hz, physics, timeline and
render callbacks, play / pause / stop, Kit-style app updates and a coroutine scheduled with
asyncio.ensure_future. Only the imports differ from Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import asyncio
import numpy as np
from manip.sim import World
from manip.sim import DynamicCuboid

world = World(stage_units_in_meters=1.0, physics_dt=1.0 / 120.0, rendering_dt=1.0 / 30.0)
world.scene.add_default_ground_plane()
cube = world.scene.add(DynamicCuboid(prim_path="/World/cube", name="cube", position=np.array([0, 0, 1.0]),
                                     size=0.1))

physics_steps = []
timeline_events = []
renders = []


def on_physics_step(step_size):
    physics_steps.append(step_size)


def on_timeline_event(event):
    timeline_events.append(event.type)


world.add_physics_callback("count_physics", callback_fn=on_physics_step)
world.add_timeline_callback("watch_timeline", on_timeline_event)
world.add_render_callback("count_renders", lambda event: renders.append(world.current_time))
world.reset()
t_reset = world.current_time

for _ in range(10):
    world.step(render=True)  # 4 physics steps per rendered frame
steps_rendered = len(physics_steps)
for _ in range(10):
    world.step(render=False)  # one physics step each
steps_unrendered = len(physics_steps) - steps_rendered

world.pause()
t_paused = world.current_time
for _ in range(5):
    world.step(render=True)
paused_still = world.current_time == t_paused

world.play()
for _ in range(15):
    simulation_app.update()  # Kit's loop: physics advances while playing
t_updates = world.current_time - t_paused

asyncio.ensure_future(world.stop_async())  # runs at the next frame, as Kit's loop would
world.step(render=True)
stopped = world.is_stopped()
world.reset()
cube_start = cube.get_world_pose()[0]
for _ in range(30):
    world.step(render=True)
fell = float(cube_start[2] - cube.get_world_pose()[0][2])
world.remove_physics_callback("count_physics")
print("steps", steps_rendered, steps_unrendered, "timeline", timeline_events, "updates", t_updates)
simulation_app.close()
