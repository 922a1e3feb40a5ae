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


def missing(owner: str, table: dict[str, str], name: str) -> AttributeError:
    """The AttributeError for `owner.name`, naming manip's equivalent when cuRobo has `name`."""
    if name in table:
        return AttributeError(f"{owner} has no '{name}' (cuRobo's name); manip's equivalent: {owner}.{table[name]}")
    return AttributeError(f"'{owner}' object has no attribute '{name}'")
