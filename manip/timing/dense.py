"""Dense-path timing (mode "along_path"): one time scaling along a spline through the points.

For DENSE paths sampled from a smooth curve (incremental IK along a Cartesian line, an
optimiser's output), where waypoint timing slows down at nearly every point. A C2
not-a-knot cubic spline `q(s)` through all the points (s = chord length [rad]) is
traversed by ONE rest-to-rest ruckig profile `s(t)`, whose limits are chosen so the chain
rule keeps every joint within its limits; the motion flows along the whole path. Paths
with sharp corners make it slow everywhere (its speed is set by the worst stretch): use
it for smooth dense paths, with "blend" as the fallback.
"""

from __future__ import annotations

import logging
import time
from typing import Sequence

import numpy as np
import ruckig

from manip.timing.checks import check_deviation_tolerance, check_inputs
from manip.timing.result import TimingResult, TimingStatus
from manip.timing.shared import (
    LIMIT_MARGIN,
    RUCKIG_ERRORS,
    RestToRest,
    RuckigFailure,
    endpoint_problems,
    failure,
    polyline_distances,
    still_result,
    stretch_factor,
    too_short,
)
from manip.trajectory import CubicSplinePath, PathProfile, PiecewiseJerkProfile, Trajectory

logger = logging.getLogger(__name__)

# Dense timing: fractions of the largest feasible path speed V tried, and of the largest
# feasible path acceleration A for each V (the shortest 1-D profile wins).
_DENSE_V_FRACTIONS = tuple(np.linspace(1.0, 0.1, 19))
_DENSE_A_FRACTIONS = (1.0, 0.8, 0.6, 0.4, 0.2)
# Dense timing: points closer than this to their predecessor are merged [rad].
_DENSE_MERGE = 1e-9
# Dense timing: samples per spline piece for the deviation from the input polyline.
_DENSE_DEVIATION_SAMPLES = 17
# Dense timing: limit reductions after a failed verification, and their factor.
_DENSE_RETRIES = 3
_DENSE_SHRINK = 0.95


class _Rest1D(RestToRest):
    """Rest-to-rest 1-D ruckig problems from 0 to `length` [rad] (the time scaling `s(t)`)."""

    def __init__(self, length: float):
        super().__init__()
        self.length = length

    def solve(self, v: float, a: float, j: float) -> float | None:
        """Duration [s] with limits (v, a, j) on s-dot, s-ddot, s-dddot (shrunk by the margin), or None."""
        try:
            res = self.calculate(self.length, v * (1 - LIMIT_MARGIN), a * (1 - LIMIT_MARGIN), j * (1 - LIMIT_MARGIN))
        except RUCKIG_ERRORS:
            return None
        if res != ruckig.Result.Working:
            return None
        return float(self.traj.duration)

    def profile(self, v: float, a: float, j: float) -> PiecewiseJerkProfile:
        """The 1-D profile for these limits, ending exactly at `length` at rest."""
        if self.solve(v, a, j) is None:
            raise RuckigFailure(f"ruckig failed on the path parameter (L={self.length}, V={v}, A={a}, J={j})")
        prof = self.rest_profile("problem")
        duration = float(self.traj.duration)
        knots = np.zeros(10)
        knots[1:8] = np.minimum(np.cumsum(prof.t), duration)
        knots[8:] = duration
        jerk = np.zeros(9)
        jerk[:7] = prof.j
        return PiecewiseJerkProfile(
            knots=knots[None, :],
            p0=np.concatenate([prof.p, [self.length]])[None, :],
            v0=np.concatenate([prof.v, [0.0]])[None, :],
            a0=np.concatenate([prof.a, [0.0]])[None, :],
            j=jerk[None, :],
        )


def _parameter_limits(
    bounds: tuple[np.ndarray, np.ndarray, np.ndarray],
    vmax: np.ndarray,
    amax: np.ndarray,
    jmax: np.ndarray,
    v_fractions: Sequence[float],
    a_fractions: Sequence[float],
) -> list[tuple[float, float, float]]:
    """Limits (V, A, J) on s-dot, s-ddot, s-dddot under which every joint limit holds.

    With per-piece maxima m1, m2, m3 of |q'|, |q''|, |q'''| (P, dof), for every piece and
    joint: |qd| <= m1 V, |qdd| <= m1 A + m2 V^2, |qddd| <= m1 J + 3 m2 V A + m3 V^3. For
    each V (a fraction of the largest feasible) and A (a fraction of the largest feasible
    for that V), J is the largest feasible; combinations where A or J would not be
    positive are left out.
    """
    m1, m2, m3 = bounds
    live = m1 > 0  # m1 == 0 on a piece means the joint does not move there (m2 = m3 = 0)
    m1, m2, m3 = m1[live], m2[live], m3[live]
    vm, am, jm = (np.broadcast_to(x, live.shape)[live] for x in (vmax, amax, jmax))
    v = np.asarray(v_fractions, dtype=float)[:, None] * float(np.min(vm / m1))  # (nv, 1)
    a_top = np.min((am - m2 * v**2) / m1, axis=1, keepdims=True)  # (nv, 1)
    a = np.asarray(a_fractions, dtype=float)[None, :] * a_top  # (nv, na)
    vv, aa = v[:, :, None], a[:, :, None]
    j = np.min((jm - 3.0 * m2 * vv * aa - m3 * vv**3) / m1, axis=2)  # (nv, na)
    ok = (a > 0) & (j > 0)
    return [(float(v[iv, 0]), float(a[iv, ia]), float(j[iv, ia])) for iv, ia in zip(*np.nonzero(ok))]


def _best_parameter_limits(
    rest: _Rest1D, bounds: tuple[np.ndarray, np.ndarray, np.ndarray], vmax: np.ndarray, amax: np.ndarray,
    jmax: np.ndarray,
) -> tuple[float, float, float] | None:
    """The (V, A, J) of `_parameter_limits` over a grid of fractions giving the shortest profile."""
    best: tuple[float, tuple[float, float, float]] | None = None
    for lim in _parameter_limits(bounds, vmax, amax, jmax, _DENSE_V_FRACTIONS, _DENSE_A_FRACTIONS):
        t = rest.solve(*lim)
        if t is not None and (best is None or t < best[0]):
            best = (t, lim)
    return None if best is None else best[1]


def _merge_close(w: np.ndarray) -> np.ndarray:
    """Indices of the points kept: a point within `_DENSE_MERGE` [rad] of the previous kept one is dropped.

    The first and last points are always kept (interior points too close to the last one
    are dropped instead), except that a path whose points all equal its start gives [0].
    """
    keep = [0]
    for i in range(1, len(w) - 1):
        if np.linalg.norm(w[i] - w[keep[-1]]) > _DENSE_MERGE:
            keep.append(i)
    while len(keep) > 1 and np.linalg.norm(w[-1] - w[keep[-1]]) <= _DENSE_MERGE:
        keep.pop()
    if not (len(keep) == 1 and np.array_equal(w[-1], w[0])):
        keep.append(len(w) - 1)
    return np.asarray(keep)


def _curve_deviation(spline: CubicSplinePath, w: np.ndarray, keep: np.ndarray) -> float:
    """Max distance [rad] of the curve from the input polyline `w`, piece by piece.

    Each piece is sampled at `_DENSE_DEVIATION_SAMPLES` points and compared with the
    stretch of `w` between its two end points (the chord when no point was merged): an
    upper bound of the distance to the whole polyline at those samples.
    """
    u = np.linspace(0.0, 1.0, _DENSE_DEVIATION_SAMPLES)[1:-1]
    h = np.diff(spline.breaks)
    s = (spline.breaks[:-1, None] + h[:, None] * u[None, :]).ravel()
    q = spline.evaluate(s)[0].reshape(h.size, u.size, -1)  # (P, U, dof)
    a, b = w[keep[:-1]], w[keep[1:]]
    d = b - a
    lam = np.einsum("pud,pd->pu", q - a[:, None, :], d) / np.einsum("pd,pd->p", d, d)[:, None]
    lam = np.clip(lam, 0.0, 1.0)
    dist = np.linalg.norm(q - a[:, None, :] - lam[:, :, None] * d[:, None, :], axis=2).max(axis=1)
    for i in np.flatnonzero(np.diff(keep) > 1):  # merged points: the original stretch
        dist[i] = polyline_distances(q[i], w[keep[i] : keep[i + 1] + 1]).max()
    return float(dist.max()) if dist.size else 0.0


def _crossing_times(timing: PiecewiseJerkProfile, s_values: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Times [s] at which the non-decreasing `s(t)` reaches each of `s_values`.

    Interpolated on the evaluations of `s` at the times `grid`, then refined by Newton steps.
    """
    s_grid = timing.evaluate(grid)[0][:, 0]
    t = np.interp(s_values, s_grid, grid)
    for _ in range(3):
        s, sd = (x[:, 0] for x in timing.evaluate(t)[:2])
        step = np.where(sd > 0, (s - s_values) / np.where(sd > 0, sd, 1.0), 0.0)
        t = np.clip(t - step, 0.0, timing.duration)
    return t


def time_parameterize_dense(
    path: np.ndarray | Sequence[Sequence[float]],
    velocity_limits: np.ndarray | Sequence[float],
    acceleration_limits: np.ndarray | Sequence[float],
    jerk_limits: np.ndarray | Sequence[float],
    *,
    dt: float = 1.0 / 60.0,
    joint_names: Sequence[str] | None = None,
    lower_limits: np.ndarray | Sequence[float] | None = None,
    upper_limits: np.ndarray | Sequence[float] | None = None,
    position_tolerance: float = 1e-6,
    deviation_tolerance: float | None = None,
    velocity_scale: float = 1.0,
    acceleration_scale: float = 1.0,
    jerk_scale: float = 1.0,
    duration: float | None = None,
) -> TimingResult:
    """Time a dense, smooth joint path as ONE motion along a spline through its points.

    For paths sampled densely from a smooth curve (incremental IK along a Cartesian
    line, an optimiser's output), where `time_parameterize` would slow down at nearly
    every point. Mode name "along_path":

    1. the points are joined by a C2 curve `q(s)`: the not-a-knot cubic spline per joint
       over the cumulative chord length `s` (`CubicSplinePath.fit`), which passes through
       every point;
    2. the time scaling `s(t)` is one rest-to-rest ruckig profile from 0 to the length
       `L`, with limits (V, A, J) on s-dot, s-ddot, s-dddot such that, with the exact
       per-piece maxima of |q'|, |q''|, |q'''|, the chain rule bounds every joint's
       velocity, acceleration and jerk by its limit (`qd = q' sd`,
       `qdd = q' sdd + q'' sd^2`, `qddd = q' sddd + 3 q'' sd sdd + q''' sd^3`); the split
       between V and A is chosen on a grid for the shortest profile;
    3. the motion is checked on its samples and every 0.25 ms (exact limits); the
       trajectory carries a `PathProfile`, so `at_time` and `resample` are exact.

    The curve's speed is bounded by its worst stretch (one profile, no speed variation
    along the path), so a path with a sharp corner is slow everywhere: use
    `time_parameterize` for paths with corners. Points closer than 1e-9 rad to their
    predecessor are merged.

    Args:
        path: (K, dof) points [rad], K >= 1; the first is the start, the last the goal.
        velocity_limits: (dof,) max |velocity| [rad/s] (or a scalar for all joints).
        acceleration_limits: (dof,) max |acceleration| [rad/s^2].
        jerk_limits: (dof,) max |jerk| [rad/s^3].
        dt: sample period of the returned trajectory [s].
        joint_names: (dof,) names; default "joint_0", "joint_1", ...
        lower_limits: (dof,) lower position limits [rad]; None = unchecked.
        upper_limits: (dof,) upper position limits [rad]; None = unchecked.
        position_tolerance: points may lie this far outside the position limits [rad];
            the curve is checked against the limits widened by the same amount.
        deviation_tolerance: if given, fail with DEVIATION_TOO_LARGE when the curve strays
            further than this from the input polyline [rad] (joint-space Euclidean).
        velocity_scale: factor in (0, 1] applied to the velocity limits.
        acceleration_scale: factor in (0, 1] applied to the acceleration limits.
        jerk_scale: factor in (0, 1] applied to the jerk limits.
        duration: desired total time [s] (uniform time stretch, as in `time_parameterize`).

    Returns:
        TimingResult with mode "along_path": `max_deviation` is how far the curve strays
        from the input polyline between its points [rad] (sampled, per piece);
        `waypoints` are the points used, `waypoint_velocities` the velocity as the motion
        passes each, `segment_durations` the time between them. Fails with
        POSITION_LIMIT when the curve overshoots a position limit between two points,
        DEVIATION_TOO_LARGE, DURATION_TOO_SHORT, or RUCKIG_FAIL / LIMIT_VIOLATION
        (numerical trouble): callers should then fall back to `time_parameterize`.

    Raises:
        InvalidInputError: as `time_parameterize` (shapes, non-finite values, limits,
            scales, points outside the position limits), or a negative tolerance.
    """
    t_start = time.perf_counter()
    check_deviation_tolerance(deviation_tolerance, optional=True)
    w, limits = check_inputs(
        path, velocity_limits, acceleration_limits, jerk_limits, dt, joint_names, lower_limits, upper_limits,
        position_tolerance, velocity_scale, acceleration_scale, jerk_scale, duration,
    )
    vmax, amax, jmax, names = limits.velocity, limits.acceleration, limits.jerk, limits.joint_names
    lower, upper = limits.lower, limits.upper
    mode = "along_path"
    keep = _merge_close(w)
    wp = w[keep]

    def fail(status: TimingStatus, msg: str, min_dur: float = float("nan"), dev: float = float("nan")) -> TimingResult:
        return failure("time_parameterize_dense", mode, status, msg, wp, t_start, min_dur, dev)

    if len(wp) == 1:  # nothing to move: a still trajectory at the (exact) end point
        return still_result(w[-1], dt, names, mode, wp, t_start)

    spline = CubicSplinePath.fit(wp)
    spline = CubicSplinePath(spline.breaks, spline.coeffs, w[-1])
    deviation = _curve_deviation(spline, w, keep)
    if deviation_tolerance is not None and deviation > deviation_tolerance:
        return fail(
            TimingStatus.DEVIATION_TOO_LARGE,
            f"the spline through the points strays {deviation:.3g} rad from the path "
            f"(tolerance {deviation_tolerance:.3g} rad)",
            dev=deviation,
        )
    if lower is not None:
        lo, hi = spline.position_range()
        if np.any(lo < lower) or np.any(hi > upper):
            jj = int(np.argmax(np.maximum(lower - lo, hi - upper)))
            return fail(
                TimingStatus.POSITION_LIMIT,
                f"the spline through the points leaves the position limits of joint {jj} ({names[jj]}): "
                f"range [{lo[jj]:.6f}, {hi[jj]:.6f}] rad",
                dev=deviation,
            )

    rest = _Rest1D(spline.length)
    bounds = spline.piece_bounds()
    lim = _best_parameter_limits(rest, bounds, vmax, amax, jmax)
    if lim is None:
        return fail(TimingStatus.RUCKIG_FAIL, "no feasible limits for the path parameter", dev=deviation)

    for attempt in range(_DENSE_RETRIES + 1):
        try:
            timing = rest.profile(*lim)
        except RuckigFailure as e:
            return fail(TimingStatus.RUCKIG_FAIL, str(e), dev=deviation)
        t_min = timing.duration
        if msg := too_short(duration, t_min):
            return fail(TimingStatus.DURATION_TOO_SHORT, msg, t_min, deviation)
        profile = PathProfile(spline, timing).time_scaled(stretch_factor(t_min, duration, dt))
        traj = Trajectory.from_profile(profile, dt, names)
        # -- verification (samples and a dense grid), exact limits
        grid = profile.dense_times()
        _, qd, qdd, qddd = profile.evaluate(grid)
        problems = []
        for arrs, lim_d, label in (
            ((traj.velocities, qd), vmax, "velocity"),
            ((traj.accelerations, qdd), amax, "acceleration"),
            ((traj.jerks, qddd), jmax, "jerk"),
        ):
            if any(np.any(np.abs(a) > lim_d) for a in arrs):
                problems.append(f"{label} above its limit")
        if not problems:
            break
        logger.debug("time_parameterize_dense: %s; limits reduced (attempt %d)", "; ".join(problems), attempt + 1)
        lim = tuple(x * _DENSE_SHRINK for x in lim)  # type: ignore[assignment]
    else:
        return fail(TimingStatus.LIMIT_VIOLATION, "verification failed: " + "; ".join(problems), t_min, deviation)
    if problems := endpoint_problems(traj, w):
        return fail(TimingStatus.LIMIT_VIOLATION, "verification failed: " + "; ".join(problems), t_min, deviation)

    times = _crossing_times(profile.timing, spline.breaks, grid)
    times[[0, -1]] = 0.0, profile.duration
    sd = profile.timing.evaluate(times)[1]
    velocities = spline.evaluate(spline.breaks)[1] * sd
    velocities[[0, -1]] = 0.0
    elapsed = time.perf_counter() - t_start
    logger.debug(
        "time_parameterize_dense: %d points (%d used), %.3f s, deviation %.3g rad, %.2f ms",
        len(w), len(wp), traj.duration, deviation, elapsed * 1e3,
    )
    return TimingResult(True, TimingStatus.SUCCESS, traj, mode, t_min, deviation, wp, velocities, np.diff(times),
                        elapsed, "")
