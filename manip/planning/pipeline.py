"""The attempts of one plan from a checked start to goal configurations.

Each attempt: a path (the straight line when valid, else the RRT-Connect search towards the
goals, shortcutting, detour restarts, optional clearance smoothing), its ruckig timing
stopping at each waypoint (`planning.time_and_validate`), the trajectory optimiser seeded by it
(`planning.trajopt.refine`), whose result is returned when it is faster and passes the certified
validation; otherwise the path's ruckig timings (corners blended, then stopping at each
waypoint), the first that passes the same validation. A path whose timed trajectory
fails the validation (a graze between the configurations the search checked) is planned
again, until MAX_ATTEMPTS or the time budget runs out. Stage times go
to `PlanContext.timings`. `MotionGenerator` checks the start and the goals and calls
`plan_to_configs`.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from manip.collision.clearance import ClearanceModel
from manip.limits import JointLimits
from manip.planning.constrained import ConstrainedClearance
from manip.planning.context import SAFETY_NET, PlanContext
from manip.planning.trajopt.settings import TrajOptSettings
from manip.planning.time_and_validate import BLEND_DEVIATION, time_and_validate, time_once
from manip.planning.path.smoothing import smooth_path
from manip.planning.trajopt.refine import refine
from manip.planning.path.restarts import shorter_way_round
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.path.search import repair_path, search_path
from manip.planning.path.shortcut import shortcut
from manip.planning.validity import Validity
from manip.trajectory import Trajectory

logger = logging.getLogger(__name__)

#: Goal sets: the search first tries this many goals (the best of `planning.path.goals`' ranking)
#: alone, for at most FOCUS_ITERATIONS RRT iterations, before searching towards all of them.
FOCUS_GOALS = 2
FOCUS_ITERATIONS = 200
#: Plans tried when a path's timed trajectory fails the validation (its certificate).
MAX_ATTEMPTS = 4
#: From this attempt on, every straight motion the planner accepts is certified
#: (`Validity.strict`: about 10 x slower searches and shortcuts; attempt 2 alone usually
#: succeeds with a new search).
STRICT_ATTEMPT = 3
#: Strict attempts first plan without certification and then certify only the path's
#: segments, searching the failing ones again with certified motions (at most this many RRT
#: iterations together, a count); a path that cannot be repaired so is planned again with
#: every motion certified, without the detour restarts (BENCHMARKS.md, "Constants").
STRICT_REPAIR_ITERATIONS = 500
#: A constrained plan that found no path searches this many RRT iterations without the
#: constraints, to say whether they made it infeasible: until the plan's own deadline, or for
#: UNCONSTRAINED_CHECK_TIME [s] when the plan ran out of budget (TIMEOUT, SAFETY_NET). Never a clock
#: of its own within the budget: a plan failed by its counts gets the same answer on a loaded machine.
UNCONSTRAINED_CHECK_ITERATIONS = 2000
UNCONSTRAINED_CHECK_TIME = 1.0


def plan_to_configs(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: np.ndarray, *,
                    limits: JointLimits, clearance: ClearanceModel) -> PlanResult:
    """Path, shortcutting, timing and validation to the best reachable of `goals` (G, dof).

    A path whose timed trajectory fails the validation (a graze between the
    configurations the search checked) is planned again, until the budget runs out; the
    third attempt on accepts only straight motions certified over their whole length
    (`Validity.strict`: slower, but a graze thinner than the check resolution, e.g. a
    finger passing an object a fraction of a millimetre deep, cannot come back). A strict
    attempt plans as the others do, then certifies the path's segments and searches the
    failing ones again with certified motions (`STRICT_REPAIR_ITERATIONS`); only when that
    fails does it search with every motion certified.
    """
    result = None
    for attempt in range(1, MAX_ATTEMPTS + 1):
        strict = attempt >= STRICT_ATTEMPT
        result = _plan_once(ctx, validity.strict() if strict else validity, start, goals, attempt, limits=limits,
                            clearance=clearance)
        if result.success or result.status is not PlanStatus.TRAJOPT_FAIL or ctx.time_left < 0:
            break
        logger.info("attempt %d: %s; planning again", attempt, result.message)
    if validity.constraints and result.status in (PlanStatus.PLAN_FAIL, PlanStatus.TIMEOUT):
        result = _constraint_failure(ctx, validity, start, goals, result)
    return result


def _constraint_failure(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: np.ndarray,
                        result: PlanResult) -> PlanResult:
    """CONSTRAINT_INFEASIBLE when a short unconstrained search (UNCONSTRAINED_CHECK_ITERATIONS)
    finds a path where the constrained plan found none; else the constrained plan's failure."""
    free = validity.unconstrained()
    t = time.perf_counter()
    path = next((np.stack([start, g]) for g in goals[:3] if free.motion(start, g)), None)
    if path is None:
        # stopped by the clock only past the plan's deadline (then the result says SAFETY_NET)
        deadline = max(ctx.deadline, time.perf_counter() + UNCONSTRAINED_CHECK_TIME)
        path, _ = search_path(start, goals, free, np.random.default_rng(ctx.options.seed), deadline,
                              max_iterations=UNCONSTRAINED_CHECK_ITERATIONS,
                              max_repair_iterations=UNCONSTRAINED_CHECK_ITERATIONS)
    ctx.add_time("plan", t)
    if path is None:
        if ctx.time_left < 0 and SAFETY_NET not in result.message:   # the check ran past the budget
            return ctx.fail(result.status, result.message, path=result.path, goal_q=result.goal_q,
                            attempts=result.attempts)
        return result
    names = ", ".join(type(c).__name__ for c in validity.constraints)
    return ctx.fail(PlanStatus.CONSTRAINT_INFEASIBLE,
                    f"no path keeping the constraints ({names}) was found ({result.message}), while a collision-free "
                    f"path without them exists", attempts=result.attempts)


def _plan_once(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: np.ndarray, attempt: int, *,
               limits: JointLimits, clearance: ClearanceModel) -> PlanResult:
    """One attempt: a path, its timing and validation, then the optimiser."""
    path, source = None, "shortcut"
    if validity.certified:
        # a path planned without certification, then only its segments certified (and
        # the failing ones searched again with certified motions): most segments pass,
        # and certifying every motion the search and shortcutting try costs ~10 x more
        path, source, why = _path(ctx, validity.loose(), start, goals, attempt, limits)
        if path is not None:
            t = time.perf_counter()
            path, _ = repair_path(path, validity, ctx.rng, ctx.deadline, max_iterations=STRICT_REPAIR_ITERATIONS)
            ctx.add_time("plan", t)
        if path is None:
            logger.info("attempt %d: no path with certified segments; a certified search", attempt)
    if path is None:
        path, source, why = _path(ctx, validity, start, goals, attempt, limits)
    if path is None:
        status = PlanStatus.TIMEOUT if ctx.time_left < 0 else PlanStatus.PLAN_FAIL
        return ctx.fail(status, why, attempts=attempt)
    goal_q = path[-1].copy()
    timed: dict[str, Trajectory] = {}
    better = None
    if ctx.options.trajopt and source == "shortcut":
        # the optimiser's seed: the path timed stopping at each waypoint (its spline fit
        # follows the path's corners more closely than the blended timing's, which cuts them);
        # the timings are validated only when the optimiser gives nothing faster
        traj, _ = time_once(ctx, path, limits=limits, validity=validity, mode="exact", deviation=BLEND_DEVIATION)
        if traj is not None:
            timed["exact"] = traj
            better = _refine(ctx, traj, limits, validity, clearance)
        if better is not None:
            return ctx.succeed(better, path, goal_q, attempt, "trajopt")
    traj, why = time_and_validate(ctx, path, goal_q, limits=limits, validity=validity, timed=timed)
    if traj is None:
        return ctx.fail(PlanStatus.TRAJOPT_FAIL, f"no valid timed trajectory: {why}", path=path, goal_q=goal_q,
                        attempts=attempt)
    return ctx.succeed(traj, path, goal_q, attempt, source)


def _refine(ctx: PlanContext, seed: Trajectory, limits: JointLimits, validity: Validity,
            clearance: ClearanceModel) -> Trajectory | None:
    """`refine.refine` with the clearance model bound to the validity's checker."""
    checker = validity.checker
    bound = clearance.bound_to(checker)
    if validity.constraints:  # the constraint rows as clearance terms (`planning.constrained`)
        bound = ConstrainedClearance(bound, validity.constraints, validity.kinematics,
                                     checker.padding + TrajOptSettings().margin)
    return refine(ctx, seed, limits=limits, validity=validity, clearance=bound, padding=checker.padding)


def _path(ctx: PlanContext, validity: Validity, start: np.ndarray, goals: np.ndarray, attempt: int,
          limits: JointLimits) -> tuple[np.ndarray | None, str, str]:
    """(path (K, dof) to one of `goals` (G, dof) or None, its source, why there is none):
    the straight line, else a search, shortcutting, restarts and clearance smoothing."""
    t = time.perf_counter()
    path, source, iterations = None, "shortcut", 0
    if attempt == 1:
        for g in goals[:3]:
            if validity.motion(start, g):
                path, source = np.stack([start, g]), "straight_line"
                break
    if path is None and len(goals) > FOCUS_GOALS:
        # the best-ranked goals first (`planning.path.goals.order_goals`): a short search towards
        # them alone, then towards every goal
        path, iterations = search_path(start, goals[:FOCUS_GOALS], validity, ctx.rng, ctx.deadline,
                                       max_iterations=FOCUS_ITERATIONS)
    if path is None:
        budget = ctx.options.search_iterations  # a count (None: the search's own cap)
        path, more = search_path(start, goals, validity, ctx.rng, ctx.deadline, max_iterations=budget,
                                 max_repair_iterations=budget)
        iterations += more
    ctx.add_time("plan", t)
    if path is None:
        return None, source, f"no collision-free path found ({iterations} iterations)"
    t = time.perf_counter()
    if len(path) > 2:
        def shorten(p: np.ndarray) -> np.ndarray:
            return shortcut(p, validity.segments, ctx.rng, ctx.deadline, screen=validity.screen,
                            screened=validity.screened)

        path = shorten(path)
        ctx.add_time("optimize", t)
        # certified, further searches cost ~10 x more for a rare gain; constrained, the path is
        # longer than the (forbidden) straight line by nature, and the searches cost as much
        if not validity.certified and not validity.constraints:
            t = time.perf_counter()
            path = shorter_way_round(path, goals, validity, shorten, rng=ctx.rng, deadline=ctx.deadline,
                                     velocity=ctx.scaled_limits(limits).velocity)
            ctx.add_time("restarts", t)
        t = time.perf_counter()
        if ctx.options.optimize_clearance:
            path = smooth_path(path, validity.checker, validity.motion, ctx.deadline)
    ctx.add_time("optimize", t)
    return path, source, ""
