"""cuRobo's batch planning (examples/motion_gen_example.py, `demo_motion_gen_batch`) on manip,
played on a simulated Franka: two goals, the retract pose's hand moved, planned at once from
one start; `result.success` is the (2,) batch vector, `result.get_paths()` the trajectories,
each played in the World from its start. cuRobo's calls are manip's (plan_batch keeps its name;
cuRobo's (1, dof) JointState start is a (dof,) configuration; `get_retract_config()` is
`default_joint_positions`); the reading of the result is cuRobo's."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip import MotionGenerator, Pose
from manip.sim import World, Franka, ArticulationAction

my_world = World(stage_units_in_meters=1.0)
my_world.scene.add_default_ground_plane()
robot = my_world.scene.add(Franka("/World/Franka", name="franka"))
my_world.reset()

motion_gen = MotionGenerator("franka", interpolation_dt=1 / 60)
motion_gen.update_world_from_sim(my_world, robot)
retract_cfg = motion_gen.default_joint_positions
state = motion_gen.fk(retract_cfg, "panda_hand")
start_state = retract_cfg + 0.3
goal_position = np.repeat(state.position[None], 2, axis=0)
goal_position[1, 0] -= 0.2
goal_pose = Pose(goal_position, np.repeat(state.quaternion[None], 2, axis=0))
result = motion_gen.plan_batch(start_state, goal_pose, link="panda_hand")
success = result.success.cpu().numpy()
print("success:", success, "position errors [mm]:", result.position_error.cpu().numpy() * 1000)
traj = result.get_paths()

reached = []
idx_list = [robot.get_dof_index(x) for x in motion_gen.joint_names]
articulation_controller = robot.get_articulation_controller()
for i, path in enumerate(traj):
    if not success[i]:
        continue
    robot.set_joint_positions(path.positions[0], joint_indices=idx_list)
    robot.set_joint_velocities(np.zeros(len(idx_list)), joint_indices=idx_list)
    for k in range(path.num_samples):
        articulation_controller.apply_action(ArticulationAction(path.positions[k], path.velocities[k],
                                                                joint_indices=idx_list))
        my_world.step(render=True)
    for _ in range(30):
        my_world.step(render=True)
    hand = motion_gen.fk(robot.get_joint_positions()[idx_list], "panda_hand").position
    reached.append(float(np.linalg.norm(hand - goal_position[i])))
simulation_app.close()
