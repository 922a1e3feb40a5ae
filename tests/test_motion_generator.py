"""MotionGenerator: inputs, statuses, pose/linear/goal-set planning, attach, determinism.

Every successful trajectory is checked by the independent verifier of
`manip.benchmarking.verify` (exact meshes, dense, limits), not by the planner's own checks.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from manip import InvalidInputError, Pose, UnknownNameError
from manip.benchmarking.verify import default_verifier
from manip.collision import Cuboid, WorldConfig
from manip.motion_generator import MotionGenerator
from manip.planning import PlanOptions, PlanStatus
from robot_constants import FRANKA_READY

READY = np.array(FRANKA_READY)
DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # hand z axis pointing down (rotation pi about x)

#: A table top in front of the robot and a wall between two reach targets.
TABLE_WALL = {
    "cuboid": {
        "table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]},
        "wall": {"dims": [0.3, 0.04, 0.45], "pose": [0.5, 0.0, 0.225, 1, 0, 0, 0]},
    }
}


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", WorldConfig.from_dict(TABLE_WALL))


def _verify(mg: MotionGenerator, result, goal_q=None, goal_pose=None, link="panda_hand"):
    traj = result.trajectory
    v = default_verifier().verify_trajectory(
        mg.world.to_dict(),
        traj.times,
        traj.positions,
        traj.velocities,
        traj.accelerations,
        traj.jerks,
        start_q=traj.positions[0],
        goal_q=goal_q,
        goal_pose=goal_pose,
        check_jerk=True,
    )
    assert v.valid, v.reasons


def _left_right(mg: MotionGenerator) -> tuple[np.ndarray, np.ndarray]:
    """Two configurations with the hand on either side of the wall."""
    left = mg.ik(Pose([0.45, 0.3, 0.25], DOWN), seed_q=READY, collision_free=True)
    right = mg.ik(Pose([0.45, -0.3, 0.25], DOWN), seed_q=READY, collision_free=True)
    assert left.success and right.success
    return left.q, right.q


def test_robot_facts(mg):
    assert mg.joint_names == [f"panda_joint{i}" for i in range(1, 8)]
    assert mg.robot_dof == 7
    np.testing.assert_allclose(mg.default_joint_positions, READY)
    assert mg.ee_link == "panda_hand"
    assert np.all(mg.lower_limits < mg.upper_limits)
    assert mg.velocity_limits.shape == (7,)


def test_plan_joints_around_wall_is_valid(mg):
    left, right = _left_right(mg)
    r = mg.plan_joints(left, right, seed=1)
    assert r.success, r.message
    assert r.status is PlanStatus.SUCCESS
    traj = r.trajectory
    np.testing.assert_allclose(traj.positions[0], left, atol=1e-9)
    np.testing.assert_allclose(traj.positions[-1], right, atol=1e-6)
    np.testing.assert_allclose(traj.velocities[[0, -1]], 0.0, atol=1e-9)
    assert traj.joint_names == tuple(mg.joint_names)
    assert {"plan", "timing", "validate", "total"} <= set(r.timings)
    _verify(mg, r, goal_q=right)


def test_plan_pose_reaches_goal_within_tolerance(mg):
    goal = Pose([0.45, -0.3, 0.3], DOWN)
    left, _ = _left_right(mg)
    r = mg.plan_pose(left, goal, seed=0)
    assert r.success, r.message
    assert r.position_error <= 1e-3 and r.rotation_error <= 0.01
    reached = mg.fk(r.trajectory.positions[-1])
    dp, dr = reached.distance(goal)
    assert dp <= 1e-3 and dr <= 0.01
    _verify(mg, r, goal_pose=goal)


def test_linear_motion_keeps_a_straight_line_and_orientation(mg):
    _, right = _left_right(mg)
    start_pose = mg.fk(right, "panda_hand_tcp")
    goal = Pose(start_pose.position - [0.0, 0.0, 0.12], start_pose.quaternion)
    r = mg.plan_pose(right, goal, link="panda_hand_tcp", linear=True)
    assert r.success, r.message
    poses = mg.fk(r.trajectory.positions, "panda_hand_tcp")
    # distance of every sample from the line, and the orientation drift
    d = poses.position - start_pose.position
    off_line = np.linalg.norm(d[:, :2], axis=1)
    assert off_line.max() < 2e-3
    _, rot = poses.distance(Pose(np.tile(start_pose.position, (len(poses), 1)), np.tile(start_pose.quaternion, (len(poses), 1))))
    assert rot.max() < 0.01
    assert r.position_error <= 1e-3


def test_goalset_index_is_curobos_tensor_of_the_pose_reached(mg):
    """cuRobo scripts read `result.goalset_index.item()` after plan_goalset."""
    left, _ = _left_right(mg)
    unreachable, reachable = Pose([2.0, 0.0, 0.3], DOWN), Pose([0.45, 0.3, 0.3], DOWN)
    r = mg.plan_goalset(left, Pose.stack([unreachable, reachable]), seed=0)
    assert r.success and r.goal_index == 1
    assert r.goalset_index.shape == (1,) and r.goalset_index.item() == 1 and r.goalset_index.dtype == np.int64


def test_goalset_picks_a_reachable_pose(mg):
    left, _ = _left_right(mg)
    unreachable = Pose([2.0, 0.0, 0.3], DOWN)
    reachable = Pose([0.45, -0.3, 0.3], DOWN)
    r = mg.plan_goalset(left, Pose.stack([unreachable, reachable]), seed=0)
    assert r.success, r.message
    assert r.goal_index == 1


def test_unreachable_pose_is_ik_fail(mg):
    r = mg.plan_pose(READY, Pose([2.0, 0.0, 0.3], DOWN))
    assert not r.success and r.status is PlanStatus.IK_FAIL
    assert r.trajectory is None


def test_start_statuses(mg):
    # a hair outside a limit (1e-6 rad, and what a simulated joint settles to: 5e-5) is accepted
    start = READY.copy()
    for excess in (1e-6, 5e-5):
        start[3] = mg.upper_limits[3] + excess
        r = mg.plan_joints(start, READY)
        assert r.success, r.message
        np.testing.assert_array_equal(r.trajectory.positions[0], start)
    start[3] = mg.upper_limits[3] + 1e-3
    assert mg.plan_joints(start, READY).status is PlanStatus.INVALID_START_JOINT_LIMITS
    # hand inside the wall
    inside = mg.ik(Pose([0.5, 0.0, 0.25], DOWN), seed_q=READY)
    assert inside.success
    assert mg.plan_joints(inside.q, READY).status is PlanStatus.INVALID_START_WORLD_COLLISION
    # the arm folded into itself (link 7 / hand against link 1-2)
    folded = np.array([0.0, 1.5, 0.0, -3.0, 0.0, 3.7, 0.0])
    free = MotionGenerator("franka")
    assert free.check_collision(folded)
    assert free.plan_joints(folded, READY).status is PlanStatus.INVALID_START_SELF_COLLISION


def test_invalid_goal_status(mg):
    inside = mg.ik(Pose([0.5, 0.0, 0.25], DOWN), seed_q=READY)
    left, _ = _left_right(mg)
    assert mg.plan_joints(left, inside.q).status is PlanStatus.INVALID_GOAL
    beyond = READY.copy()
    beyond[0] = 3.5
    assert mg.plan_joints(left, beyond).status is PlanStatus.INVALID_GOAL


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda m: m.plan_joints(np.zeros(6), READY), r"start_q must have shape"),
        (lambda m: m.plan_joints(READY, np.full(7, np.nan)), r"non-finite"),
        (lambda m: m.plan_joints(READY, READY, speed=2), r"unknown planning option"),
        (lambda m: m.plan_joints(READY, READY, velocity_scale=1.5), r"velocity_scale"),
        (lambda m: m.plan_pose(READY, [0.4, 0, 0.4, 1, 0, 0, 0]), r"manip.Pose"),
        (lambda m: m.fk(READY, link="gripper"), r"frame 'gripper' not found; available: .*panda_hand"),
        # cuRobo's JointState.position of one state is (1, dof): the message says what to pass
        (lambda m: m.plan_joints(READY[None], READY), r"got \(1, 7\) \(one configuration, .*: pass start_q\[0\]\)"),
        (lambda m: m.plan_joints(READY, READY[None]), r"got \(1, 7\) \(one configuration, .*: pass goal_q\[0\]\)"),
    ],
)
def test_bad_input_raises(mg, call, match):
    with pytest.raises((InvalidInputError, UnknownNameError), match=match):
        call(mg)


def test_same_seed_same_plan(mg):
    left, right = _left_right(mg)
    a = mg.plan_joints(left, right, seed=7)
    b = mg.plan_joints(left, right, seed=7)
    assert a.success and b.success
    np.testing.assert_array_equal(a.trajectory.positions, b.trajectory.positions)


def test_call_seed_alone_decides_pose_plan(mg):
    # the IK restarts of a pose goal follow the call's seed, not the generator's: a plan with
    # seed=3 is the same from MotionGenerator(seed=3) and from MotionGenerator(seed=0) (the IK
    # stage used the generator's seed, so retrying with other seeds retried the same IK)
    left, _ = _left_right(mg)
    goal = Pose([0.5, -0.25, 0.2], DOWN)
    seeded = MotionGenerator("franka", WorldConfig.from_dict(TABLE_WALL), seed=3)
    a = mg.plan_pose(left, goal, seed=3)
    b = seeded.plan_pose(left, goal)
    assert a.success and b.success
    np.testing.assert_array_equal(a.goal_q, b.goal_q)
    np.testing.assert_array_equal(a.trajectory.positions, b.trajectory.positions)
    _verify(mg, a, goal_pose=goal)


def test_attach_and_detach_object():
    mg = MotionGenerator("franka", {"cuboid": {"shelf": {"dims": [0.4, 0.4, 0.02], "pose": [0.5, 0.0, 0.30, 1, 0, 0, 0]}}})
    # the hand 10 cm above the shelf top is free; a 20 cm box hanging below it is not
    q = mg.ik(Pose([0.5, 0.0, 0.31 + 0.1 + 0.1034], DOWN), seed_q=READY).q
    assert not mg.check_collision(q)
    box_pose = mg.fk(q, "panda_hand_tcp") @ Pose([0.0, 0.0, 0.05])
    mg.attach_object(Cuboid("box", [0.05, 0.05, 0.2], box_pose), q=q)
    assert mg.check_collision(q)
    mg.detach_object(q)
    assert "box" in mg.world.names
    placed = mg.world.get("box").pose
    assert placed.isclose(box_pose, 1e-9, 1e-9)
    assert mg.check_collision(q)  # the box is back in the world, intersecting the hand region
    mg.remove_obstacle("box")
    assert not mg.check_collision(q)


def test_velocity_scale_slows_the_motion(mg):
    left, right = _left_right(mg)
    fast = mg.plan_joints(left, right, seed=3)
    slow = mg.plan_joints(left, right, seed=3, velocity_scale=0.5, acceleration_scale=0.5)
    assert fast.success and slow.success
    assert slow.trajectory.duration > fast.trajectory.duration * 1.3
    assert np.all(np.abs(slow.trajectory.velocities) <= 0.5 * mg.velocity_limits + 1e-9)




def test_velocity_and_acceleration_scales_given_to_the_constructor():
    # cuRobo's MotionGenConfig.load_from_robot_config(..., velocity_scale=, acceleration_scale=):
    # a TypeError here before; the generator's defaults, which a call's options override
    slow = MotionGenerator("franka", WorldConfig.from_dict(TABLE_WALL), velocity_scale=0.5, acceleration_scale=0.25)
    left, right = _left_right(slow)
    r = slow.plan_joints(left, right, seed=1)
    assert r.success, r.message
    assert np.all(r.trajectory.max_abs_velocity() <= 0.5 * slow.velocity_limits * (1 + 1e-6))
    assert np.all(r.trajectory.max_abs_acceleration() <= 0.25 * slow.acceleration_limits * (1 + 1e-6))
    _verify(slow, r, goal_q=right)
    fast = slow.plan_joints(left, right, seed=1, velocity_scale=1.0, acceleration_scale=1.0)
    assert fast.success and fast.motion_time < r.motion_time
    with pytest.raises(InvalidInputError, match=r"velocity_scale must be a number in \(0, 1\]; got 2"):
        MotionGenerator("franka", velocity_scale=2)

def test_attach_and_detach_need_the_configuration():
    """A grasp without its configuration attached the cube at its pose relative to the hand at
    the *default* configuration (here 0.6 m away from the hand that grasped it), and a detach
    without one put the carried cube back where the hand would be at the default configuration,
    on the way home: both were accepted silently. They need q (or pose_in_link), as cuRobo's
    attach needs the joint state."""
    mg = MotionGenerator("franka", {"cuboid": {"cube": {"dims": [0.05] * 3, "pose": [0.5, -0.3, 0.025, 1, 0, 0, 0]}}})
    grasp = mg.ik(Pose([0.5, -0.3, 0.03], DOWN), "panda_hand_tcp", READY).q
    with pytest.raises(InvalidInputError, match="attach_object needs q"):
        mg.attach_object("cube", link="panda_hand_tcp")
    assert mg.world.names == ["cube"] and not mg.checker.attached_objects
    mg.attach_object("cube", grasp, link="panda_hand_tcp")
    carried = mg.plan_pose(grasp, Pose([0.4, 0.3, 0.3], DOWN), "panda_hand_tcp")
    assert carried.success, carried.message
    with pytest.raises(InvalidInputError, match="detach_object needs q, the configuration at release"):
        mg.detach_object()
    assert "cube" in mg.checker.attached_objects
    mg.detach_object(carried.goal_q)
    assert mg.world.get("cube").pose.isclose(Pose([0.4, 0.3, 0.3 - 0.005]), 1e-3, 1e-2)
    home = mg.plan_joints(carried.goal_q, READY)   # the cube stays where it was released, off the way home
    assert home.success, home.message
    # an external shape placed in the link frame needs no configuration
    mg.attach_object(Cuboid("tool", [0.02, 0.02, 0.1]), pose_in_link=[0.0, 0.0, 0.05], link="panda_hand_tcp")
    assert "tool" in mg.checker.attached_objects


def test_a_held_object_still_on_its_support_says_how_to_lift_it():
    # cuRobo's flow, attach then plan the lift, from a cube resting on the table: the start
    # collides (the cube touches the table); the message says what to do
    mg = MotionGenerator("franka", {"cuboid": {"cube": {"dims": [0.05] * 3, "pose": [0.5, -0.3, 0.025, 1, 0, 0, 0]},
                                               "table": {"dims": [1.0, 1.2, 0.04], "pose": [0.5, 0, -0.02, 1, 0, 0, 0]}}})
    grasp = mg.ik(Pose([0.5, -0.3, 0.03], DOWN), "panda_hand_tcp", READY).q
    assert not mg.check_collision(grasp)
    mg.attach_object("cube", grasp, link="panda_hand_tcp")
    r = mg.plan_pose(grasp, Pose([0.5, -0.3, 0.2], DOWN), "panda_hand_tcp", linear=True)
    assert r.status is PlanStatus.INVALID_START_WORLD_COLLISION
    assert r.message.startswith("start in collision: cube touches table")
    assert r.message.endswith("(still on its support?): plan the lift with plan_grasp, whose lift may leave the "
                              "support, or attach it where it is clear")
    mg.detach_object(grasp)
    inside = mg.ik(Pose([0.5, -0.3, -0.01], DOWN), "panda_hand_tcp", READY).q   # the fingers themselves in the table
    blocked = mg.plan_joints(inside, READY)
    assert blocked.status is PlanStatus.INVALID_START_WORLD_COLLISION and "plan_grasp" not in blocked.message

def test_curobo_names_point_to_manips():
    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    # a cuRobo script's first calls: each was a bare "object has no attribute"
    with pytest.raises(AttributeError, match=r"no 'plan_single' \(cuRobo's name\); manip's equivalent: "
                                             r"MotionGenerator.plan_pose\(start_q, goal_pose\)"):
        mg.plan_single
    with pytest.raises(AttributeError, match="MotionGenerator.attach_object"):
        mg.attach_objects_to_robot
    result = mg.plan_joints(q0, q0 + 0.1)
    with pytest.raises(AttributeError, match=r"PlanResult.trajectory \(times, positions"):
        result.get_interpolated_plan()
    with pytest.raises(AttributeError, match="'PlanResult' object has no attribute 'no_such_field'"):
        result.no_such_field
    # a goal-set plan's index, and the stage timings, under cuRobo's MotionGenResult names
    assert result.goalset_index is None   # a joint goal (cuRobo's default); goal sets: test_goalset_index
    for name, where in (("ik_time", 'timings["ik"]'), ("trajopt_time", 'timings["trajopt"]'),
                        ("graph_time", 'timings["plan"]'), ("used_graph", "source")):
        with pytest.raises(AttributeError, match=re.escape(f"PlanResult.{where}")):
            getattr(result, name)
    assert not hasattr(mg, "warmup") and hasattr(result, "trajectory")
    # results still pickle and copy (plan_many sends them between processes)
    import copy
    import pickle
    again = pickle.loads(pickle.dumps(result))
    assert np.array_equal(again.trajectory.positions, result.trajectory.positions)
    assert copy.deepcopy(result).status is result.status


def test_a_pose_goal_at_a_tiny_velocity_scale_is_planned_not_raised(mg):
    """A motion of over an hour (velocity_scale 1e-4): ruckig refuses the lower bound that ranks
    the goal's IK solutions (a RuckigError, or a ValueError for its code -101); the bound falls
    back to the joints' own S-curves, and the plan goes on as plan_joints' does."""
    goal = Pose([0.45, -0.3, 0.3], DOWN)
    left, _ = _left_right(mg)
    r = mg.plan_pose(left, goal, seed=0, velocity_scale=1e-4, dt=1.0)
    assert r.success, r.message
    assert r.trajectory.duration > 3600.0
    assert np.all(np.abs(r.trajectory.velocities) <= 1e-4 * mg.velocity_limits * (1 + 1e-6))
    _verify(mg, r, goal_pose=goal)


def test_curobo_names_of_the_world_pose_and_ik_point_to_manips(mg):
    """manip's WorldConfig, Pose, IKSolver and IKResult carry cuRobo's class names; a cuRobo
    script's calls on them (`world.add_obstacle`, `Pose.from_list`, `ik_solver.solve_single`,
    `result.solution`) name manip's equivalent instead of a bare "no attribute"."""
    world = WorldConfig.from_dict(TABLE_WALL)
    cases = [
        (world, "add_obstacle", "WorldConfig.add(obstacle)"), (world, "remove_obstacle", "WorldConfig.remove(name)"),
        (world, "get_obstacle", "WorldConfig.get(name)"), (world, "objects", "WorldConfig.obstacles"),
        (world, "cuboid", "WorldConfig.obstacles"), (world, "clone", "WorldConfig.copy()"),
        (Pose([0, 0, 0]), "to_list", "Pose.to_xyz_wxyz()"),
        (Pose([0, 0, 0]), "get_matrix", "Pose.as_matrix()"), (Pose([0, 0, 0]), "multiply", "@"),
        (mg.ik_solver, "solve_single", "IKSolver.solve(goal"),
    ]
    result = mg.ik(Pose([0.45, -0.3, 0.3], DOWN), seed_q=READY)
    cases += [(result, "js_solution", "IKResult.solution"), (result, "goalset_index", "IKSolver.solve_goalset")]
    assert result.solution.shape == (1, 1, 7) and np.array_equal(result.solution[result.success], [result.q])
    for owner, name, where in cases:
        with pytest.raises(AttributeError, match=rf"no '{name}' \(cuRobo's name\); manip's equivalent: .*{re.escape(where)}"):
            getattr(owner, name)
    # cuRobo's goal constructor works as it does there: [x, y, z, qw, qx, qy, qz]
    assert Pose.from_list([0.45, -0.3, 0.3, 0, 1, 0, 0]).isclose(Pose([0.45, -0.3, 0.3], DOWN))
    # other missing names, private ones included, stay plain (copy and pickle probe those)
    for owner in (world, Pose([0, 0, 0]), mg.ik_solver, result):
        with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
            owner.no_such_name
        assert not hasattr(owner, "_no_such_private")
    import copy
    import pickle
    assert pickle.loads(pickle.dumps(world)).names == world.names
    assert copy.deepcopy(Pose([1, 2, 3])).isclose(Pose([1, 2, 3]))
    assert np.array_equal(pickle.loads(pickle.dumps(result)).q, result.q)



def test_curobo_plan_config_kinematics_and_generator_names_point_to_manips(mg):
    """cuRobo's MotionGenPlanConfig fields passed as options (`timeout`, `max_attempts`,
    `time_dilation_factor`, ...), `motion_gen.dof` and `kin_model.get_state(q)` name manip's
    equivalent (they were a bare unknown option / "no attribute")."""
    q0 = mg.default_joint_positions
    goal = Pose([0.45, -0.3, 0.3], DOWN)
    with pytest.raises(InvalidInputError, match=r"unknown planning option\(s\) \['max_attempts', 'timeout'\]; valid: .*"
                                                r"cuRobo's MotionGenPlanConfig fields in manip: max_attempts -> .*"
                                                r"timeout -> time_budget \[s\]"):
        mg.plan_pose(q0, goal, timeout=2.0, max_attempts=4)
    with pytest.raises(InvalidInputError, match=r"time_dilation_factor -> velocity_scale=f and acceleration_scale=f\*\*2"):
        mg.plan_joints(q0, q0 + 0.1, time_dilation_factor=0.5)
    with pytest.raises(InvalidInputError, match=r"enable_opt -> trajopt"):
        mg.plan_batch(q0, [goal], enable_opt=False)
    with pytest.raises(InvalidInputError) as plain:   # a name cuRobo lacks keeps the plain message
        mg.plan_joints(q0, q0 + 0.1, no_such_option=1)
    assert "cuRobo" not in str(plain.value)
    kin = mg.kinematics
    trajectory = mg.plan_joints(q0, q0 + 0.1).trajectory   # what cuRobo's get_interpolated_plan() gives
    for owner, name, where in ((mg, "dof", "MotionGenerator.robot_dof"),
                               (mg, "get_retract_config", "MotionGenerator.default_joint_positions"),
                               (mg, "plan_batch_env", "manip.batch.plan_many"),
                               (kin, "get_state", "Kinematics.fk(q, link)"), (kin, "get_joint_limits", "Kinematics.limits"),
                               (mg.ik_solver, "fk", "IKSolver.kinematics.fk"),
                               (trajectory, "position", "Trajectory.positions ((T, dof)"),
                               (mg.batch_ik(Pose.stack([goal, goal])), "js_solution", "BatchIKResult.solution"),
                               (trajectory, "velocity", "Trajectory.velocities"),
                               (trajectory, "get_ordered_joint_state", "Trajectory.positions[:, [t.joint_names.index(n)")):
        with pytest.raises(AttributeError, match=rf"no '{name}' \(cuRobo's name\); manip's equivalent: {re.escape(where)}"):
            getattr(owner, name)
    with pytest.raises(AttributeError, match="'Kinematics' object has no attribute 'no_such_name'"):
        kin.no_such_name
    import copy
    import pickle
    assert copy.copy(kin).dof == kin.dof and not hasattr(kin, "__no_such_dunder__")
    assert pickle.loads(pickle.dumps(trajectory)).duration == trajectory.duration
    assert pickle.loads(pickle.dumps(PlanOptions(seed=3))).seed == 3

def test_a_start_a_hair_outside_a_limit_never_leaves_the_limits_again():
    """A start 5e-5 rad above panda_joint7's upper limit is accepted as given, and the timing may
    reach that far out; but once a joint is inside its limits it stays inside (1e-6 rad): the
    linear motion's spline through IK points lying on the limit went 2 urad past it mid-motion."""
    mg = MotionGenerator("franka")
    base = mg.ik(Pose([0.4, -0.2, 0.3], DOWN), seed_q=READY).q
    start = base.copy()
    start[6] = mg.upper_limits[6] + 5e-5
    here = mg.fk(start)
    goal = Pose(here.position + [0.0, 0.0, 0.05], here.quaternion)
    r = mg.plan_pose(start, goal, linear=True)
    assert r.success, r.message
    t = np.union1d(r.trajectory.times, np.linspace(0.0, r.trajectory.duration, 5001))
    q = r.trajectory.at_time(t)[0]
    out = np.maximum(mg.lower_limits - q, q - mg.upper_limits)
    assert np.array_equal(q[0], start) and out.max() <= 5e-5 + 1e-12
    inside = out <= 1e-6
    assert not np.any(np.maximum.accumulate(inside, axis=0) & ~inside)
    dp, dr = mg.fk(r.trajectory.positions[-1]).distance(goal)
    assert dp <= 1e-3 and dr <= 0.01


def test_a_linear_motion_to_a_goal_out_of_reach_says_so(mg):
    """benchmarks/unseen.py bad: a straight line to a goal 3 m away said only "IK fails on the
    line at 16% (NOT_CONVERGED)"; the line's end is out of reach, as plan_pose's IK_FAIL says."""
    r = mg.plan_pose(READY, Pose([3.0, 0.0, 0.3], DOWN), linear=True)
    assert r.status is PlanStatus.LINEAR_PATH_FAIL
    assert "out of reach" in r.message and "3.000 m" in r.message, r.message
    free = MotionGenerator("franka")   # within reach, in free space: unchanged
    r = free.plan_pose(READY, Pose([0.6, 0.0, 0.3], DOWN), linear=True)
    assert r.success, r.message


def test_a_linear_motion_through_an_obstacle_says_where_and_what_it_touches():
    """benchmarks/unseen_sim.py --perturb-all seed 5500, episode 36: a grasp's approach failed with
    "the straight line collides", naming neither where nor what."""
    mg = MotionGenerator("franka")
    hand = mg.fk(READY)
    mg.update_world({"cuboid": {"block": {"dims": [0.1, 0.1, 0.05],
                                          "pose": [*(hand.position - [0, 0, 0.25]), 1, 0, 0, 0]}}})
    r = mg.plan_pose(READY, Pose(hand.position - [0, 0, 0.4], hand.quaternion), linear=True)
    assert r.status is PlanStatus.LINEAR_PATH_FAIL
    assert re.search(r"collides at \d+% of the line: in collision: panda_\w+ touches block", r.message), r.message


def test_a_start_that_differs_from_the_goal_by_rounding_plans_a_still_motion():
    """The arm parked at the goal with 1e-18 rad of drift in one joint (pick_and_place's
    recovery to the wait pose): SUCCESS, not TRAJOPT_FAIL "endpoints differ"."""
    mg = MotionGenerator("franka")
    goal = mg.default_joint_positions
    start = goal.copy()
    start[4] += 1.4e-18
    r = mg.plan_joints(start, goal)
    assert r.success, (r.status, r.message)
    assert np.abs(r.trajectory.positions[-1] - goal).max() < 1e-12


def test_a_joint_goal_a_whole_turn_round_a_post_says_the_shorter_goal():
    """A UR5 joint goal 2 pi - 0.3 rad round the base, a post behind the arm: no path (the arm would
    wind through the post); the same placements 0.3 rad the other way plan at once. The failure
    said only "no collision-free path found"; it now names the turn and the nearer goal."""
    mg = MotionGenerator("ur5")
    mg.update_world({"cuboid": {"post": {"dims": [0.2, 0.1, 1.6], "pose": [-0.25, 0, 0.7, 1, 0, 0, 0]}}})
    start = np.array([0.0, -np.pi / 2, 0.0, -np.pi / 2, 0.0, 0.0])
    goal = start.copy()
    goal[0] = 2 * np.pi - 0.3
    r = mg.plan_joints(start, goal, time_budget=1.0)
    assert r.status in (PlanStatus.PLAN_FAIL, PlanStatus.TIMEOUT)
    assert "turns shoulder_pan_joint by +5.98 rad" in r.message and "shoulder_pan_joint at -0.300 rad" in r.message
    near = start.copy()
    near[0] = -0.3
    assert mg.plan_joints(start, near).success
