"""cuRobo's MotionGen names and where manip has them (data, and the messages naming them).

A script written against cuRobo (`motion_gen.plan_single(...)`, `result.get_interpolated_plan()`)
asking a `MotionGenerator` or a `PlanResult` for one gets an AttributeError that names manip's
equivalent instead of a bare "no attribute".
"""

from __future__ import annotations

#: cuRobo `MotionGen` member -> manip's `MotionGenerator` equivalent.
MOTION_GEN = {
    "plan_single": "plan_pose(start_q, goal_pose) (a Pose, quaternion w, x, y, z; returns a PlanResult)",
    "plan_single_js": "plan_joints(start_q, goal_q)",
    "warmup": "nothing: the compiled kernels are prebuilt (the first plan takes about 1 s of CPU)",
    "attach_objects_to_robot": "attach_object(name, q, link=...) (one obstacle of the world, by name)",
    "attach_external_objects_to_robot": "attach_object(shape, q, link=...) (a Cuboid, Sphere, ... not in the world)",
    "attach_spheres_to_robot": "attach_object(Sphere(...), q, link=...)",
    "detach_object_from_robot": "detach_object(q)",
    "detach_spheres_from_robot": "detach_object(q)",
    "compute_kinematics": "fk(q, link)",
    "solve_ik": "ik(goal_pose, link, seed_q)",
    "get_active_js": "joint_names (a full robot state, the gripper's joints last, is accepted as it is)",
    "world_coll_checker": "checker (check_collision(q), distance(q))",
    "world_collision": "checker (check_collision(q), distance(q))",
    "clear_world_cache": "update_world(None) (no obstacles)",
    "dof": "robot_dof",
    "get_retract_config": "default_joint_positions ((dof,) [rad])",
    "world_model": "world (a WorldConfig; checker for the collision queries)",
    "plan_batch_env": "manip.batch.plan_many([Problem(world, start, goal), ...]) (each problem its own world)",
    "update_batch_world": "manip.batch.plan_many([Problem(world, start, goal), ...]) (each problem its own world)",
    "plan_batch_goalset": "plan_goalset(start_q, goals) for each problem",
}

#: cuRobo `RobotWorld` member (`curobo.wrap.model.robot_world`: collision and kinematics queries)
#: -> the `MotionGenerator` equivalent (a RobotWorld script builds a MotionGenerator in its place).
ROBOT_WORLD = {
    "get_kinematics": "fk(q, link) (one link's Pose; (N, dof) -> a batched Pose); checker.spheres(q) for the "
                      "collision spheres",
    "get_collision_distance": "checker.world_clearance_batch(Q) ((N,) signed clearance [m] to the world from joint "
                              "configurations, <= 0 in contact; cuRobo's takes spheres and reports penetration > 0)",
    "get_collision_constraint": "checker.world_clearance_batch(Q) ((N,) signed clearance [m], <= 0 in contact)",
    "collision_constraint": "checker.world_clearance_batch(Q) ((N,) signed clearance [m], <= 0 in contact)",
    "collision_cost": "checker.world_clearance_batch(Q) ((N,) signed clearance [m], <= 0 in contact)",
    "get_collision_vector": "checker.distance_report(q) (signed distances [m] and the closest pair)",
    "get_self_collision_distance": "checker.distance_report(q).self_distance (signed [m], < 0: penetration; "
                                   "check_collision(q) for the exact yes/no)",
    "get_self_collision": "check_collision(q) (world and self; checker.distance_report(q) says which)",
    "self_collision_cost": "checker.distance_report(q).self_distance (signed [m])",
    "get_world_self_collision_distance_from_joints": "checker.world_clearance_batch(Q) (world, (N,) [m]) and "
                                                     "checker.distance_report(q) per configuration (.world_distance, "
                                                     ".self_distance [m])",
    "get_world_self_collision_distance_from_joint_trajectory": "checker.certify_path(path) (the continuous motion "
                                                               "through the (T, dof) waypoints, certified or not)",
    "validate": "checker.in_collision_batch(Q) ((N,) bool, True = in collision with the world or itself: "
                "cuRobo's validity is its negation)",
    "validate_trajectory": "checker.certify_path(path) (continuous, certified)",
    "sample": "kinematics.limits (sample uniformly between lower and upper, keep the rows where "
              "checker.in_collision_batch(Q) is False)",
    "sample_trajectory": "plan_joints(start_q, goal_q).trajectory",
    "get_point_robot_distance": "distance(q) after add_obstacle(Sphere(name, radius, position=p)) for the points "
                                "(or a WorldConfig from the point cloud)",
    "pose_distance": "manip.Pose.distance (pose.distance(other): position error [m], rotation angle [rad])",
    "get_bound": "kinematics.limits (lower, upper)",
    "contact_distance": "the robot configuration's collision padding [m] (robot.yaml `collision: padding`); "
                        "distance(q) is without it",
    "rejection_ratio": "nothing: sampling valid configurations is the caller's (see sample)",
}

#: cuRobo `MotionGenPlanConfig` field -> manip's planning option (`manip.PlanOptions`), for the
#: error naming an unknown option: a cuRobo script passes them as keyword arguments.
PLAN_CONFIG = {
    "timeout": "time_budget [s]",
    "max_attempts": "no such option: every stage is bounded by counts (search_iterations) within time_budget; "
                    "after a failure, retry with another seed",
    "enable_graph": "no such option: the path search runs whenever the straight line collides",
    "enable_graph_attempt": "no such option: the path search runs whenever the straight line collides",
    "disable_graph_attempt": "no such option: the path search runs whenever the straight line collides",
    "need_graph_success": "no such option: the path search runs whenever the straight line collides",
    "enable_opt": "trajopt (True/False)",
    "enable_finetune_trajopt": "trajopt (the optimiser minimises the duration itself; no finetune stage)",
    "parallel_finetune": "trajopt (the optimiser minimises the duration itself; no finetune stage)",
    "finetune_attempts": "trajopt (the optimiser minimises the duration itself; no finetune stage)",
    "time_dilation_factor": "velocity_scale=f and acceleration_scale=f**2 (the limits of a motion retimed "
                            "f times as fast), or duration [s]",
    "num_ik_seeds": "ik_solutions (collision-free IK solutions sought per goal pose)",
    "num_trajopt_seeds": "no such option: one optimisation of the searched path (seed for another)",
    "num_graph_seeds": "search_iterations (one search; seed for another)",
    "check_start_validity": "no such option: the start is always checked (INVALID_START_* statuses)",
    "pose_cost_metric": "constraints=(OrientationConstraint(...), PositionConstraint(...)) or plan_pose(..., linear=True)",
}

#: cuRobo `MotionGenResult` member -> manip's `PlanResult` equivalent.
RESULT = {
    "get_interpolated_plan": "trajectory (times, positions, velocities, accelerations, jerks; .resample(dt))",
    "interpolated_plan": "trajectory",
    "optimized_plan": "trajectory (path: the waypoints before timing)",
    "optimized_dt": "trajectory.dt",
    "interpolation_dt": "trajectory.dt",
    "solve_time": "plan_time (and timings per stage)",
    "total_time": "plan_time",
    "valid_query": "status (INVALID_* members say what was wrong with the query)",
    "path_buffer_last_tstep": "trajectory.num_samples",
    "ik_time": 'timings["ik"] [s]',
    "trajopt_time": 'timings["trajopt"] [s]',
    "graph_time": 'timings["plan"] [s] (the path search)',
    "used_graph": 'source ("straight_line" when no search was needed)',
}


#: cuRobo `JointState` member (what `get_interpolated_plan()` returns) -> manip's `Trajectory` equivalent.
TRAJECTORY = {
    "position": "positions ((T, dof) [rad]; the last state: positions[-1])",
    "velocity": "velocities ((T, dof) [rad/s])",
    "acceleration": "accelerations ((T, dof) [rad/s^2])",
    "jerk": "jerks ((T, dof) [rad/s^3])",
    "get_ordered_joint_state": "positions[:, [t.joint_names.index(n) for n in names]] (joint_names: the column "
                               "order; joint_indices_for(robot) for a manip.sim robot)",
    "get_augmented_joint_state": "joint_names (the arm joints only; a gripper's are not in the trajectory)",
    "trim_trajectory": "at_time(times) (or resample(dt))",
    "clone": "the Trajectory itself (read-only arrays)",
    "shape": "positions.shape ((T, dof))",
}

#: cuRobo `WorldConfig` member -> manip's `WorldConfig` equivalent.
WORLD_CONFIG = {
    "add_obstacle": "add(obstacle)",
    "remove_obstacle": "remove(name)",
    "get_obstacle": "get(name)",
    "objects": "obstacles (a list of every shape)",
    "cuboid": 'obstacles (filter by kind: [o for o in world if o.kind == "cuboid"])',
    "sphere": 'obstacles (filter by kind: [o for o in world if o.kind == "sphere"])',
    "cylinder": 'obstacles (filter by kind: [o for o in world if o.kind == "cylinder"])',
    "capsule": 'obstacles (filter by kind: [o for o in world if o.kind == "capsule"])',
    "mesh": 'obstacles (filter by kind: [o for o in world if o.kind == "mesh"])',
    "clone": "copy()",
    "create_obb_world": "the world itself (primitives are checked exactly; no bounding boxes needed)",
    "create_collision_support_world": "the world itself (meshes and every primitive are checked as they are)",
}

#: cuRobo `Pose` member -> manip's `Pose` equivalent (`Pose.from_list` is the same on both).
POSE = {
    "to_list": "to_xyz_wxyz() (cuRobo's order; to_xyz_xyzw() for ROS's)",
    "tolist": "to_xyz_wxyz() (cuRobo's order; to_xyz_xyzw() for ROS's)",
    "get_matrix": "as_matrix()",
    "multiply": "@ (a @ b: b's pose expressed in a's frame composed with a)",
    "clone": "the Pose itself (immutable)",
    "batch": "len(pose) (is_batch says whether it is a batch)",
}

#: cuRobo `IKSolver` member -> manip's `IKSolver` equivalent.
IK_SOLVER = {
    "solve_single": "solve(goal, link, seed_q)",
    "sample_configs": "kinematics.limits (sample uniformly between lower and upper)",
    "fk": "kinematics.fk(q, link)",
}

#: cuRobo `CudaRobotModel` member -> manip's `Kinematics` equivalent.
KINEMATICS = {
    "get_state": "fk(q, link) (one link's Pose; (N, dof) -> a batched Pose)",
    "forward": "fk(q, link)",
    "get_link_poses": "fk(q, link) for each link",
    "get_joint_limits": "limits (a JointLimits: lower, upper, velocity, acceleration, jerk)",
    "get_dof": "dof",
    "lock_jointstate": "nothing: configurations are the arm joints (Kinematics.pinned(q, free) holds some)",
}

#: cuRobo `IKResult` member -> manip's `IKResult` equivalent.
IK_RESULT = {
    "js_solution": "solution (cuRobo's (batch, seeds, dof) array) or q ((dof,); (N, dof) for a batch)",
    "goalset_index": "manip.IKSolver.solve_goalset(goals).goalset_index (a solve / solve_batch result has one goal per row)",
    "error": "position_error [m] and rotation_error [rad]",
}


def unknown_options(names) -> str:
    """What manip calls the cuRobo `MotionGenPlanConfig` fields among `names` ("" when none is one)."""
    known = [f"{n} -> {PLAN_CONFIG[n]}" for n in names if n in PLAN_CONFIG]
    return "; cuRobo's MotionGenPlanConfig fields in manip: " + "; ".join(known) if known else ""


def missing(owner: str, table: dict[str, str], name: str) -> AttributeError:
    """The AttributeError for `owner.name`, naming manip's equivalent when cuRobo has `name`."""
    if name in table:
        where = table[name]
        # a member of `owner` is named through it; a module path or "nothing: ..." as written
        where = where if where.startswith(("manip.", "nothing")) else f"{owner}.{where}"
        return AttributeError(f"{owner} has no '{name}' (cuRobo's name); manip's equivalent: {where}")
    return AttributeError(f"'{owner}' object has no attribute '{name}'")
