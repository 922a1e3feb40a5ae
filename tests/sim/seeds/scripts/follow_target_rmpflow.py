"""Isaac Sim's standalone "follow target with RMPflow" example: the Franka's FollowTarget task,
RmpFlow from the Franka's config (interface_config_loader), driven frame by frame through an
ArticulationMotionPolicy; the script moves the target cube. Lula's IK (LulaKinematicsSolver +
ArticulationKinematicsSolver) checks the reached pose. Only the imports differ
(isaacsim.robot_motion.motion_generation / isaacsim.robot.manipulators.examples.franka -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import FollowTarget
from manip.sim import ArticulationMotionPolicy, RmpFlow, interface_config_loader
from manip.sim import ArticulationKinematicsSolver, LulaKinematicsSolver

my_world = World(stage_units_in_meters=1.0)
my_task = FollowTarget(name="follow_target_task")
my_world.add_task(my_task)
my_world.reset()
task_params = my_world.get_task("follow_target_task").get_params()
franka_name = task_params["robot_name"]["value"]
target_name = task_params["target_name"]["value"]
my_franka = my_world.scene.get_object(franka_name)

rmp_flow_config = interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow")
rmp_flow = RmpFlow(**rmp_flow_config)
physics_dt = 1.0 / 60
articulation_rmp = ArticulationMotionPolicy(my_franka, rmp_flow, physics_dt)
articulation_controller = my_franka.get_articulation_controller()

kinematics_config = interface_config_loader.load_supported_lula_kinematics_solver_config("Franka")
lula_solver = LulaKinematicsSolver(**kinematics_config)
ik_solver = ArticulationKinematicsSolver(my_franka, lula_solver, "right_gripper")

target = my_world.scene.get_object(target_name)
goals = [np.array([0.4, 0.3, 0.4]), np.array([0.5, -0.2, 0.3])]
errors, ik_errors = [], []
for goal in goals:
    target.set_world_pose(position=goal)
    for _ in range(180):
        my_world.step(render=True)
        if my_world.is_playing():
            observations = my_world.get_observations()
            robot_base_translation, robot_base_orientation = my_franka.get_world_pose()
            rmp_flow.set_robot_base_pose(robot_base_translation, robot_base_orientation)
            rmp_flow.set_end_effector_target(
                target_position=observations[target_name]["position"],
                target_orientation=observations[target_name]["orientation"],
            )
            rmp_flow.update_world()
            actions = articulation_rmp.get_next_articulation_action(physics_dt)
            articulation_controller.apply_action(actions)
    lula_solver.set_robot_base_pose(*my_franka.get_world_pose())
    ee_position, ee_rotation = ik_solver.compute_end_effector_pose()
    errors.append(float(np.linalg.norm(ee_position - goal)))
    action, success = ik_solver.compute_inverse_kinematics(goal, observations[target_name]["orientation"])
    ik_errors.append(success)
    print(f"goal {goal}: right_gripper at {np.round(ee_position, 3)} ({errors[-1]:.4f} m); IK success {success}")
simulation_app.close()
