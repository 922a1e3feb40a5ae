"""A MotionGenerator shared by threads: concurrent reads give the sequential answers, world
edits from another thread never break a plan, and each plan sees one world."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from manip import MotionGenerator, Pose
from manip.collision import Cuboid, Sphere, WorldConfig
from robot_constants import FRANKA_READY

READY = np.array(FRANKA_READY)
#: Planning budget of the determinism checks [s]: generous, so that only the seed decides a plan.
BUDGET = 60.0
WORLD = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0.0, -0.02, 1, 0, 0, 0]},
                    "post": {"dims": [0.06, 0.06, 0.5], "pose": [0.45, 0.0, 0.25, 1, 0, 0, 0]}}}


@pytest.fixture(scope="module")
def mg():
    return MotionGenerator("franka", WORLD)


def _run(workers):
    """Run the callables in threads; re-raise the first exception of any of them."""
    errors = []

    def wrap(fn):
        try:
            fn()
        except BaseException as exc:  # noqa: BLE001 - reported below
            errors.append(exc)

    threads = [threading.Thread(target=wrap, args=(fn,)) for fn in workers]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]


def _configs(mg, n, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(mg.lower_limits, mg.upper_limits, (n, mg.robot_dof))


def test_fk_from_two_threads_matches_sequential(mg):
    Q = _configs(mg, 1500, 0)
    ref = [mg.fk(q) for q in Q]
    out = [[None] * len(Q), [None] * len(Q)]

    def work(k):
        return lambda: [out[k].__setitem__(i, mg.fk(q)) for i, q in enumerate(Q)]

    _run([work(0), work(1)])
    for k in range(2):
        for a, b in zip(out[k], ref):
            assert np.array_equal(a.position, b.position) and np.array_equal(a.quaternion, b.quaternion)


def test_ik_and_batch_ik_from_two_threads_match_sequential(mg):
    goals = mg.fk(_configs(mg, 12, 1))
    ref = [mg.ik(g, seed_q=READY) for g in goals]
    ref_batch = mg.batch_ik(goals, seed_q=READY)
    out: dict = {}

    def single():
        out["single"] = [mg.ik(g, seed_q=READY) for g in goals]

    def batch():
        out["batch"] = mg.batch_ik(goals, seed_q=READY)

    _run([single, batch])
    for a, b in zip(out["single"], ref):
        assert a.success == b.success and np.array_equal(a.q, b.q)
    assert np.array_equal(out["batch"].q, ref_batch.q)
    assert np.array_equal(out["batch"].success, ref_batch.success)


def _plan_problems(mg):
    starts = [READY, READY + np.array([0.3, 0.2, 0.0, 0.1, 0.0, 0.1, 0.0])]
    goals = [np.array([0.9, 0.3, 0.2, -1.9, -0.1, 2.1, 0.9]), np.array([-0.8, 0.2, -0.1, -2.0, 0.1, 2.0, 0.5])]
    return list(zip(starts, goals))


def test_plans_from_two_threads_with_a_world_editing_thread():
    """Two planning threads and a thread removing and adding obstacles far from the robot
    (listed before the near ones, so every edit shifts the near obstacles' indices): every
    plan gives the sequential answer (the optimiser is off to keep the test short; every stage
    is bounded by counts, so only the wall-clock budget could change an answer: it is generous
    here, since on a loaded 2-core CI machine these threaded plans took up to 6 s)."""
    near = list(MotionGenerator("franka", WORLD).world)

    def far_then_near(tag):
        return WorldConfig([Sphere(f"far{tag}_{i}", 0.05, [3.0 + 0.01 * i, 3.0, 3.0]) for i in range(20)] + near)

    mg = MotionGenerator("franka", far_then_near(0))
    problems = _plan_problems(mg)
    ref = [mg.plan_joints(s, g, seed=3, trajopt=False, time_budget=BUDGET) for s, g in problems]
    assert all(r.success for r in ref)
    stop = threading.Event()
    edits = [0]

    def planner(k):
        def fn():
            for _ in range(3):
                s, g = problems[k]
                r = mg.plan_joints(s, g, seed=3, trajopt=False, time_budget=BUDGET)
                assert r.success, r.message
                assert np.array_equal(r.trajectory.positions, ref[k].trajectory.positions)
                assert not mg.check_collision(g)
        return fn

    def editor():
        i = 0
        while not stop.is_set():
            first = mg.world.names[0]
            if first.startswith("far"):
                mg.remove_obstacle(first)  # the near obstacles move down one index
                mg.add_obstacle(Sphere(f"new{i}", 0.05, [3.0 + 0.01 * (i % 50), 3.2, 3.0]))
            else:
                mg.update_world(far_then_near(i))
            i += 1
            edits[0] += 1

    def planners():
        try:
            _run([planner(0), planner(1)])
        finally:
            stop.set()

    _run([planners, editor])
    assert edits[0] > 0


def test_each_plan_sees_one_world_while_an_obstacle_toggles(mg):
    """A thread toggles an obstacle across the straight motion while another plans: no
    error, and every returned trajectory is collision-free in the world it started with
    (with or without the obstacle; both are checked against the world without it)."""
    start, goal = READY, np.array([-0.6, 0.1, 0.0, -2.1, 0.0, 2.2, 0.8])
    blocker = Cuboid("blocker", [0.1, 0.1, 0.1], [0.3, 0.3, 0.5])
    stop = threading.Event()
    results = []

    def toggler():
        while not stop.is_set():
            mg.add_obstacle(blocker)
            mg.remove_obstacle("blocker")

    def planner():
        try:
            for seed in range(4):
                results.append(mg.plan_joints(start, goal, seed=seed, time_budget=120.0))  # a safety net
        finally:
            stop.set()

    _run([planner, toggler])
    assert "blocker" not in mg.world
    assert results and all(r.success for r in results)
    for r in results:
        assert mg.checker.path_valid(r.trajectory.positions, resolution=0.005).valid


def test_snapshot_does_not_see_later_edits(mg):
    q = READY
    hand = mg.fk(q, "panda_hand").position
    snap = mg.checker.snapshot()
    mg.add_obstacle(Sphere("at_hand", 0.05, hand))
    try:
        assert mg.check_collision(q)
        assert not snap.in_collision(q)
        with pytest.raises(Exception, match="read-only"):
            snap.add_obstacle(Sphere("x", 0.1, [2, 2, 2]))
    finally:
        mg.remove_obstacle("at_hand")
    assert not mg.check_collision(q)


def test_pose_goal_plans_from_two_threads(mg):
    goals = [Pose([0.45, 0.25, 0.35], [0, 1, 0, 0]), Pose([0.45, -0.25, 0.35], [0, 1, 0, 0])]
    ref = [mg.plan_pose(READY, g, seed=1, trajopt=False, time_budget=BUDGET) for g in goals]
    out = [None, None]

    def work(k):
        def fn():
            out[k] = mg.plan_pose(READY, goals[k], seed=1, trajopt=False, time_budget=BUDGET)
        return fn

    _run([work(0), work(1)])
    for a, b in zip(out, ref):
        assert a.success == b.success
        if a.success:
            assert np.array_equal(a.trajectory.positions, b.trajectory.positions)


def test_separate_generators_of_different_robots_plan_in_threads_as_in_sequence():
    """README: separate generators may plan in threads at once (round three: the Franka, UR5,
    Kinova and xArm7 at once gave the sequential plans bit for bit; two of them here)."""
    gens = {"franka": MotionGenerator("franka"), "ur5": MotionGenerator("ur5")}
    problems = {}
    for name, g in gens.items():
        rng = np.random.default_rng([4001, len(name)])
        while True:
            a, b = rng.uniform(g.lower_limits, g.upper_limits, (2, g.robot_dof))
            b = a + np.clip(b - a, -1.0, 1.0)
            if not g.check_collision(a) and not g.check_collision(b):
                break
        problems[name] = (a, b)
    ref = {n: gens[n].plan_joints(*problems[n], seed=5, time_budget=BUDGET) for n in gens}
    assert all(r.success for r in ref.values())
    out = {}
    _run([lambda n=n: out.__setitem__(n, gens[n].plan_joints(*problems[n], seed=5, time_budget=BUDGET)) for n in gens])
    for n in gens:
        assert out[n].success and np.array_equal(out[n].trajectory.positions, ref[n].trajectory.positions), n
