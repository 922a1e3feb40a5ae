"""A Franka picks Isaac's default cube and places it, with the PickPlace task and the
PickPlaceController (the standalone "pick and place" pattern of Isaac's Franka examples).
Written as for Isaac Sim 4.x; only the imports differ (omni.isaac... -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import PickPlace
from manip.sim import PickPlaceController

my_world = World(stage_units_in_meters=1.0)
my_task = PickPlace()
my_world.add_task(my_task)
my_world.reset()
task_params = my_task.get_params()
my_franka = my_world.scene.get_object(task_params["robot_name"]["value"])
my_controller = PickPlaceController(
    name="pick_place_controller", gripper=my_franka.gripper, robot_articulation=my_franka
)
articulation_controller = my_franka.get_articulation_controller()

reset_needed = False
done = False
for i in range(3000):
    my_world.step(render=True)
    if my_world.is_stopped() and not reset_needed:
        reset_needed = True
    if my_world.is_playing():
        if reset_needed:
            my_world.reset()
            my_controller.reset()
            reset_needed = False
        observations = my_world.get_observations()
        actions = my_controller.forward(
            picking_position=observations[task_params["cube_name"]["value"]]["position"],
            placing_position=observations[task_params["cube_name"]["value"]]["target_position"],
            current_joint_positions=observations[task_params["robot_name"]["value"]]["joint_positions"],
            end_effector_offset=np.array([0, 0.005, 0]),
        )
        if my_controller.is_done():
            print("done picking and placing")
            done = True
            break
        articulation_controller.apply_action(actions)

observations = my_world.get_observations()
cube_position = observations[task_params["cube_name"]["value"]]["position"]
target_position = observations[task_params["cube_name"]["value"]]["target_position"]
print("cube at", cube_position, "target", target_position)
simulation_app.close()
