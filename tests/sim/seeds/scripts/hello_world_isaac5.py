"""Isaac Sim 5's "Hello World" standalone example: a blue cube falls on the ground plane and a
physics callback reads its state every step (isaacsim.core.api names). Only the imports differ
(isaacsim.core.api... -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import DynamicCuboid

world = World(stage_units_in_meters=1.0)
world.scene.add_default_ground_plane()
fancy_cube = world.scene.add(
    DynamicCuboid(
        prim_path="/World/random_cube",
        name="fancy_cube",
        position=np.array([0, 0, 1.0]),
        scale=np.array([0.5015, 0.5015, 0.5015]),
        color=np.array([0, 0, 1.0]),
    )
)

states = []


def print_cube_info(step_size):
    position, orientation = fancy_cube.get_world_pose()
    linear_velocity = fancy_cube.get_linear_velocity()
    states.append((step_size, position.copy(), linear_velocity.copy()))


world.add_physics_callback("sim_step", callback_fn=print_cube_info)
world.reset()
for i in range(120):
    world.step(render=True)
    if i % 30 == 0:
        position, orientation = fancy_cube.get_world_pose()
        print("Cube position is : " + str(position))
        print("Cube's orientation is : " + str(orientation))
        print("Cube's linear velocity is : " + str(fancy_cube.get_linear_velocity()))
world.remove_physics_callback("sim_step")
final_position, final_orientation = fancy_cube.get_world_pose()
simulation_app.close()
