"""cuRobo's batched IK example (examples/ik_example.py: sample reachable configurations, take
their end-effector poses as goals, `solve_batch`, read `success` / `solution` as tensors) on
manip, then each solution played on a simulated Franka and its hand read back through the
link's prim. cuRobo's calls are manip's (`IKSolver(IKSolverConfig...)` is the MotionGenerator's
`batch_ik(..., collision_free=True)`, `sample_configs` a uniform draw filtered by
`checker.in_collision_batch`, `ik_solver.fk(q)` is `kinematics.fk(q)`); the reading of the
result is cuRobo's: (N, 1) `success`, (N, 1, dof) `solution`, `solution[success]`."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import time

import numpy as np
from manip import MotionGenerator, Pose
from manip.sim import ArticulationAction, Franka, World, get_prim_at_path

my_world = World(stage_units_in_meters=1.0)
my_world.scene.add_default_ground_plane()
robot = my_world.scene.add(Franka("/World/Franka", name="franka"))
my_world.reset()

motion_gen = MotionGenerator("franka")
motion_gen.update_world_from_sim(my_world, robot)
kin = motion_gen.kinematics

# cuRobo: q_sample = ik_solver.sample_configs(n)  (feasible configurations)
rng = np.random.default_rng(7)
q_sample = rng.uniform(kin.limits.lower, kin.limits.upper, size=(400, kin.dof))
q_sample = q_sample[~motion_gen.checker.in_collision_batch(q_sample)][:40]
kin_state = kin.fk(q_sample)
goal = Pose(kin_state.position, kin_state.quaternion)

st = time.time()
result = motion_gen.batch_ik(goal, collision_free=True)   # cuRobo: ik_solver.solve_batch(goal)
print(
    "Success, Solve Time(s), hz ",
    np.count_nonzero(result.success) / len(q_sample),
    result.solve_time,
    q_sample.shape[0] / (time.time() - st),
    np.mean(result.position_error),
    np.mean(result.rotation_error),
)
success = result.success.cpu().numpy()
solutions = result.solution[result.success]          # (K, dof): cuRobo's line
goal_index = np.flatnonzero(success[:, 0])

# play the first few on the simulated Franka: drive to each, then read the hand's prim
hand = get_prim_at_path("/World/Franka/panda_hand")
idx_list = [robot.get_dof_index(x) for x in motion_gen.joint_names]
controller = robot.get_articulation_controller()
hand_errors = []
for q, i in zip(solutions[:4], goal_index[:4]):
    robot.set_joint_positions(q, joint_indices=idx_list)
    robot.set_joint_velocities(np.zeros(len(idx_list)), joint_indices=idx_list)
    for _ in range(60):
        controller.apply_action(ArticulationAction(joint_positions=q, joint_indices=idx_list))
        my_world.step(render=False)
    position, _ = hand.get_world_pose()
    hand_errors.append(float(np.linalg.norm(position - goal.position[i])))
print("simulated hand errors [mm]:", np.round(np.array(hand_errors) * 1000, 2))
simulation_app.close()
