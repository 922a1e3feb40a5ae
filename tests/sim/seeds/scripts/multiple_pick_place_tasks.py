"""Two PickPlace tasks side by side, each with its Franka and its cube, offset by the task's
offset (the pattern of Isaac's "Multiple Tasks" tutorial), a PickPlaceController per robot,
a physics callback counting steps, and each task's own metrics and is_done read through the
World. Written as for Isaac Sim 4.x; only the imports differ (omni.isaac... -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import PickPlace
from manip.sim import PickPlaceController
from manip.sim import euler_angles_to_quat
from manip.sim import rotational_distance_single_axis, tf_matrix_from_pose


class TimedPickPlace(PickPlace):
    """Isaac's PickPlace with the metrics a training script adds: how far the cube is from its
    target, and done once it rests there."""

    def calculate_metrics(self) -> dict:
        cube_position, _ = self._cube.get_world_pose()
        return {"distance_to_target": float(np.linalg.norm(cube_position[:2] - self._target_position[:2]))}

    def is_done(self) -> bool:
        return self.calculate_metrics()["distance_to_target"] < 0.02


my_world = World(stage_units_in_meters=1.0)
num_tasks = 2
for i in range(num_tasks):
    my_world.add_task(TimedPickPlace(name="task_" + str(i), offset=np.array([0, (i * 2) - 1, 0])))
my_world.reset()

physics_steps = []
my_world.add_physics_callback("count_steps", callback_fn=lambda step_size: physics_steps.append(step_size))

frankas, cube_names, robot_names, controllers = [], [], [], []
for i in range(num_tasks):
    task_params = my_world.get_task("task_" + str(i)).get_params()
    robot_names.append(task_params["robot_name"]["value"])
    cube_names.append(task_params["cube_name"]["value"])
    frankas.append(my_world.scene.get_object(robot_names[i]))
    controllers.append(PickPlaceController(name="pick_place_controller_" + str(i), gripper=frankas[i].gripper,
                                           robot_articulation=frankas[i]))

done = [False] * num_tasks
for step in range(4000):
    my_world.step(render=True)
    if not my_world.is_playing():
        continue
    observations = my_world.get_observations()
    for i in range(num_tasks):
        if controllers[i].is_done():
            done[i] = True
            continue
        actions = controllers[i].forward(
            picking_position=observations[cube_names[i]]["position"],
            placing_position=observations[cube_names[i]]["target_position"],
            current_joint_positions=observations[robot_names[i]]["joint_positions"],
            end_effector_offset=np.array([0, 0.005, 0]),
        )
        frankas[i].apply_action(actions)
    if all(done):
        break

for _ in range(30):  # let the cubes settle
    my_world.step(render=True)

metrics = my_world.calculate_metrics()
tasks_done = [my_world.get_task("task_" + str(i)).is_done() for i in range(num_tasks)]
all_done = my_world.is_done()
observations = my_world.get_observations()
cube_positions = [observations[name]["position"] for name in cube_names]
target_positions = [observations[name]["target_position"] for name in cube_names]
robot_positions = [franka.get_world_pose()[0] for franka in frankas]
# the hand points down at the end, as it placed the cube
hand_tilts = []
for franka in frankas:
    position, orientation = franka.end_effector.get_world_pose()
    hand_tilts.append(rotational_distance_single_axis(tf_matrix_from_pose(position, orientation),
                                                      tf_matrix_from_pose([0, 0, 0], euler_angles_to_quat([180, 0, 0],
                                                                                                          degrees=True)),
                                                      [0, 0, 1]))
simulation_app.close()
