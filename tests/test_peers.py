"""The peer planners of the side-by-side benchmark (benchmarks/peers).

The peers need the `bench` extra (roboplan, ompl, toppra); tests of a peer that is not
installed are skipped with the reason `available_peers()` gives. Trajectories are judged by
the benchmark's independent verifier (`manip.benchmarking.verify`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field

import numpy as np
import pytest
from robot_constants import REPO_ROOT

sys.path.insert(0, str(REPO_ROOT))  # make `benchmarks` importable

from benchmarks.peers import (  # noqa: E402
    PEER_NAMES,
    PeerUnavailableError,
    available_peers,
    get_peer,
)
from benchmarks.peers._common import uniform_times, world_obstacles  # noqa: E402
from manip.errors import InvalidInputError, UnknownNameError  # noqa: E402
from robot_constants import FRANKA_READY  # noqa: E402

AVAILABLE = available_peers()
RUNNABLE = [n for n in ("roboplan", "ompl") if AVAILABLE[n] == "ok"]
ARM = tuple(f"panda_joint{i}" for i in range(1, 8))


try:  # the benchmark's problem type; a stand-in with the same fields when it is absent
    from manip.benchmarking.mbm_problems import MBMProblem as Problem
except ImportError:  # pragma: no cover

    @dataclass(frozen=True)
    class Problem:  # type: ignore[no-redef]
        """Stand-in with the fields of `manip.benchmarking.mbm_problems.MBMProblem`."""

        scene: str
        index: int
        world: dict = field(repr=False)
        start: np.ndarray = field(repr=False)
        goal: np.ndarray = field(repr=False)
        joint_names: tuple[str, ...] = ARM


READY = np.array(FRANKA_READY)
# A box right where the hand passes when joint 1 swings from -1 to +1 rad: the straight
# joint-space line collides, start and goal do not.
WALL_WORLD = {"cuboid": {"block": {"dims": [0.2, 0.2, 0.3], "pose": [0.45, 0.0, 0.45, 1.0, 0.0, 0.0, 0.0]}}}
WALL_START = READY + np.array([-1.0, 0, 0, 0, 0, 0, 0])
WALL_GOAL = READY + np.array([1.0, 0, 0, 0, 0, 0, 0])


def wall_problem() -> Problem:
    return Problem("wall", 1, WALL_WORLD, WALL_START.copy(), WALL_GOAL.copy())


def param(name: str):
    return pytest.param(name, marks=pytest.mark.skipif(AVAILABLE[name] != "ok", reason=f"{name}: {AVAILABLE[name]}"))


PEERS = [param("roboplan"), param("ompl")]


@pytest.fixture(scope="module")
def verifier():
    verify = pytest.importorskip("manip.benchmarking.verify", reason="the benchmark's verifier is not in this checkout")
    return verify.default_verifier()


@pytest.fixture(scope="module")
def peers() -> dict:
    return {n: get_peer(n, timeout_s=20.0) for n in RUNNABLE}


# ---------------------------------------------------------------------------- registry
def test_available_peers_lists_every_peer_with_a_reason():
    assert tuple(AVAILABLE) == PEER_NAMES
    assert "source package" in AVAILABLE["vamp"] and "download" in AVAILABLE["vamp"]
    assert "numpy < 2" in AVAILABLE["mplib"]
    for name, reason in AVAILABLE.items():
        assert reason == "ok" or len(reason) > 20, name


def test_get_peer_rejects_unknown_and_unavailable_names():
    with pytest.raises(UnknownNameError, match="available: .*ompl.*roboplan"):
        get_peer("moveit")
    for name in ("vamp", "mplib"):
        with pytest.raises(PeerUnavailableError, match=name):
            get_peer(name)


def test_world_obstacles_parses_and_validates():
    obs = world_obstacles(
        {
            "cuboid": {"b": {"dims": [0.1, 0.2, 0.3], "pose": [1, 2, 3, 0, 0, 0, 1]}},
            "cylinder": {"c": {"radius": 0.05, "height": 0.2, "pose": [0, 0, 0, 1, 0, 0, 0]}},
        }
    )
    assert [(o.name, o.kind, o.size) for o in obs] == [("b", "box", (0.1, 0.2, 0.3)), ("c", "cylinder", (0.05, 0.2))]
    # quaternion (w, x, y, z) = (0, 0, 0, 1): a half turn about z
    np.testing.assert_allclose(obs[0].T[:3, :3], np.diag([-1.0, -1.0, 1.0]), atol=1e-12)
    np.testing.assert_allclose(obs[0].T[:3, 3], [1, 2, 3])
    with pytest.raises(InvalidInputError, match="sphere"):
        world_obstacles({"sphere": {"s": {"radius": 0.1, "pose": [0, 0, 0, 1, 0, 0, 0]}}})
    with pytest.raises(InvalidInputError, match="dims"):
        world_obstacles({"cuboid": {"b": {"dims": [0.1, -0.2, 0.3], "pose": [0, 0, 0, 1, 0, 0, 0]}}})
    with pytest.raises(InvalidInputError, match="malformed"):
        world_obstacles({"cylinder": {"c": {"radius": 0.1, "pose": [0, 0, 0, 1, 0, 0, 0]}}})


def test_uniform_times_ends_at_duration():
    t = uniform_times(0.035)
    np.testing.assert_allclose(t, [0.0, 0.01, 0.02, 0.03, 0.035])
    np.testing.assert_allclose(uniform_times(0.03), [0.0, 0.01, 0.02, 0.03])


# ---------------------------------------------------------------------------- planning
def _check_output(out, problem, verifier, goal_pose=None):
    assert out.success, out.status
    assert out.status == "SUCCESS"
    assert out.plan_time_s > 0 and out.setup_time_s >= 0
    T = len(out.times)
    for a in (out.positions, out.velocities, out.accelerations, out.jerks):
        assert a.shape == (T, 7) and np.all(np.isfinite(a))
    assert out.times[0] == 0.0
    dt = np.diff(out.times)
    assert np.all(dt > 0) and np.all(dt <= 0.01 + 1e-9)
    assert np.all(np.abs(dt[:-1] - 0.01) < 1e-6)  # every 0.01 s but the last interval
    assert not out.claims_jerk_limits
    kw = {"goal_pose": goal_pose} if goal_pose is not None else {}
    v = verifier.verify_trajectory(
        problem, out.times, out.positions, velocities=out.velocities, accelerations=out.accelerations, **kw
    )
    assert v.valid, v.reasons
    return v


@pytest.mark.parametrize("name", PEERS)
def test_joint_goal_around_an_obstacle_is_valid(name, peers, verifier):
    problem = wall_problem()
    # the problem needs a detour: the straight joint-space line hits the block
    line = np.linspace(WALL_START, WALL_GOAL, 50)
    assert verifier.first_collision(line, WALL_WORLD) is not None
    assert verifier.check_problem(problem).valid
    out = peers[name].plan(problem, "joint", seed=0)
    v = _check_output(out, problem, verifier)
    np.testing.assert_allclose(out.positions[0], WALL_START, atol=1e-9)
    np.testing.assert_allclose(out.positions[-1], WALL_GOAL, atol=1e-6)
    np.testing.assert_allclose(out.velocities[[0, -1]], 0.0, atol=1e-6)
    assert v.path_length > np.linalg.norm(WALL_GOAL - WALL_START)  # went around
    assert out.n_waypoints >= 3
    assert set(out.stage_times_s) == {"plan", "shortcut", "time_parameterization"}


@pytest.mark.parametrize("name", PEERS)
def test_pose_goal_reaches_the_hand_pose(name, peers, verifier):
    from manip.benchmarking.mbm_problems import goal_pose

    problem = wall_problem()
    out = peers[name].plan(problem, "pose", seed=1)
    v = _check_output(out, problem, verifier, goal_pose=goal_pose(problem))
    assert v.goal_position_error < 1e-3 and v.goal_rotation_error < 1e-2
    assert "ik" in out.stage_times_s and out.stage_times_s["ik"] <= out.plan_time_s
    np.testing.assert_allclose(out.positions[-1], out.goal_configuration, atol=1e-6)


@pytest.mark.parametrize("name", PEERS)
def test_start_in_collision_is_reported_not_planned(name, peers):
    blocked = {"cuboid": {"around_hand": {"dims": [0.3, 0.3, 0.3], "pose": [0.3, 0.0, 0.6, 1.0, 0.0, 0.0, 0.0]}}}
    out = peers[name].plan(Problem("blocked", 1, blocked, READY.copy(), WALL_GOAL.copy()), "joint")
    assert not out.success
    assert out.status == "INVALID_START"
    assert out.positions is None


@pytest.mark.parametrize("name", PEERS)
def test_bad_inputs_raise(name, peers):
    with pytest.raises(InvalidInputError, match="goal_kind"):
        peers[name].plan(wall_problem(), "cartesian")
    bad = Problem("wall", 1, WALL_WORLD, WALL_START[:6], WALL_GOAL)
    with pytest.raises(InvalidInputError, match="start"):
        peers[name].plan(bad, "joint")


@pytest.mark.parametrize("name", PEERS)
def test_world_is_cleared_between_problems(name, peers, verifier):
    """A second, obstacle-free problem must not see the first problem's obstacles."""
    peer = peers[name]
    assert not peer.plan(
        Problem("blocked", 1, {"cuboid": {"b": {"dims": [0.3, 0.3, 0.3], "pose": [0.3, 0.0, 0.6, 1, 0, 0, 0]}}}, READY.copy(), WALL_GOAL.copy()),
        "joint",
    ).success
    free = Problem("free", 1, {}, READY.copy(), WALL_GOAL.copy())
    out = peer.plan(free, "joint")
    _check_output(out, free, verifier)
    assert out.n_waypoints == 2  # straight line once the world is empty


@pytest.mark.skipif(AVAILABLE["roboplan"] != "ok", reason=f"roboplan: {AVAILABLE['roboplan']}")
def test_roboplan_is_deterministic_for_a_seed(peers):
    a = peers["roboplan"].plan(wall_problem(), "joint", seed=3)
    b = peers["roboplan"].plan(wall_problem(), "joint", seed=3)
    assert a.success and b.success
    np.testing.assert_array_equal(a.positions, b.positions)


@pytest.mark.skipif(AVAILABLE["ompl"] != "ok", reason=f"ompl: {AVAILABLE['ompl']}")
def test_stop_at_waypoints_path_stays_on_the_polyline():
    from benchmarks.peers.ompl_peer import StopAtWaypointsPath

    W = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [1.0, 2.0], [0.0, 2.0]])  # one duplicate
    path = StopAtWaypointsPath(W)
    s = np.linspace(0, path.path_interval[1], 401)
    Q = path(s)
    # every point lies on one of the segments
    on_first = (np.abs(Q[:, 1]) < 1e-12) & (Q[:, 0] >= -1e-12) & (Q[:, 0] <= 1 + 1e-12)
    on_second = np.abs(Q[:, 0] - 1) < 1e-12
    on_third = np.abs(Q[:, 1] - 2) < 1e-12
    assert np.all(on_first | on_second | on_third)
    np.testing.assert_allclose(path.knots, [0, 1, 3, 4])
    np.testing.assert_allclose(path(path.knots, 1), 0.0, atol=1e-12)  # rests at waypoints
    # derivatives match finite differences inside a segment
    h = 1e-6
    for s0 in (0.3, 1.7, 3.5):
        np.testing.assert_allclose(path(s0, 1), (path(s0 + h) - path(s0 - h)) / (2 * h), atol=1e-6)
        np.testing.assert_allclose(path(s0, 2), (path(s0 + h, 1) - path(s0 - h, 1)) / (2 * h), atol=1e-4)
    with pytest.raises(InvalidInputError):
        StopAtWaypointsPath(np.zeros((3, 2)))


# ---------------------------------------------------------------------------- MotionBenchMaker
def _mbm_problem(scene: str, index: int):
    mbm = pytest.importorskip("manip.benchmarking.mbm_problems", reason="the benchmark's MBM loader is not in this checkout")
    if not mbm.dataset_available():
        pytest.skip(f"MotionBenchMaker dataset not found at {mbm.default_dataset_path()}")
    return [p for p in mbm.load_mbm_problems(scenes=[scene], limit_per_scene=index) if p.index == index][0]


@pytest.mark.parametrize("name", PEERS)
def test_solves_a_motionbenchmaker_problem(name, peers, verifier):
    problem = _mbm_problem("bookshelf_small_panda", 1)
    assert verifier.check_problem(problem).valid
    out = peers[name].plan(problem, "joint", seed=0)
    _check_output(out, problem, verifier)


@pytest.mark.skipif(AVAILABLE["ompl"] != "ok", reason=f"ompl: {AVAILABLE['ompl']}")
def test_ompl_time_parameterization_respects_the_limits(peers):
    """Stop-at-waypoint TOPP-RA, short segments included: velocity and acceleration (given
    and second divided differences of the positions) stay within the Franka limits."""
    from benchmarks.peers.ompl_peer import StopAtWaypointsPath

    peer = peers["ompl"]
    rng = np.random.default_rng(7)
    for _ in range(8):
        K = int(rng.integers(2, 6))
        W = rng.uniform(0.8 * peer.lower, 0.8 * peer.upper, size=(K, 7))
        frac = np.where(rng.uniform(size=(K - 1, 1)) < 0.3, rng.uniform(1e-4, 1e-2, (K - 1, 1)), rng.uniform(0.05, 1.0, (K - 1, 1)))
        W[1:] = W[:-1] + (W[1:] - W[:-1]) * frac
        times, P, V, A = peer._time_parameterize(StopAtWaypointsPath(W))
        np.testing.assert_allclose(P[0], W[0], atol=1e-12)
        np.testing.assert_allclose(P[-1], W[-1], atol=1e-9)
        dt = np.diff(times)
        v_fd = np.diff(P, axis=0) / dt[:, None]
        a_fd = np.diff(v_fd, axis=0) / (0.5 * (dt[1:] + dt[:-1]))[:, None]
        assert np.max(np.abs(V) / peer.vlim) <= 1.0
        assert np.max(np.abs(v_fd) / peer.vlim) <= 1.0
        assert np.max(np.abs(A) / peer.alim) <= 1.0
        assert np.max(np.abs(a_fd) / peer.alim) <= 1.0
