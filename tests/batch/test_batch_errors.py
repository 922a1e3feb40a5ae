"""manip.batch: a problem that raises inside a worker is a failed result for its id; the batch goes on."""

from __future__ import annotations

import multiprocessing as mp
from collections import Counter

import numpy as np
import pytest

from manip import MotionGenerator
from manip.batch import (
    BATCH_OPTIONS,
    Problem,
    plan_many,
    plan_stream,
    problem_seed,
    worker,
)
from manip.benchmarking.scenes import make_problems
from manip.errors import InvalidInputError
from manip.planning.result import PlanStatus

# Budgets far above the planning times, so that a loaded machine cannot change a result.
OPTIONS = {"time_budget": 30.0}
SEED = 3
#: A valid option that only fails once planned: every motion of these scenes lasts far more than
#: MAX_SAMPLES * 1e-6 s, so the planner raises InvalidInputError("dt: the motion lasts ...").
RAISING = {**OPTIONS, "dt": 1e-6}
BAD = "seeded_table/2"


@pytest.fixture(scope="module")
def problems() -> list[Problem]:
    """Ten table and shelf problems; problem BAD has options that raise once planned."""
    base = make_problems("table", 5, 1) + make_problems("shelf", 5, 1)
    return [Problem(p.world, p.start, p.goal, id=f"{p.scene}/{p.index}",
                    options=RAISING if f"{p.scene}/{p.index}" == BAD else OPTIONS) for p in base]


@pytest.fixture(scope="module")
def reference(problems):
    """The single planning calls of every problem with OPTIONS (BAD's too), in this process."""
    worker.warm_up(("franka",))
    out = {}
    for p in problems:
        mg = MotionGenerator("franka", p.world)
        out[p.id] = mg.plan_joints(p.start, p.goal, seed=problem_seed(SEED, p.id), **{**BATCH_OPTIONS, **OPTIONS})
    return out


def assert_same(result, ref) -> None:
    assert result.status == ref.status and result.success == ref.success
    if ref.trajectory is not None:
        np.testing.assert_array_equal(result.trajectory.positions, ref.trajectory.positions)


def assert_raised(result, pid) -> None:
    assert not result.success
    assert result.status is PlanStatus.RAISED
    assert result.trajectory is None
    assert f"problem {pid!r} raised InvalidInputError: dt: the motion lasts at least" in result.message
    assert "MAX_SAMPLES" in result.message
    assert "raised an exception" in result.status.hint


def test_the_single_call_raises(problems):
    p = next(p for p in problems if p.id == BAD)
    with pytest.raises(InvalidInputError, match="dt: the motion lasts at least"):
        MotionGenerator("franka", p.world).plan_joints(p.start, p.goal, **p.options)


def test_a_raising_problem_is_a_failed_result_and_every_other_result_is_returned(problems, reference):
    results = plan_many(problems, workers=2, seed=SEED, progress=False)
    assert len(results) == len(problems)
    for p, r in zip(problems, results):
        if p.id == BAD:
            assert_raised(r, BAD)
        else:
            assert_same(r, reference[p.id])
    assert sum(r.success for r in results) >= 7
    assert not mp.active_children()


def test_the_stream_goes_on_after_a_raising_problem(problems, reference):
    # the bad problem first, on a single worker: every later problem is planned by the same
    # process after it raised, and gives the single call's result
    order = sorted(problems, key=lambda p: p.id != BAD)
    seen = Counter()
    for pid, result in plan_stream(order, workers=1, seed=SEED):
        seen[pid] += 1
        if pid == BAD:
            assert_raised(result, BAD)
        else:
            assert_same(result, reference[pid])
    assert sorted(seen) == sorted(p.id for p in problems) and set(seen.values()) == {1}


def test_several_raising_problems_each_fail_alone(problems, reference):
    batch = [Problem(p.world, p.start, p.goal, id=p.id, options=RAISING if i % 3 == 0 else OPTIONS)
             for i, p in enumerate(problems)]
    results = plan_many(batch, workers=2, seed=SEED, progress=False)
    for i, (p, r) in enumerate(zip(batch, results)):
        if i % 3 == 0:
            assert_raised(r, p.id)
        else:
            assert_same(r, reference[p.id])


def test_bad_input_found_before_the_workers_start_still_raises(problems):
    batch = [Problem(p.world, p.start, p.goal, id=p.id, options=OPTIONS) for p in problems[:2]]
    batch.append(Problem(problems[2].world, problems[2].start, problems[2].goal, id="zero dt", options={"dt": 0.0}))
    with pytest.raises(InvalidInputError) as info:
        plan_many(batch, workers=2, progress=False)
    assert "'zero dt'" in str(info.value) and "dt" in str(info.value)
    assert not mp.active_children()


# ------------------------------------------------------------------ Ray (the ray extra)
def test_ray_a_raising_problem_is_a_failed_result_and_the_batch_goes_on(ray_cluster, problems, reference):
    seen = Counter()
    for pid, result in plan_stream(problems, backend="ray", seed=SEED):
        seen[pid] += 1
        if pid == BAD:
            assert_raised(result, BAD)
        else:
            assert_same(result, reference[pid])
    assert sorted(seen) == sorted(p.id for p in problems) and set(seen.values()) == {1}
    # the actors that planned it are kept warm and plan the next batch
    from manip.batch import ray_backend

    assert len(ray_backend.kept_actors()) == 2
    results = plan_many(problems, backend="ray", seed=SEED, progress=False)
    assert_raised(results[[p.id for p in problems].index(BAD)], BAD)
