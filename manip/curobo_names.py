"""cuRobo's MotionGen names and where manip has them (data only).

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
    "goalset_index": "goal_index (which pose of plan_goalset's batch was reached)",
    "ik_time": 'timings["ik"] [s]',
    "trajopt_time": 'timings["trajopt"] [s]',
    "graph_time": 'timings["plan"] [s] (the path search)',
    "used_graph": 'source ("straight_line" when no search was needed)',
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
    "solve_goalset": "solve_batch(goals, link, seed_q) (each goal solved; MotionGenerator.plan_goalset picks the best)",
    "solve_batch_goalset": "solve_batch(goals, link, seed_q)",
    "sample_configs": "kinematics.limits (sample uniformly between lower and upper)",
}

#: cuRobo `IKResult` member -> manip's `IKResult` equivalent.
IK_RESULT = {
    "solution": "q ((dof,) joints in joint_names order)",
    "js_solution": "q ((dof,) joints in joint_names order)",
    "goalset_index": "nothing: IK takes one goal (MotionGenerator.batch_ik for several)",
    "error": "position_error [m] and rotation_error [rad]",
}


def missing(owner: str, table: dict[str, str], name: str) -> AttributeError:
    """The AttributeError for `owner.name`, naming manip's equivalent when cuRobo has `name`."""
    if name in table:
        return AttributeError(f"{owner} has no '{name}' (cuRobo's name); manip's equivalent: {owner}.{table[name]}")
    return AttributeError(f"'{owner}' object has no attribute '{name}'")
