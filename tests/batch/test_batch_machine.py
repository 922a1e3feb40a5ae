"""manip.batch: a batch plans the same on a slow machine (its search is bounded by a count, the
clock is only a safety net), and a result the clock did cut short says so.

The "slow machine" is a worker whose clock reads SLOWDOWN times its own CPU time: a plan sees
the seconds of a machine SLOWDOWN times slower, whatever else this machine runs meanwhile (a
wall clock would also count the time the worker waits for a CPU, and the verdict would depend
on the load)."""

from __future__ import annotations

import time

import numpy as np
import pytest

from manip import MotionGenerator
from manip.batch import BATCH_OPTIONS, Problem, plan_many, worker
from manip.batch.plan import run_tasks
from manip.batch.problem import prepare
from manip.benchmarking.scenes import make_problems
from manip.planning.context import SAFETY_NET
from manip.planning.result import PlanStatus

SEED = 0
#: The clock of a "slow machine" worker reads SLOWDOWN times its CPU seconds: the batch's 60 s
#: safety net is 4 s of CPU per plan (cage/28, the longest, takes about 1 s here).
SLOWDOWN = 15.0
#: The clock as the only bound: no count budget for the search, a 2 s time budget, which the
#: slowed clock reaches after 0.13 s of CPU (cage/28's search needs about 1 s).
CLOCK_ONLY = {"search_iterations": None, "time_budget": 2.0}


def _on_a_slow_machine(task):
    """`worker.solve` in a worker whose `time.perf_counter` reads SLOWDOWN x its CPU time."""
    if not getattr(time.perf_counter, "slowed", False):
        origin = time.perf_counter()
        cpu = time.process_time
        cpu0 = cpu()

        def slow() -> float:
            return origin + SLOWDOWN * (cpu() - cpu0)

        slow.slowed = True
        time.perf_counter = slow
    return worker.solve(task)


@pytest.fixture(scope="module")
def batch() -> list[Problem]:
    """Cage problem 28 (its search needs about 2,000 RRT iterations with batch seed 0), shelf
    problem 3 (about 300) and two table problems, with the batch's default options."""
    cage = make_problems("cage", 29, 0)[28]
    shelves = make_problems("shelf", 4, 0)
    tables = make_problems("table", 2, 0)
    return [Problem(p.world, p.start, p.goal, id=f"{p.scene}/{p.index}") for p in (cage, shelves[3], *tables)]


def noted(result) -> bool:
    """Whether the result says the clock may have cut it short."""
    return result.status is PlanStatus.TIMEOUT or SAFETY_NET in result.message


def same(a, b) -> bool:
    """Same status, message and bit-identical trajectory."""
    if a.status is not b.status or a.message != b.message or (a.trajectory is None) != (b.trajectory is None):
        return False
    return a.trajectory is None or (np.array_equal(a.trajectory.positions, b.trajectory.positions)
                                    and np.array_equal(a.trajectory.velocities, b.trajectory.velocities))


def test_a_batch_plans_the_same_on_a_slow_machine(batch):
    assert all(t.options["search_iterations"] == BATCH_OPTIONS["search_iterations"] for t in prepare(batch, SEED))
    normal = dict(zip([p.id for p in batch], plan_many(batch, workers=2, seed=SEED, progress=False)))
    slow = dict(run_tasks(prepare(batch, SEED), workers=2, backend="process", job=_on_a_slow_machine))
    assert sorted(slow) == sorted(normal)
    assert all(r.success and not noted(r) for r in normal.values()), {k: r.message for k, r in normal.items()}
    for pid, r in slow.items():
        assert not noted(r), (pid, r.status, r.message)
        assert same(r, normal[pid]), pid


def test_without_a_count_the_slow_machine_changes_results_and_says_so(batch):
    """The control: with the clock as the only bound the slowed worker's plans are cut short (so
    the test above could fail), and every result that differs carries the note (the plans on
    the real clock may be cut short too on a loaded machine: then they carry it)."""
    clock_only = [Problem(p.world, p.start, p.goal, options=CLOCK_ONLY, id=p.id) for p in batch]
    normal = dict(zip([p.id for p in batch], plan_many(clock_only, workers=2, seed=SEED, progress=False)))
    slow = dict(run_tasks(prepare(clock_only, SEED), workers=2, backend="process", job=_on_a_slow_machine))
    assert slow["seeded_cage/28"].status is PlanStatus.TIMEOUT
    for pid, r in slow.items():
        assert same(r, normal[pid]) or noted(r) or noted(normal[pid]), pid


def test_a_plan_past_its_time_budget_says_so():
    # a free straight line: no stage looks at the clock, so the late plan is the same motion,
    # but only a plan that ended within its budget is vouched for
    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    goal = np.clip(q0 + 0.3, mg.lower_limits, mg.upper_limits)
    on_time = mg.plan_joints(q0, goal, time_budget=30.0)
    late = mg.plan_joints(q0, goal, time_budget=1e-9)
    assert on_time.success and on_time.source == "straight_line" and on_time.message == ""
    assert late.success and late.message == SAFETY_NET
    np.testing.assert_array_equal(late.trajectory.positions, on_time.trajectory.positions)
