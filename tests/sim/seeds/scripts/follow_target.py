"""The Franka's end effector follows a target cube that the script moves (Isaac's
FollowTarget task with its RMPFlowController). Only the imports differ from Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import FollowTarget
from manip.sim import RMPFlowController

my_world = World(stage_units_in_meters=1.0)
my_task = FollowTarget(name="follow_target_task")
my_world.add_task(my_task)
my_world.reset()
task_params = my_world.get_task("follow_target_task").get_params()
franka_name = task_params["robot_name"]["value"]
target_name = task_params["target_name"]["value"]
my_franka = my_world.scene.get_object(franka_name)
my_controller = RMPFlowController(name="target_follower_controller", robot_articulation=my_franka)
articulation_controller = my_franka.get_articulation_controller()
target = my_world.scene.get_object(target_name)

waypoints = [np.array([0.45, 0.2, 0.35]), np.array([0.4, -0.25, 0.5])]
errors = []
for waypoint in waypoints:
    target.set_world_pose(position=waypoint)
    for i in range(240):
        my_world.step(render=True)
        if my_world.is_playing():
            observations = my_world.get_observations()
            actions = my_controller.forward(
                target_end_effector_position=observations[target_name]["position"],
                target_end_effector_orientation=observations[target_name]["orientation"],
            )
            articulation_controller.apply_action(actions)
    end_effector = my_franka.end_effector.get_world_pose()[0]
    errors.append(float(np.linalg.norm(end_effector - waypoint)))
    print(f"target {waypoint}: end effector {np.round(end_effector, 3)}, error {errors[-1]:.4f} m")
simulation_app.close()
