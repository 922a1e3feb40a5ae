"""Trajectory optimisation: fast, short, smooth motions from a collision-free seed.

The motion is a uniform cubic B-spline at rest at both ends (`planning.trajopt.bspline`), whose
velocity, acceleration, jerk and position limits are linear constraints on its control
points that hold for the continuous motion. Sequential convex optimisation with a trust
region (`planning.trajopt.sco`; each iteration one QP, PIQP's sparse interface or any `qpsolvers`
solver) improves it, with the clearance of the robot's sphere cover above `margin`
(linearised at samples of the current motion, `collision.clearance`) as an L1 penalty
(TrajOpt's formulation: every QP is feasible); at an end whose configuration is near an
obstacle (where the sphere cover is too coarse), the first/last piece stays on the seed's
first/last straight segment.

The spline fitted to the seed exceeds the limits at the seed's duration (it follows a
ruckig-timed polyline), so a few iterations at that duration first bring it within the
limits and clear of obstacles. Then, by default (`free_duration`), one SCO over the control
points and the knot step together minimises the duration itself (the limits hard and
linearised in the step). The alternative (`free_duration=False`, used by
`smoothness="smooth"`, whose jerk objective needs a fixed duration to mean anything) is
cuRobo's outer loop: SCO rounds at fixed durations, each result uniformly re-timed until a
limit is active, the next target 30 % of the way from the longest target not reached (at
first the straight line's lower bound) to the best so far. The result is certified by the
caller against the exact meshes; on any failure the caller keeps the seed trajectory.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from manip.collision.clearance import ClearanceModel
from manip.errors import InvalidInputError
from manip.limits import JointLimits
from manip.planning.trajopt import bspline
from manip.planning.trajopt.sco import SplineProblem, sco_fixed_step, sco_free_step
from manip.planning.trajopt.settings import SMOOTH, TrajOptSettings
from manip.trajectory import PiecewiseJerkProfile
from manip.validation import non_negative

__all__ = ["SMOOTH", "TrajOptResult", "TrajOptSettings", "optimize_trajectory"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class TrajOptResult:
    """Outcome of `optimize_trajectory`.

    Attributes:
        success: True when `profile` is within the limits and its sampled sphere clearance
            satisfied the constraints (the exact certificate is the caller's).
        profile: the motion (None on failure).
        control: (N + 3, dof) its control points [rad].
        duration: its duration [s].
        solves: QPs solved.
        message: why it failed ("" on success).
        ends_tied: ends (0, 1 or 2) whose first / last pieces were kept on the seed's
            straight segments (`TrajOptSettings.ray_points`; ends near an obstacle).
    """

    success: bool
    profile: PiecewiseJerkProfile | None
    control: np.ndarray | None
    duration: float
    solves: int
    message: str = ""
    ends_tied: int = 0


def optimize_trajectory(
    seed_positions: np.ndarray,
    seed_times: np.ndarray,
    *,
    limits: JointLimits,
    clearance: ClearanceModel,
    padding: float,
    deadline: float,
    settings: TrajOptSettings = TrajOptSettings(),
    min_duration: float = 0.0,
    max_duration: float = np.inf,
    max_solves: int | float = np.inf,
    end_rays: bool = True,
) -> TrajOptResult:
    """Optimise a rest-to-rest motion seeded by a sampled one (e.g. a timed collision-free path).

    Args:
        seed_positions: (T, dof) samples of a limit-respecting motion, collision-free or
            nearly so (its sampled sphere clearance is the floor the result keeps) [rad].
        seed_times: (T,) their times [s] (the last is the seed's duration).
        limits: the velocity, acceleration and jerk limits (already scaled) and the
            position limits (required) of the dof joints.
        clearance: the sphere-cover clearance model of the robot and world.
        padding: clearance the planner keeps [m] (added to `settings.margin`).
        deadline: `time.perf_counter()` value to stop at (the best result so far is kept).
        settings: see TrajOptSettings.
        min_duration: a lower bound of the duration [s] (e.g. the straight line's): the
            free-duration SCO's floor, and the bisection's first target not reached (see
            `TrajOptSettings.duration_tolerance`).
        max_duration: the duration to beat [s] (e.g. the seed's): the bisection stops before
            a target this long (it could only give slower motions); the free-duration SCO
            does not use it (the caller compares).
        max_solves: QPs at most (a count, so the result does not depend on the machine).
        end_rays: keep the motion's first and last two pieces on the seed's first and last
            straight segments (the seed must be a polyline's timing; the pieces near a goal
            that almost touches an obstacle are then exactly as free as the seed's).
    """
    seed_positions, seed_times = _check_seed(seed_positions, seed_times)
    if not (max_solves >= 1):
        raise InvalidInputError(f"max_solves must be >= 1; got {max_solves!r}")
    if not (np.isfinite(min_duration) and min_duration >= 0.0 and max_duration > 0.0):
        raise InvalidInputError(f"min_duration must be finite and >= 0 and max_duration > 0 [s]; got {min_duration!r}, "
                                f"{max_duration!r}")
    dof = seed_positions.shape[1]
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(f"limits must be a manip.JointLimits; got {type(limits).__name__}")
    if limits.dof != dof or limits.lower is None:
        raise InvalidInputError(f"limits must be for the seed's {dof} joints, with position limits; got {limits.dof} "
                                f"joints{'' if limits.lower is not None else ', no position limits'}")
    lower, upper = limits.lower, limits.upper
    non_negative(padding, "padding", "m")
    start, goal = seed_positions[0], seed_positions[-1]
    n = settings.intervals
    prob = SplineProblem(n, dof, settings, start, goal)
    c = bspline.control_from_samples(seed_positions, np.asarray(seed_times, float), float(seed_times[-1]), n)
    c[3:n] = np.clip(c[3:n], lower, upper)
    if end_rays and n >= 8:
        # an end near an obstacle keeps the seed's approach (the sphere cover is too coarse there)
        near = clearance.terms(np.stack([start, goal]), padding + settings.margin + settings.activation).config
        d_start, d_goal = _end_directions(seed_positions)
        prob.set_rays(d_start if 0 in near else None, d_goal if 1 in near else None, settings.ray_points)
        c = prob.project_rays(c)
    margin = padding + settings.margin
    clearance = _RememberedTerms(clearance)  # the free-duration SCO starts where the first iterations ended
    if settings.free_duration:
        return _free_duration(prob, c, float(seed_times[-1]) / n, limits=limits, clearance=clearance, margin=margin,
                              settings=settings, deadline=deadline, h_floor=max(min_duration, 0.0) / n,
                              max_solves=max_solves)
    h = float(seed_times[-1]) / n
    h_floor = max(min_duration, 0.0) / n  # no motion is faster than the lower bound
    h_max = max_duration / n
    h_low = h_floor
    fit = c
    second_chance = settings.second_chance
    best: tuple[np.ndarray, float] | None = None
    solves = 0
    message = ""
    radius = settings.trust_region
    for _ in range(settings.rounds):
        if time.perf_counter() > deadline or solves >= max_solves:
            break
        ok, c_new, used, why, radius = sco_fixed_step(prob, c, h, radius, limits=limits, clearance=clearance,
                                                      margin=margin, settings=settings, deadline=deadline,
                                                      max_solves=max_solves - solves)
        # the next round starts from twice the last step size (a step rejected there would
        # be rejected at the same shape again)
        radius = min(settings.trust_region, 2.0 * radius)
        solves += used
        # the optimised shape, uniformly re-timed until a limit is active (limits are soft in the QP)
        h_star = bspline.limit_step(c_new, limits) if ok else np.inf
        logger.debug("trajopt: target T = %.3f s: %s, feasible T = %.3f s (%d QPs) %s", n * h,
                     "ok" if ok else "failed", n * h_star, used, why)
        if ok and (best is None or h_star < best[1]):
            best = (c_new, h_star)
        if second_chance and (best is None or best[1] >= h_max):
            # nothing usable at the seed's duration (the spline fitted to the seed exceeds the
            # limits there, and repairing both limits and clearance failed): once more from
            # the fit, at the duration where it is within the limits
            second_chance = False
            c, h, h_low, radius = fit, max(h, bspline.limit_step(fit, limits)), h_floor, settings.trust_region
            continue
        if best is None:
            message = why
            break
        if not ok or h_star > h * 1.02:
            h_low = max(h_low, h)  # this target was not reached
        if ok:
            c = c_new  # the next round goes on from this shape (straighter, even if not faster yet)
        h_best = best[1]
        if h_best - h_low <= settings.duration_tolerance * h_best:
            break
        # between the unreached target and the best (a target at or above max_duration
        # could only give slower motions than the one to beat)
        h = h_low + settings.bisection * (min(h_best, h_max) - h_low)
        if h >= h_max:
            break
    if best is None:
        return TrajOptResult(False, None, None, float("nan"), solves, message or "no time left", prob.ends_tied)
    c, h = best
    return TrajOptResult(True, bspline.to_profile(c, h), c, n * h, solves, "", prob.ends_tied)


def _free_duration(prob: SplineProblem, c: np.ndarray, h_seed: float, *, limits: JointLimits,
                   clearance: ClearanceModel, margin: float, settings: TrajOptSettings, deadline: float,
                   h_floor: float, max_solves: int | float) -> TrajOptResult:
    """`s.first_iterations` at the seed's step h_seed [s] (kept when they end above the
    clearance floor), then the free-duration SCO from there."""
    s = settings
    solves = 0
    if s.first_iterations:
        ok, first, solves, why, _ = sco_fixed_step(prob, c, h_seed, s.trust_region, limits=limits,
                                                   clearance=clearance, margin=margin, settings=s,
                                                   deadline=deadline, max_solves=max_solves,
                                                   iterations=s.first_iterations)
        logger.debug("trajopt: at the seed's T = %.3f s: %s (%d QPs) %s", prob.n * h_seed, "ok" if ok else "failed",
                     solves, why)
        c = first if ok else c
    if solves < max_solves:
        c, used = sco_free_step(prob, c, limits=limits, clearance=clearance, margin=margin, settings=s,
                                deadline=deadline, h_floor=h_floor, max_solves=max_solves - solves)
        solves += used
    h = bspline.limit_step(c, limits)
    logger.debug("trajopt: free duration T = %.3f s (%d QPs)", prob.n * h, solves)
    return TrajOptResult(True, bspline.to_profile(c, h), c, prob.n * h, solves, "", prob.ends_tied)


class _RememberedTerms:
    """A clearance model's `terms`, each result kept for the rest of one optimisation (the world
    does not change meanwhile): the same samples are not evaluated twice."""

    def __init__(self, clearance: ClearanceModel):
        self._clearance = clearance
        self._seen: dict = {}

    def terms(self, Q: np.ndarray, activation: float):
        Q = np.ascontiguousarray(Q, dtype=float)
        key = (Q.shape, float(activation), Q.tobytes())
        found = self._seen.get(key)
        if found is None:
            if len(self._seen) >= 64:  # a bound on the memory (an optimisation makes ~10-40 calls)
                self._seen.clear()
            found = self._seen[key] = self._clearance.terms(Q, activation)
        return found


def _check_seed(positions, times) -> tuple[np.ndarray, np.ndarray]:
    """The seed as float arrays (T, dof), (T,); raises InvalidInputError on bad shapes or values."""
    q = np.asarray(positions, dtype=float)
    t = np.asarray(times, dtype=float)
    if q.ndim != 2 or q.shape[0] < 2:
        raise InvalidInputError(f"seed_positions must have shape (T, dof) with T >= 2; got {q.shape}")
    if t.shape != (q.shape[0],):
        raise InvalidInputError(f"seed_times must have shape ({q.shape[0]},) like seed_positions' rows; got {t.shape}")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(t))):
        raise InvalidInputError("seed_positions and seed_times must be finite")
    if t[0] != 0.0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError("seed_times must start at 0 and increase strictly [s]")
    return q, t


def _end_directions(seed_positions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions [rad] of the seed's first and last straight stretches: from the start to the
    first sample where the motion turns, and from the goal back to the last such sample."""
    q = seed_positions

    def last_on_line(q0: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """From q0 to the farthest of `rows` (in order) still on the line through the first that
        moves (rows that do not move are passed over)."""
        if not len(rows):
            return np.zeros_like(q0)
        V = rows - q0
        moving = np.flatnonzero(np.linalg.norm(V, axis=1) >= 1e-12)
        if moving.size == 0:
            return rows[-1] - q0
        first, rest = moving[0], moving[1:]
        direction = V[first] / np.linalg.norm(V[first])
        W = V[rest]
        off = np.linalg.norm(W - (W @ direction)[:, None] * direction, axis=1) > 1e-6
        if off.any():  # the motion turns at rest[k]: the last moving row before it
            k = int(np.argmax(off))
            last = rest[k - 1] if k > 0 else first
        else:
            last = rest[-1] if rest.size else first
        return rows[last] - q0  # a new array (a row of V is a view: its alignment can change dot products' last bit)

    return last_on_line(q[0], q[1:]), last_on_line(q[-1], q[-2::-1])
