"""Plans depend on the seed, not on the clock or the garbage collector: a clock that jumps (a slow,
loaded machine) and collections at other points give the same plans bit for bit, as long as the
plan's own deadline has not passed (README, "Counts, not the clock")."""

from __future__ import annotations

import gc
import itertools
import threading
import time

import numpy as np
import pytest

from manip import MotionGenerator, PlanStatus, Pose, PositionConstraint
from manip.benchmarking.scenes import make_problems
from manip.planning.context import SAFETY_NET

DOWN = [0, 1, 0, 0]
TCP = "panda_hand_tcp"
#: A budget the jumping clock cannot use up (a jump of JUMP s per reading, ~10^4 readings per plan).
BUDGET = 1e9
JUMP = 2.0


@pytest.fixture
def jumping_clock(monkeypatch):
    """`time.perf_counter` advancing JUMP s more at every reading (as if each stage between two
    readings took seconds): only a deadline reads it, and none of the plan's is reached."""
    real = time.perf_counter
    jumps = itertools.count()

    def clock() -> float:
        return real() + JUMP * next(jumps)

    def use():
        monkeypatch.setattr(time, "perf_counter", clock)

    return use


def _same(a, b) -> None:
    assert (a.status, a.success, a.attempts, a.source) == (b.status, b.success, b.attempts, b.source)
    assert SAFETY_NET not in a.message and SAFETY_NET not in b.message
    assert a.message == b.message
    for x, y in ((a.path, b.path), (a.goal_q, b.goal_q)):
        assert (x is None) == (y is None) and (x is None or np.array_equal(x, y))
    if a.trajectory is not None:
        assert np.array_equal(a.trajectory.positions, b.trajectory.positions)
        assert np.array_equal(a.trajectory.velocities, b.trajectory.velocities)


@pytest.fixture(scope="module")
def cage():
    mg = MotionGenerator("franka", seed=0)
    return mg, make_problems("cage", 2, seed=3)


def _plans(mg, problems):
    out = []
    for p in problems:
        mg.update_world(p.world)
        out.append(mg.plan_joints(p.start, p.goal, time_budget=BUDGET))
        out.append(mg.plan_pose(p.start, mg.fk(p.goal), time_budget=BUDGET))
    return out


def test_a_jumping_clock_gives_the_same_plans(cage, jumping_clock):
    mg, problems = cage
    ref = _plans(mg, problems)
    assert any(r.source != "straight_line" for r in ref)  # searched, shortcut, optimised
    jumping_clock()
    for a, b in zip(_plans(mg, problems), ref):
        _same(a, b)


def test_garbage_collection_at_other_points_gives_the_same_plans(cage):
    mg, problems = cage
    ref = _plans(mg, problems)
    threshold = gc.get_threshold()
    try:
        gc.set_threshold(1, 1, 1)   # a collection at (nearly) every allocation of a container
        collected = _plans(mg, problems)
        gc.disable()
        uncollected = _plans(mg, problems)
    finally:
        gc.enable()
        gc.set_threshold(*threshold)
    for a, b, c in zip(collected, uncollected, ref):
        _same(a, c)
        _same(b, c)


def test_two_threads_on_separate_generators_under_collections_plan_as_in_sequence(cage):
    """Two generators planning at once while a third thread collects garbage in a loop."""
    mg, problems = cage
    ref = _plans(mg, problems)
    out: dict = {}
    stop = threading.Event()

    def collect():
        while not stop.is_set():
            gc.collect()

    def plan(k: int):
        out[k] = _plans(MotionGenerator("franka", seed=0), problems)

    threads = [threading.Thread(target=plan, args=(k,)) for k in range(2)]
    collector = threading.Thread(target=collect)
    collector.start()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    stop.set()
    collector.join()
    for k in range(2):
        for a, b in zip(out[k], ref):
            _same(a, b)


def test_the_constraint_check_of_a_failed_plan_reads_no_clock_of_its_own(jumping_clock):
    """A constrained plan that failed by its count (`search_iterations`) asks an unconstrained search
    whether the constraints are to blame; that search is bounded by counts and by the plan's own
    deadline only (before, by a second 1 s deadline of its own: on a slow machine it gave PLAN_FAIL
    where a fast one gave CONSTRAINT_INFEASIBLE, with no SAFETY_NET in the message)."""
    world = {"cuboid": {"wall": {"dims": [0.5, 0.04, 0.6], "pose": [0.5, 0.0, 0.3, 1, 0, 0, 0]}}}
    mg = MotionGenerator("franka", world, seed=0)
    box = PositionConstraint(lower=(0.3, -0.5, 0.1), upper=(0.7, 0.5, 0.5), link=TCP)
    q0 = mg.ik(Pose([0.45, 0.3, 0.3], DOWN), TCP, collision_free=True).q
    goal = Pose([0.45, -0.3, 0.3], DOWN)

    def plan():
        return mg.plan_pose(q0, goal, TCP, constraints=(box,), search_iterations=200, time_budget=BUDGET)

    ref = plan()
    assert ref.status is PlanStatus.CONSTRAINT_INFEASIBLE, ref.message
    jumping_clock()
    _same(plan(), ref)


def test_a_constraint_check_cut_by_the_clock_says_so(monkeypatch):
    """When the clock runs past the plan's deadline during that check (a slow machine), the
    check may stop early: the result (PLAN_FAIL instead of CONSTRAINT_INFEASIBLE) then ends with
    SAFETY_NET, as every answer the clock may have changed does."""
    from manip.planning import pipeline

    world = {"cuboid": {"wall": {"dims": [0.5, 0.04, 0.6], "pose": [0.5, 0.0, 0.3, 1, 0, 0, 0]}}}
    mg = MotionGenerator("franka", world, seed=0)
    box = PositionConstraint(lower=(0.3, -0.5, 0.1), upper=(0.7, 0.5, 0.5), link=TCP)
    q0 = mg.ik(Pose([0.45, 0.3, 0.3], DOWN), TCP, collision_free=True).q
    real, late = time.perf_counter, itertools.count()
    original = pipeline._constraint_failure

    def slow_check(*args, **kwargs):   # from here on, every reading of the clock is 100 s later
        monkeypatch.setattr(time, "perf_counter", lambda: real() + 100.0 * next(late))
        return original(*args, **kwargs)

    monkeypatch.setattr(pipeline, "_constraint_failure", slow_check)
    r = mg.plan_pose(q0, Pose([0.45, -0.3, 0.3], DOWN), TCP, constraints=(box,), search_iterations=200)
    assert r.status is PlanStatus.PLAN_FAIL and r.message.endswith(SAFETY_NET), (r.status, r.message)
