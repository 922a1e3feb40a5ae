"""The code that runs in a worker process: warm motion generators, one per robot.

A worker builds one `MotionGenerator` per robot the first time it meets that robot and
keeps it for its whole life (the compiled kernels, sphere covers and IK tables are loaded
once). Consecutive problems with the same world (same `Task.world_key`) reuse the loaded
world; another world costs an `update_world` (milliseconds), not a new generator.

`warm_up` plans one small problem and solves one IK problem so that the compiled kernels are
loaded (or compiled) before real problems arrive: a kernel compiled during a problem would
eat its time budget. `single_threaded` limits a worker's native thread pools (numpy's
OpenBLAS, scipy's) to one thread: a worker is one CPU, and two workers whose BLAS threads each
reach for the other core slow each other down. Both backends `start` a worker with both.
"""

from __future__ import annotations

import logging
import os
import time

import numpy as np
from threadpoolctl import threadpool_limits

from manip.batch.problem import ProblemId, RobotSpec, Task
from manip.motion_generator import MotionGenerator
from manip.planning.result import PlanResult, PlanStatus
from manip.pose import Pose

log = logging.getLogger(__name__)

# Per-process state of a worker: robot name -> (generator, key of its loaded world).
_GENERATORS: dict[str, tuple[MotionGenerator, str | None]] = {}
# Robots (keys) whose generator this process has warmed up: a process forked from a warm one
# inherits them (and the loaded kernels) and skips their warm-up.
_WARM: set[str] = set()

#: Budget of the warm-up plans [s] (long: they include compiling or loading kernels).
WARM_UP_BUDGET = 120.0


def generator(robot: str | RobotSpec) -> MotionGenerator:
    """This process's warm MotionGenerator of `robot` (built on first use)."""
    key = str(robot)
    if key not in _GENERATORS:
        _GENERATORS[key] = (MotionGenerator(robot.config if isinstance(robot, RobotSpec) else robot), None)
    return _GENERATORS[key][0]


def single_threaded() -> None:
    """Limit this process's native thread pools (BLAS, OpenMP) to one thread each, for the
    rest of its life. `benchmarks/batch.py`, 200 problems on 2 cores: 2 workers 1.49-1.57 x one
    end to end with numpy's default of a BLAS thread per core (worker CPU per problem 1.11-1.18 x
    that of a lone worker), 1.67-1.76 x with one thread (0.98-1.02 x)."""
    threadpool_limits(limits=1)


def start(robots: tuple[str | RobotSpec, ...]) -> None:
    """A new worker's start (both backends): `warm_up`, then `single_threaded` (after it: it
    limits the libraries loaded so far, and the warm-up loads them)."""
    warm_up(robots)
    single_threaded()


def warm_up(robots: tuple[str | RobotSpec, ...]) -> dict[str, float]:
    """Build the generators of `robots` and load every compiled kernel: one plan, one IK call.

    A joint plan from the default configuration to a moved one around a box placed between
    the two hand positions (collision checking, path search, shortcutting, timing, the
    optimiser) and an IK call for a pose near the moved hand load every numba kernel that
    planning can meet (compiling those missing from the on-disk cache), so that no kernel
    is loaded or compiled inside a problem's time budget; `tests/batch/test_batch.py` checks that
    planning every scene kind afterwards, to joint and pose goals, loads no other. More
    warm-up plans would only add their own planning time to the worker's start-up. The
    results are discarded and the world is emptied afterwards.

    A robot this process (or the process it was forked from) has warmed up already is skipped.

    Args:
        robots: robot names, robot.yaml paths or `RobotSpec`s.

    Returns:
        Seconds spent per stage, summed over the robots: "build" (the generators), "joint
        plan", "ik" (both including the kernels they loaded or compiled) and "total".
    """
    times = {"build": 0.0, "joint plan": 0.0, "ik": 0.0}
    t_start = time.perf_counter()
    for robot in robots:
        if str(robot) in _WARM:
            continue
        t = time.perf_counter()
        mg = generator(robot)
        times["build"] += time.perf_counter() - t
        q0 = mg.default_joint_positions
        lo, hi = mg.lower_limits, mg.upper_limits
        q1 = np.clip(q0 + 0.5 * (hi - lo) * np.where(np.arange(len(q0)) % 2 == 0, 0.3, -0.2), lo, hi)
        p0, goal = mg.fk(q0).position, mg.fk(q1)
        mid = 0.5 * (p0 + goal.position)
        world = {"cuboid": {"warm_up": {"dims": [0.08, 0.08, 0.08], "pose": [*mid.tolist(), 1.0, 0.0, 0.0, 0.0]}}}
        mg.update_world(world)
        t = time.perf_counter()
        mg.plan_joints(q0, q1, seed=0, time_budget=WARM_UP_BUDGET)
        times["joint plan"] += time.perf_counter() - t
        t = time.perf_counter()
        # as a pose goal's IK (several solutions, moved along the self-motion towards the start)
        mg.ik_solver.solve_many(Pose(goal.position + 0.02, goal.quaternion), n=2, seed_q=q0, toward_seed=True)
        times["ik"] += time.perf_counter() - t
        mg.update_world({})
        _GENERATORS[str(robot)] = (mg, None)
        _WARM.add(str(robot))
    times["total"] = time.perf_counter() - t_start
    log.info("worker %d warm in %.2f s (%s): %s", os.getpid(), times["total"], ", ".join(map(str, robots)),
             ", ".join(f"{k} {v:.2f} s" for k, v in times.items() if k != "total"))
    return times


def solve(task: Task) -> tuple[ProblemId, PlanResult]:
    """Plan one task on this process's warm generator (warmed up first if it is new).

    A task whose planning raises (an option valid on its own that fails once planned, such
    as a `dt` giving more than `manip.validation.MAX_SAMPLES` samples, or a bug) gives a
    failed result, `raised_result`, instead of losing the rest of the batch; the generator
    reloads the world for the next task.

    Args:
        task: a validated problem.

    Returns:
        (the task's id, the PlanResult of the single planning call).
    """
    key = str(task.robot)
    t0 = time.perf_counter()
    try:
        if key not in _GENERATORS:
            warm_up((task.robot,))
        mg = _GENERATORS[key][0]
        if _GENERATORS[key][1] != task.world_key:
            _GENERATORS[key] = (mg, None)  # until loaded whole (an edit that raises leaves it half-loaded)
            mg.update_world(task.world)
            _GENERATORS[key] = (mg, task.world_key)
        if isinstance(task.goal, Pose):
            result = mg.plan_pose(task.start, task.goal, **task.options)
        else:
            result = mg.plan_joints(task.start, task.goal, **task.options)
    except Exception as exc:  # one problem never costs the batch: it becomes a failed result
        log.warning("problem %r raised %s", task.id, type(exc).__name__, exc_info=True)
        if key in _GENERATORS:
            _GENERATORS[key] = (_GENERATORS[key][0], None)  # its world may be half-edited: reload it
        return task.id, raised_result(task.id, exc, time.perf_counter() - t0)
    return task.id, result


def raised_result(problem_id: ProblemId, exc: BaseException, seconds: float = float("nan")) -> PlanResult:
    """The failed result of a problem whose planning raised `exc`: status RAISED, the message
    "problem <id> raised <type>: <text>", `timings["total"]` = `seconds` [s]."""
    return PlanResult(success=False, status=PlanStatus.RAISED, timings={"total": float(seconds)},
                      message=f"problem {problem_id!r} raised {type(exc).__name__}: {exc}")
