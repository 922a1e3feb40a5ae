"""cuRobo's `motion_gen_reacher` loop (examples/isaac_sim/motion_gen_reacher.py) on manip: a
Franka in the simulated World reaches a target cube; whenever the cube has moved and the robot
is at rest, plan from the robot's joint state to the cube's pose, and if
`result.success.item()`, play the interpolated plan one step per physics step with its joint
names mapped to the robot's DoF indices. cuRobo's MotionGen calls are manip's MotionGenerator
ones (plan_single -> plan_pose, get_interpolated_plan() -> trajectory); the loop is cuRobo's."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip import MotionGenerator, Pose
from manip.sim import World, Franka, VisualCuboid, ArticulationAction

my_world = World(stage_units_in_meters=1.0)
my_world.scene.add_default_ground_plane()
robot = my_world.scene.add(Franka("/World/Franka", name="franka"))
target = my_world.scene.add(VisualCuboid("/World/target", name="target", position=np.array([0.5, 0.0, 0.5]),
                                         orientation=np.array([0, 1, 0, 0]), color=np.array([1.0, 0, 0]), size=0.05))
my_world.reset()

motion_gen = MotionGenerator("franka", interpolation_dt=1 / 60)
motion_gen.update_world_from_sim(my_world, robot, ignore=["/World/target"])
articulation_controller = robot.get_articulation_controller()

goals = [np.array([0.5, 0.0, 0.5]), np.array([0.4, 0.3, 0.3]), np.array([0.35, -0.35, 0.45])]
past_pose = None
cmd_plan, cmd_idx, idx_list = None, 0, None
reached, plans = [], 0
for step in range(900):
    if step % 300 == 0:
        target.set_world_pose(position=goals[step // 300])
    my_world.step(render=True)
    cube_position, cube_orientation = target.get_world_pose()
    sim_js = robot.get_joints_state()
    robot_static = np.max(np.abs(sim_js.velocities)) < 0.2
    if past_pose is None:
        past_pose = cube_position
    if (np.linalg.norm(cube_position - past_pose) > 1e-3 or plans == 0) and robot_static and cmd_plan is None:
        ik_goal = Pose(cube_position - robot.get_world_pose()[0], cube_orientation)   # in the robot's base frame
        result = motion_gen.plan_pose(sim_js.positions, ik_goal, link="panda_hand_tcp")
        plans += 1
        succ = result.success.item()   # cuRobo's success is a tensor
        if succ:
            cmd_plan = result.trajectory     # cuRobo: result.get_interpolated_plan()
            idx_list = [robot.get_dof_index(x) for x in cmd_plan.joint_names]
            cmd_idx = 0
        else:
            print("Plan did not converge to a solution:", result.status, result.message)
    past_pose = cube_position
    if cmd_plan is not None:
        articulation_controller.apply_action(ArticulationAction(
            cmd_plan.positions[cmd_idx], cmd_plan.velocities[cmd_idx], joint_indices=idx_list))
        cmd_idx += 1
        if cmd_idx >= cmd_plan.num_samples:
            cmd_idx, cmd_plan = 0, None
            tcp = motion_gen.fk(robot.get_joint_positions(), "panda_hand_tcp").position + robot.get_world_pose()[0]
            reached.append(float(np.linalg.norm(tcp - target.get_world_pose()[0])))
            print(f"reached the target within {reached[-1] * 1000:.1f} mm")
simulation_app.close()
