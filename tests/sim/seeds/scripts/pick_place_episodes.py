"""Isaac Sim's Franka pick-and-place standalone example (PickPlace task + PickPlaceController),
with its own target (the Denso Cobotta example's), run for two episodes: the script resets the World and the
controller after the first and picks again. Only the imports differ
(isaacsim.core.api / isaacsim.robot.manipulators.examples.franka -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import PickPlace
from manip.sim import PickPlaceController

my_world = World(stage_units_in_meters=1.0, physics_dt=1 / 60, rendering_dt=1 / 60)
target_position = np.array([-0.3, 0.6, 0])
target_position[2] = 0.0515 / 2.0
my_task = PickPlace(name="denso_pick_place", target_position=target_position)
my_world.add_task(my_task)
my_world.reset()
my_franka = my_world.scene.get_object("my_franka") or my_world.scene.get_object(
    my_task.get_params()["robot_name"]["value"])
my_controller = PickPlaceController(name="controller", robot_articulation=my_franka, gripper=my_franka.gripper)
task_params = my_world.get_task("denso_pick_place").get_params()
articulation_controller = my_franka.get_articulation_controller()

episodes = []
i = 0
reset_needed = False
while simulation_app.is_running() and len(episodes) < 2 and i < 8000:
    my_world.step(render=True)
    i += 1
    if my_world.is_stopped() and not reset_needed:
        reset_needed = True
    if my_world.is_playing():
        if reset_needed:
            my_world.reset()
            reset_needed = False
            my_controller.reset()
        if my_world.current_time_step_index == 0:
            my_controller.reset()
        observations = my_world.get_observations()
        actions = my_controller.forward(
            picking_position=observations[task_params["cube_name"]["value"]]["position"],
            placing_position=observations[task_params["cube_name"]["value"]]["target_position"],
            current_joint_positions=observations[task_params["robot_name"]["value"]]["joint_positions"],
            end_effector_offset=np.array([0, 0.005, 0]),
        )
        if my_controller.is_done():
            cube = observations[task_params["cube_name"]["value"]]
            episodes.append((cube["position"].copy(), cube["target_position"].copy(), my_controller.failure))
            print(f"episode {len(episodes)} done: cube at {np.round(cube['position'], 3)}")
            my_world.reset()
            my_controller.reset()
            continue
        articulation_controller.apply_action(actions)
simulation_app.close()
