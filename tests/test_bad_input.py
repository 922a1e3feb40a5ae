"""Hostile inputs to the planner side's public API: every call raises a manip error (an
InvalidInputError or an UnknownNameError, both ValueError/KeyError subclasses) whose message
names the argument that was wrong. Nothing is silently clamped, truncated or coerced.

Classes covered: NaN and inf, wrong shapes, wrong dtypes (strings, complex, booleans,
None, objects), unknown names, empty names, zero and non-unit quaternions, degenerate
shapes, missing mesh files, duplicate names, absurd sizes (more samples or IK points than
the documented maxima), unknown options and options of the wrong type.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from manip import InvalidInputError, MotionGenerator, Pose, UnknownNameError
from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.control import ReactiveController
from manip.collision import Capsule, CollisionChecker, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.errors import ManipError
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.planning import PlanStatus
from manip.planning.options import PlanOptions
from manip.robot_config import load_robot_config
from manip.validation import MAX_SAMPLES
from robot_constants import FRANKA_READY

READY = np.array(FRANKA_READY)
GOAL = np.array([0.5, -0.4, 0.2, -2.0, 0.1, 1.9, 0.6])
DOWN = [0.0, 1.0, 0.0, 0.0]
HAND_GOAL = Pose([0.45, 0.2, 0.35], DOWN)
TABLE = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]}}}


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", TABLE)


def _raises(fn, names: str | tuple[str, ...], exc=(InvalidInputError, UnknownNameError)):
    """fn() raises `exc` and the message names one of `names` (the argument)."""
    with pytest.raises(exc) as info:
        fn()
    assert isinstance(info.value, ManipError)
    names = (names,) if isinstance(names, str) else names
    message = str(info.value)
    assert any(n in message for n in names), f"message does not name {names}: {message}"
    return message


BAD_Q = [
    ("nan", np.r_[np.nan, READY[1:]]),
    ("inf", np.r_[np.inf, READY[1:]]),
    ("short", READY[:6]),
    ("long", np.r_[READY, 0.0]),
    ("3d", READY[None, None]),
    ("strings", ["a"] * 7),
    ("complex", READY + 1j),
    ("booleans", [True] * 7),
    ("none", None),
    ("ragged", [[0.0] * 7, [0.0] * 6]),
    ("scalar", 0.5),
]


# ---------------------------------------------------------------------------- configurations
@pytest.mark.parametrize("kind, q", BAD_Q, ids=[k for k, _ in BAD_Q])
def test_fk_bad_q(mg, kind, q):
    _raises(lambda: mg.fk(q), "q")


@pytest.mark.parametrize("kind, q", BAD_Q, ids=[k for k, _ in BAD_Q])
def test_plan_joints_bad_start_and_goal(mg, kind, q):
    _raises(lambda: mg.plan_joints(q, GOAL), "start_q")
    _raises(lambda: mg.plan_joints(READY, q), "goal_q")


@pytest.mark.parametrize("kind, q", BAD_Q, ids=[k for k, _ in BAD_Q])
def test_collision_queries_bad_q(mg, kind, q):
    _raises(lambda: mg.check_collision(q), "q")
    _raises(lambda: mg.distance(q), "q")


def test_complex_q_is_not_truncated(mg):
    """NumPy would drop the imaginary part (with a warning) and answer for the real part."""
    _raises(lambda: mg.fk(READY + 0.5j), "q")
    _raises(lambda: mg.fk(np.asarray(READY, dtype=complex)), "q")



def test_a_joint_state_object_says_to_pass_the_numbers(mg):
    # a cuRobo JointState (its .position a (1, dof) tensor) given where manip takes an array:
    # it said only "non-numeric values <JointState object>"
    class JointState:
        def __init__(self, position):
            self.position = position

    state = JointState(READY[None])
    msg = _raises(lambda: mg.plan_joints(state, READY), "start_q")
    assert "as cuRobo's JointState: pass the configuration itself as a NumPy array, e.g. js.position[0]" in msg
    msg = _raises(lambda: mg.fk(state), "q")
    assert "js.position[0]" in msg
    assert "JointState" not in _raises(lambda: mg.fk([None] * 7), "q")   # no hint without a .position

def test_batch_where_one_configuration_is_expected(mg):
    _raises(lambda: mg.check_collision(np.stack([READY, READY])), "q")
    _raises(lambda: mg.plan_joints(np.stack([READY, READY]), GOAL), "start_q")
    _raises(lambda: mg.plan_joints(READY, np.stack([GOAL, GOAL])), "goal_q")


# ---------------------------------------------------------------------------- links
@pytest.mark.parametrize("link", ["", "gripper", 0, 1.5, ["panda_hand"], b"panda_hand"])
def test_link_is_never_replaced_by_the_end_effector(mg, link):
    """`link or ee_link` would have answered for the end-effector for "" and 0."""
    _raises(lambda: mg.fk(READY, link), "link")
    _raises(lambda: mg.ik(HAND_GOAL, link), "link")
    _raises(lambda: mg.batch_ik(Pose.stack([HAND_GOAL]), link), "link")
    _raises(lambda: mg.plan_pose(READY, HAND_GOAL, link), "link")
    _raises(lambda: mg.plan_pose(READY, HAND_GOAL, link, linear=True), "link")
    _raises(lambda: mg.plan_goalset(READY, Pose.stack([HAND_GOAL]), link), "link")
    _raises(lambda: mg.attach_object(Cuboid("held", [0.02] * 3), link=link), "link")


def test_unknown_link_lists_the_frames(mg):
    msg = _raises(lambda: mg.fk(READY, "gripper"), "link")
    assert "panda_hand" in msg


# ---------------------------------------------------------------------------- options
BAD_OPTIONS = [
    ("time_budget", 0), ("time_budget", -1.0), ("time_budget", np.nan), ("time_budget", np.inf), ("time_budget", "1"),
    ("search_iterations", 0), ("search_iterations", 2.5), ("search_iterations", "100"), ("search_iterations", True),
    ("search_iterations", 10**7),
    ("seed", "abc"), ("seed", -1), ("seed", 1.5), ("seed", True), ("seed", None),
    ("dt", 0.0), ("dt", -0.01), ("dt", "0.01"), ("dt", 1 + 1j),
    ("velocity_scale", 0.0), ("velocity_scale", 1.5), ("velocity_scale", "1"),
    ("acceleration_scale", -0.5), ("acceleration_scale", np.nan),
    ("duration", 0.0), ("duration", -2.0), ("duration", "3"),
    ("ik_solutions", "3"), ("ik_solutions", 0), ("ik_solutions", 2.5), ("ik_solutions", 10**9),
    ("linear_step", 0), ("linear_step", -1), ("linear_step", "0.01"),
    ("optimize_clearance", "no"), ("optimize_clearance", 1), ("optimize_clearance", None),
    ("trajopt", "yes"), ("trajopt", 0),
    ("smoothness", "fast"), ("smoothness", 1), ("smoothness", None),
]


@pytest.mark.parametrize("name, value", BAD_OPTIONS, ids=[f"{n}={v!r}" for n, v in BAD_OPTIONS])
def test_bad_option_values(mg, name, value):
    _raises(lambda: mg.plan_joints(READY, GOAL, **{name: value}), name)
    _raises(lambda: PlanOptions(**{name: value}), name)


def test_unknown_option_lists_the_valid_ones(mg):
    msg = _raises(lambda: mg.plan_joints(READY, GOAL, time_bugdet=1.0), "time_bugdet")
    assert "time_budget" in msg


def test_plan_batch_checks_options_and_counts(mg):
    _raises(lambda: mg.plan_batch(READY, np.stack([GOAL, GOAL]), seed="abc"), "seed")
    _raises(lambda: mg.plan_batch(np.stack([READY] * 3), np.stack([GOAL, GOAL])), ("start_qs", "goals"))
    _raises(lambda: mg.plan_batch(READY, [HAND_GOAL, GOAL]), "goals")
    _raises(lambda: mg.plan_batch(READY, "goal"), "goals")


def test_plan_batch_of_no_goals_is_empty_whatever_their_form(mg):
    """One start and no goals is a batch of 0 problems, as (0, 7) starts and goals are."""
    empty_pose = Pose(np.zeros((0, 3)), np.zeros((0, 4)))
    for starts in (READY, np.zeros((0, 7))):
        for goals in ([], (), np.zeros((0, 7)), empty_pose):
            assert mg.plan_batch(starts, goals) == [], (starts.shape, goals)
    # no start for two goals is still a count mismatch, and a bad option still fails first
    _raises(lambda: mg.plan_batch(np.zeros((0, 7)), np.stack([GOAL, GOAL])), ("start_qs", "goals"))
    _raises(lambda: mg.plan_batch(READY, [], seed="abc"), "seed")


def test_plan_batch_accepts_a_list_of_poses(mg):
    out = mg.plan_batch(READY, [HAND_GOAL, Pose([0.45, -0.2, 0.35], DOWN)], time_budget=5.0)
    assert len(out) == 2 and all(r.success for r in out)


def test_boolean_arguments(mg):
    _raises(lambda: mg.plan_pose(READY, HAND_GOAL, linear="yes"), "linear")
    _raises(lambda: mg.ik(HAND_GOAL, collision_free="yes"), "collision_free")
    _raises(lambda: mg.batch_ik(Pose.stack([HAND_GOAL]), collision_free=1), "collision_free")


# ---------------------------------------------------------------------------- absurd sizes
def test_absurd_sample_counts_are_refused(mg):
    """More than MAX_SAMPLES samples: refused before anything is allocated."""
    _raises(lambda: mg.plan_joints(READY, GOAL, velocity_scale=1e-6), "velocity_scale")
    _raises(lambda: mg.plan_joints(READY, GOAL, acceleration_scale=1e-9), "acceleration_scale")
    _raises(lambda: mg.plan_joints(READY, GOAL, duration=1e6), "duration")
    _raises(lambda: mg.plan_joints(READY, GOAL, dt=1e-7), "dt")
    _raises(lambda: mg.plan_pose(READY, HAND_GOAL, dt=1e-7), "dt")
    _raises(lambda: PlanOptions(duration=MAX_SAMPLES * 0.1, dt=0.01), "duration")
    PlanOptions(duration=(MAX_SAMPLES - 10) * 0.01, dt=0.01)  # within the maximum


def test_absurd_linear_step_is_refused(mg):
    _raises(lambda: mg.plan_pose(READY, HAND_GOAL, linear=True, linear_step=1e-7), "linear_step")


def test_documented_maxima():
    assert MAX_SAMPLES == 100_000
    from manip.motion_generator import MAX_LINEAR_POINTS

    assert MAX_LINEAR_POINTS == 10_000


# ---------------------------------------------------------------------------- goals near limits
def test_joint_goal_within_the_limit_tolerance_is_clipped(mg):
    """A goal 1e-5 rad past a limit is treated like a start: accepted, ending on the limit."""
    goal = GOAL.copy()
    goal[3] = mg.upper_limits[3] + 1e-5
    r = mg.plan_joints(READY, goal, seed=0)
    assert r.success, r.message
    assert r.trajectory.positions[-1][3] == pytest.approx(mg.upper_limits[3], abs=1e-9)
    assert np.all(r.trajectory.positions <= mg.upper_limits + 1e-9)
    goal[3] = mg.upper_limits[3] + 1e-3
    r = mg.plan_joints(READY, goal, seed=0)
    assert r.status is PlanStatus.INVALID_GOAL and "panda_joint4" in r.message


# ---------------------------------------------------------------------------- constructor
@pytest.mark.parametrize("kwargs, name", [
    (dict(robot=None), "robot"), (dict(robot=123), "robot"), (dict(robot="no_such_robot"), "robot"),
    (dict(world=[1, 2]), "world"), (dict(world={"box": {}}), "kind"),
    (dict(padding=-0.1), "padding"), (dict(padding="0.1"), "padding"), (dict(padding=np.nan), "padding"),
    (dict(time_budget=0), "time_budget"), (dict(interpolation_dt=-1.0), "dt"),
    (dict(resolution=0.0), "resolution"), (dict(search_resolution=-1), "search_resolution"),
    (dict(seed="abc"), "seed"), (dict(seed=-1), "seed"), (dict(seed=1.5), "seed"),
])
def test_constructor_arguments(kwargs, name):
    _raises(lambda: MotionGenerator(**kwargs), name)


# ---------------------------------------------------------------------------- poses and quaternions
@pytest.mark.parametrize("quaternion", [[0, 0, 0, 0], [2, 0, 0, 0], [1, 0, 0], [np.nan, 0, 0, 1], [1 + 1j, 0, 0, 0],
                                        ["w", "x", "y", "z"]])
def test_bad_quaternions(quaternion):
    _raises(lambda: Pose([0, 0, 0], quaternion), "quaternion")


@pytest.mark.parametrize("position", [[0, 0], [np.nan, 0, 0], [np.inf, 0, 0], ["x", "y", "z"], [1j, 0, 0], None])
def test_bad_positions(position):
    _raises(lambda: Pose(position), "position")


def test_pose_constructors():
    _raises(lambda: Pose.from_matrix(np.eye(3)), "matrix")
    _raises(lambda: Pose.from_matrix(2 * np.eye(4)), "matrix")
    _raises(lambda: Pose.from_xyz_xyzw([0, 0, 0, 1]), "x, y, z")
    _raises(lambda: Pose.from_xyz_wxyz([0, 0, 0, 0, 0, 0, 0]), "quaternion")
    _raises(lambda: Pose.stack([]), "poses")
    _raises(lambda: Pose.stack([HAND_GOAL, [0, 0, 0]]), "poses")
    _raises(lambda: HAND_GOAL.transform_points([[1, 2]]), "points")
    _raises(lambda: quat.normalize([0.0, 0.0, 0.0, 0.0]), "quaternion")


def test_goals_of_the_wrong_type(mg):
    _raises(lambda: mg.ik([0.4, 0.0, 0.4]), "goal")
    _raises(lambda: mg.batch_ik([HAND_GOAL, HAND_GOAL]), "goals")
    _raises(lambda: mg.plan_pose(READY, [0.4, 0.0, 0.4]), "goal")
    _raises(lambda: mg.plan_pose(READY, Pose.stack([HAND_GOAL, HAND_GOAL])), "goal")
    _raises(lambda: mg.plan_goalset(READY, [HAND_GOAL]), "goals")


# ---------------------------------------------------------------------------- IK
def test_ik_arguments(mg):
    _raises(lambda: mg.ik(HAND_GOAL, seed_q=[0.0] * 6), "seed_q")
    _raises(lambda: mg.ik(HAND_GOAL, num_solutions=0), "num_solutions")
    _raises(lambda: mg.ik(HAND_GOAL, num_solutions="3"), "num_solutions")
    _raises(lambda: mg.ik(HAND_GOAL, seed="x"), "seed")
    _raises(lambda: mg.ik(HAND_GOAL, time_limit=-1.0), "time_limit")
    _raises(lambda: mg.ik(HAND_GOAL, validity_fn="not callable"), "validity_fn")
    _raises(lambda: mg.batch_ik(Pose.stack([HAND_GOAL, HAND_GOAL]), seed_q=np.zeros((3, 7))), "seed_q")
    solver = mg.ik_solver
    _raises(lambda: solver.solve_many(HAND_GOAL, n=0), "n")
    _raises(lambda: solver.solve_many(HAND_GOAL, attempts=2.5), "attempts")
    _raises(lambda: solver.solve_many(HAND_GOAL, min_distance=-1), "min_distance")


@pytest.mark.parametrize("kwargs, name", [
    (dict(position_tolerance=0), "position_tolerance"), (dict(rotation_tolerance=np.nan), "rotation_tolerance"),
    (dict(max_iterations=1.5), "max_iterations"), (dict(max_attempts=0), "max_attempts"),
    (dict(seed="abc"), "seed"), (dict(damping=-1), "damping"), (dict(max_step=0), "max_step"),
])
def test_ik_solver_settings(mg, kwargs, name):
    _raises(lambda: IKSolver(mg.kinematics, **kwargs), name)


def test_batched_ik_honours_collision_free(mg):
    """Every solution of a collision-free batched IK is free; the deprecated batched `ik`
    forwards the flag."""
    goals = Pose.stack([Pose([0.5, y, 0.02], DOWN) for y in (-0.2, 0.0, 0.2)] + [HAND_GOAL])  # hand in the table
    free = mg.batch_ik(goals, seed_q=READY, collision_free=True)
    loose = mg.batch_ik(goals, seed_q=READY)
    for ok, q in zip(free.success, free.q):
        if ok:
            assert not mg.check_collision(q)
    assert free.success[-1]
    assert any(ok and mg.check_collision(q) for ok, q in zip(loose.success, loose.q))
    with pytest.warns(DeprecationWarning):
        old = mg.ik(goals, seed_q=READY, collision_free=True)
    for ok, q in zip(old.success, old.q):
        if ok:
            assert not mg.check_collision(q)


# ---------------------------------------------------------------------------- world
@pytest.mark.parametrize("make, name", [
    (lambda: Cuboid("b", [0.1, 0.1]), "dims"), (lambda: Cuboid("b", [0.1, -0.1, 0.1]), "dims"),
    (lambda: Cuboid("b", [0.1, np.nan, 0.1]), "dims"), (lambda: Cuboid("b", ["a", 1, 1]), "dims"),
    (lambda: Cuboid("b", [0.0, 0.1, 0.1]), "dims"), (lambda: Cuboid("", [0.1] * 3), "name"),
    (lambda: Cuboid(3, [0.1] * 3), "name"), (lambda: Cuboid("b", [0.1] * 3, [0, 0]), "pose"),
    (lambda: Cuboid("b", [0.1] * 3, [0, 0, np.nan]), "pose"), (lambda: Cuboid("b", [0.1] * 3, [0, 0, 0, 0, 0, 0, 0]), "quaternion"),
    (lambda: Cuboid("b", [0.1] * 3, [0, 0, 0, 2, 0, 0, 0]), "quaternion"), (lambda: Cuboid("b", [0.1] * 3, [1j, 0, 0]), "pose"),
    (lambda: Sphere("s", 0.0), "radius"), (lambda: Sphere("s", -1), "radius"), (lambda: Sphere("s", "big"), "radius"),
    (lambda: Sphere("s", np.inf), "radius"), (lambda: Cylinder("c", 0.1, 0.0), "height"),
    (lambda: Cylinder("c", np.nan, 0.1), "radius"), (lambda: Capsule("c", 0.1, -1), "height"),
    (lambda: Mesh("m", file_path="/no/such/file.stl"), "file_path"),
    (lambda: Mesh("m", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0.5, 1, 2]]), "faces"),
    (lambda: Mesh("m", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 3]]), "face"),
    (lambda: Mesh("m", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[["a", 1, 2]]), "faces"),
    (lambda: Mesh("m", vertices=[[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]]), "vertices"),
    (lambda: Mesh("m", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]], scale=0), "scale"),
    (lambda: Mesh("m"), "file_path"),
])
def test_degenerate_shapes(make, name):
    _raises(make, name)


def test_mesh_faces_from_a_dict_are_not_truncated():
    world = {"mesh": {"m": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "faces": [[0.5, 1, 2]]}}}
    _raises(lambda: WorldConfig.from_dict(world), "faces")
    ok = {"mesh": {"m": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "faces": [[0.0, 1.0, 2.0]]}}}
    assert WorldConfig.from_dict(ok).get("m").faces.tolist() == [[0, 1, 2]]


def test_world_dicts():
    _raises(lambda: WorldConfig.from_dict({"box": {}}), "kind")
    _raises(lambda: WorldConfig.from_dict({"cuboid": {"b": {"dims": [0.1] * 3, "size": 1}}}), "key")
    _raises(lambda: WorldConfig.from_dict({"cuboid": {"b": {"pose": [0, 0, 0]}}}), "dims")
    _raises(lambda: WorldConfig.from_dict([1]), "world")
    _raises(lambda: WorldConfig.from_yaml("/no/such/world.yml"), "world file")
    w = WorldConfig([Cuboid("b", [0.1] * 3)])
    _raises(lambda: w.add(Cuboid("b", [0.2] * 3)), "name")
    _raises(lambda: w.add("b"), "obstacle")
    _raises(lambda: w.remove("c"), "obstacle", UnknownNameError)


def test_world_edits(mg):
    _raises(lambda: mg.add_obstacle("box"), "obstacle")
    _raises(lambda: mg.add_obstacle(Cuboid("table", [0.1] * 3)), "name")
    _raises(lambda: mg.remove_obstacle("nothing"), "obstacle", UnknownNameError)
    _raises(lambda: mg.update_world(42), "world")
    # a cuRobo user's world file name: the message says how to read it
    _raises(lambda: mg.update_world("collision_table.yml"), "WorldConfig.from_yaml(path)")
    _raises(lambda: MotionGenerator("franka", Path("collision_table.yml")), "WorldConfig.from_yaml(path)")
    _raises(lambda: mg.checker.update_obstacle_pose("table", [0, 0]), "pose")
    _raises(lambda: mg.attach_object("nothing"), "obstacle", UnknownNameError)
    _raises(lambda: mg.attach_object(Cuboid("held", [0.02] * 3), q=[0.0] * 6), "q")
    _raises(lambda: mg.detach_object(READY, name="nothing"), "attached object", UnknownNameError)
    assert mg.world.names == ["table"]


def test_collision_checker_arguments(mg):
    ck = mg.checker
    _raises(lambda: CollisionChecker(mg.config, mg.kinematics, padding=-1), "padding")
    _raises(lambda: setattr(ck, "padding", "big"), "padding")
    _raises(lambda: ck.motion_valid(READY, GOAL, resolution=0), "resolution")
    _raises(lambda: ck.path_valid(np.zeros((0, 7))), "path")
    _raises(lambda: ck.certify_path(np.full((3, 7), np.nan)), "path")
    _raises(lambda: ck.in_collision_batch(np.zeros((4, 6))), "Q")


# ---------------------------------------------------------------------------- robots
def test_robot_configs():
    _raises(lambda: load_robot_config("no_such_robot"), "robot", UnknownNameError)
    kin = Kinematics(load_robot_config("franka"))
    _raises(lambda: kin.frame_id(""), "link", UnknownNameError)
    _raises(lambda: kin.frame_id(None), "link")
    _raises(lambda: kin.check_q(READY + 1j, "start_q"), "start_q")


# ---------------------------------------------------------------------------- articulation actions
@pytest.mark.parametrize("kwargs, name", [
    (dict(joint_positions=[0.1, 0.2], joint_indices=[0.7, 1.9]), "joint_indices"),
    (dict(joint_positions=[0.1], joint_indices=[-1]), "joint_indices"),
    (dict(joint_positions=[0.1], joint_indices=["a"]), "joint_indices"),
    (dict(joint_positions=[0.1], joint_indices=[True]), "joint_indices"),
    (dict(joint_positions=[0.1], joint_indices=[np.nan]), "joint_indices"),
    (dict(joint_positions=["a"]), "joint_positions"),
    (dict(joint_positions=[1 + 1j]), "joint_positions"),
    (dict(joint_velocities=[np.inf]), "joint_velocities"),
    (dict(joint_efforts=[True]), "joint_efforts"),
    (dict(joint_positions=[0.1, 0.2], joint_indices=[0]), "lengths"),
])
def test_articulation_action(kwargs, name):
    _raises(lambda: ArticulationAction(**kwargs), name)


def test_articulation_action_accepts_integral_indices():
    assert ArticulationAction([0.1, 0.2], joint_indices=np.array([0.0, 3.0])).joint_indices.tolist() == [0, 3]
    assert ArticulationAction([0.1, None], joint_indices=np.array([1, 2])).joint_indices.tolist() == [1, 2]


def test_no_file_is_created(tmp_path: Path):
    """A refused world file leaves nothing behind (sanity of the error path)."""
    _raises(lambda: WorldConfig.from_yaml(tmp_path / "missing.yml"), "world file")
    assert list(tmp_path.iterdir()) == []


def test_more_collision_arguments(mg):
    _raises(lambda: CollisionChecker(mg.config, mg.kinematics, sphere_tolerance=0.0), "sphere_tolerance")
    _raises(lambda: mg.attach_object(Cuboid("held", [0.02] * 3), q=READY, allowed_links="panda_hand"), "allowed_links")
    _raises(lambda: mg.attach_object(Cuboid("held", [0.02] * 3), q=READY, allowed_links=["nope"]), "link",
            UnknownNameError)
    _raises(lambda: mg.checker.set_gripper_positions([0.04, 1j]), "gripper")
    _raises(lambda: mg.checker.set_gripper_positions([0.04, 0.5]), "gripper")
    _raises(lambda: load_robot_config(123), "robot", UnknownNameError)
    # a MotionGenerator where a robot is expected (the reactive controller's first argument):
    # it was "robot '<manip.motion_generator.MotionGenerator object at 0x...>' not found"
    _raises(lambda: ReactiveController(mg), "which holds one: pass its .config", InvalidInputError)
    assert ReactiveController(mg.config).step(READY, mg.fk(READY, "panda_hand_tcp"), 0.01) is not None
    assert not mg.checker.attached_objects


def test_an_empty_batch_of_goal_poses_is_refused(mg):
    # plan_goalset crashed with "ValueError: min() arg is an empty sequence"; plan_grasp
    # returned IK_FAIL "no grasp candidate was tried"; plan_place blamed "poses"
    empty = Pose(np.zeros((0, 3)), np.zeros((0, 4)))
    _raises(lambda: mg.plan_goalset(READY, empty), "goals must hold at least one pose")
    mg.add_obstacle(Cuboid("cube_e", [0.05] * 3, Pose([0.5, 0.0, 0.05])))
    try:
        _raises(lambda: mg.plan_grasp(READY, empty, "cube_e"), "grasps must hold at least one pose")
        mg.attach_object("cube_e", q=READY)
        _raises(lambda: mg.plan_place(READY, empty), "placements must hold at least one pose")
        mg.detach_object(READY)
    finally:
        mg.remove_obstacle("cube_e")
    assert len(mg.batch_ik(empty).success) == 0 and mg.batch_ik(empty).solution.shape == (0, 1, 7)  # batches of 0
    assert mg.plan_batch(np.zeros((0, 7)), empty) == []


def test_a_results_truth_is_its_success_so_if_result_cannot_let_a_failure_through(mg):
    """`if result:` tests `.success` (an object's default truth, always true, let a failed plan
    through); a batch of IK results (one success per goal) has no truth value."""
    from manip.timing import time_path

    q0 = mg.default_joint_positions
    ok = [mg.plan_joints(q0, q0 + 0.1), mg.ik(mg.fk(q0)), time_path(np.array([q0, q0 + 0.1]), mg.config.limits)]
    failed = [mg.ik(Pose([3.0, 0.0, 0.5], [0, 1, 0, 0])),   # out of reach
              mg.plan_pose(q0, Pose([3.0, 0.0, 0.5], [0, 1, 0, 0]))]
    assert [r.success for r in ok + failed] == [True, True, True, False, False]
    assert [bool(r) for r in ok + failed] == [True, True, True, False, False]
    batch = mg.batch_ik(Pose(np.array([mg.fk(q0).position, [3.0, 0.0, 0.5]]), np.array([[0, 1, 0, 0]] * 2)))
    assert batch.solved.tolist() == [True, False] and batch.success.tolist() == [[True], [False]]
    with pytest.raises(TypeError, match=r"success"):
        bool(batch)
