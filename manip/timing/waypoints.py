"""Waypoint timing (modes "exact" and "blend"): ruckig segments joined at the waypoints.

The waypoints [rad] are joined by ruckig's exact time-optimal, jerk-limited
state-to-state segments (`Ruckig.calculate` with one target state; ruckig's waypoint
feature, `intermediate_positions`, calls a cloud service and is never used). Each segment
starts and ends with zero acceleration, so the acceleration is continuous across segments.

* ``"exact"``: stop at every corner of the path. Each segment is rest-to-rest along its
  straight line, timed as a 1-D ruckig problem in the arc length with the joint limits
  projected onto the line (ruckig's own `Synchronization.Phase` falls back to time
  synchronisation, which leaves the line, whenever the slowest joint's scaled profile
  would break another joint's limit). The motion is on the segments up to round-off and
  time-optimal for each straight segment. Repeated and collinear waypoints are merged
  first, so straight runs are not interrupted.
* ``"blend"``: first, waypoints within half of `deviation_tolerance` of the chord of their
  neighbours are dropped (Douglas-Peucker; dense paths from an optimiser become a few
  waypoints). The motion then passes through the remaining interior waypoints with a
  non-zero velocity along the bisector of the corner (heuristic below), which is faster
  but leaves the straight segments. Every segment whose deviation from the input path
  exceeds `deviation_tolerance`, or whose position range leaves the position limits, has
  the speed caps of its ends lowered (zero after a few reductions, which gives an exact
  segment) until all segments pass. Stopping everywhere is also tried and the faster
  result kept, so blending is never slower than exact.

Deviation is the joint-space Euclidean distance [rad] between the motion and the input
path (the polyline through the given waypoints), an upper bound of the L-inf distance;
it is measured every <= 10 ms with the sampling error bounded and subtracted from the
tolerance, and reported as `TimingResult.max_deviation`.

Waypoint velocity heuristic (blend): at an interior waypoint with unit incoming and
outgoing directions `u_in`, `u_out` and turning angle `theta`, the velocity is zero if
`theta > stop_angle`, else along the bisector `u_in + u_out`, with the speed capped by
the velocity limits along it and by `sqrt(a tol / 2) / sin(theta / 2)` (the sideways
speed that can be removed within half the tolerance at half the acceleration `a`
along it), then limited by forward/backward reachability passes
(`v_i^2 <= v_{i-1}^2 + a L / 2`) so neighbouring speeds are consistent.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from manip.timing.checks import Checked
from manip.timing.result import TimingResult, TimingStatus
from manip.timing.segments import (
    DEVIATION_STEP,
    Segment,
    SegmentSolver,
    assemble,
    max_polyline_distance,
    segment_deviation,
)
from manip.timing.shared import (
    RuckigFailure,
    endpoint_problems,
    failure,
    polyline_distances,
    still_result,
    stretch_factor,
    too_short,
)
from manip.trajectory import PiecewiseJerkProfile, Trajectory

logger = logging.getLogger(__name__)

# A segment whose ends are at rest is "exact" when it stays this close to its line [rad].
_EXACT_DEVIATION = 1e-9
# Blend mode: reductions of a waypoint's speed cap before it is set to zero.
_MAX_HALVINGS = 4
# Blend mode: global speed levels tried (0 = stop everywhere = exact). Measured on random
# and smooth 7-DoF paths, lower levels (0.8 ... 0.2) beat 1.0 by < 1 % on average.
_SPEED_LEVELS = (1.0, 0.0)


def _simplify(path: np.ndarray) -> np.ndarray:
    """Drop repeated waypoints and interior waypoints lying on the segment of their neighbours."""
    keep = [path[0]]
    for w in path[1:]:
        if not np.array_equal(w, keep[-1]):
            keep.append(w)
    if len(keep) == 1:
        return np.asarray(keep)
    out = [keep[0]]
    for i in range(1, len(keep) - 1):
        a, b, c = out[-1], keep[i], keep[i + 1]
        d = c - a
        dd = float(d @ d)
        lam = float((b - a) @ d) / dd if dd > 0 else -1.0
        if 0.0 < lam < 1.0 and np.max(np.abs(a + lam * d - b)) <= _EXACT_DEVIATION:
            continue  # b is on segment a-c: removing it leaves the geometric path unchanged
        out.append(b)
    out.append(keep[-1])
    return np.asarray(out)


def _path_deviation(profile: PiecewiseJerkProfile, path: np.ndarray, times: np.ndarray) -> float:
    """Max over time of the distance from the motion to the polyline `path` [rad].

    Measured at `times` and every <= `DEVIATION_STEP` (see `polyline_distances`).
    """
    if len(path) < 2 or profile.duration == 0:
        return 0.0
    n = int(np.ceil(profile.duration / DEVIATION_STEP)) + 1
    ts = np.clip(np.union1d(times, np.linspace(0.0, profile.duration, n)), 0.0, profile.duration)  # as `evaluate`
    pieces = [np.ascontiguousarray(a, dtype=np.float64)
              for a in (profile.knots, profile.p0, profile.v0, profile.a0, profile.j, path)]
    return float(max_polyline_distance(*pieces[:5], ts, pieces[5]))


# ---------------------------------------------------------------------------- heuristics
def _douglas_peucker(w: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices of the waypoints to keep so every dropped one is within `tolerance` of its chord.

    Euclidean distance; the distance to a segment is convex, so the whole dropped stretch
    of the polyline (not only its vertices) is within `tolerance` of the chord, and
    (the projection onto the chord being continuous and onto) every point of the chord is
    within `tolerance` of that stretch.
    """
    keep = np.zeros(len(w), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(w) - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        dist = polyline_distances(w[a + 1 : b], w[[a, b]])
        m = int(np.argmax(dist))
        if dist[m] > tolerance:
            keep[a + 1 + m] = True
            stack += [(a, a + 1 + m), (a + 1 + m, b)]
    return np.flatnonzero(keep)


@dataclass
class _Blend:
    """Per-waypoint blend data: direction, speed cap, acceleration budget (see `_blend_data`)."""

    directions: np.ndarray  # (K, dof) unit vectors (0 where the motion stops)
    caps: np.ndarray  # (K,) speed caps [rad/s]
    accel: np.ndarray  # (K,) acceleration budget along the direction [rad/s^2]
    lengths: np.ndarray  # (K - 1,) segment lengths [rad]

    def velocities(self, caps: np.ndarray | None = None) -> np.ndarray:
        """(K, dof) waypoint velocities: caps limited by reachability (forward/backward passes)."""
        speed = (self.caps if caps is None else caps).copy()
        k = len(speed)
        for i in range(1, k - 1):
            speed[i] = min(speed[i], np.sqrt(speed[i - 1] ** 2 + self.accel[i] * self.lengths[i - 1]))
        for i in range(k - 2, 0, -1):
            speed[i] = min(speed[i], np.sqrt(speed[i + 1] ** 2 + self.accel[i] * self.lengths[i]))
        return self.directions * speed[:, None]


def _blend_data(
    w: np.ndarray, vmax: np.ndarray, amax: np.ndarray, stop_angle: float, tolerance: float
) -> _Blend:
    """Waypoint velocity heuristic for blend mode.

    Direction: the bisector of the corner (zero if the corner turns by more than
    `stop_angle`, and at both ends). Speed: the smallest of (a) the velocity limits along
    it, (b) the speed whose sideways component `v sin(theta / 2)` can be removed within
    the deviation tolerance at half the acceleration along it,
    `sqrt(a tol) / sin(theta / 2)`, and (c) what can be reached from and stopped in the
    neighbouring segments (`v_i^2 <= v_{i-1}^2 + a L`, forward and backward passes, at
    half the acceleration to leave room for the jerk limit).
    """
    k, dof = w.shape
    d = np.diff(w, axis=0)
    lengths = np.linalg.norm(d, axis=1)
    u = d / lengths[:, None]
    cos_stop = np.cos(stop_angle)
    directions = np.zeros((k, dof))
    caps = np.zeros(k)
    accel = np.zeros(k)
    for i in range(1, k - 1):
        cos_t = float(np.clip(u[i - 1] @ u[i], -1.0, 1.0))
        if cos_t < cos_stop:
            continue
        direction = u[i - 1] + u[i]
        direction /= np.linalg.norm(direction)
        mag = np.abs(direction)
        nz = mag > 1e-12
        s_v = float(np.min(vmax[nz] / mag[nz]))
        a_dir = float(np.min(amax[nz] / mag[nz]))
        sin_half = np.sqrt(max(0.0, (1.0 - cos_t) / 2.0))
        s_dev = np.sqrt(0.5 * a_dir * tolerance) / sin_half if sin_half > 1e-12 else np.inf
        directions[i] = direction
        caps[i] = min(s_v, s_dev) * (1 - 1e-12)
        accel[i] = 0.5 * a_dir
    return _Blend(directions, caps, accel, lengths)


@dataclass
class _Plan:
    segments: list[Segment]
    velocities: np.ndarray
    duration: float


def _plan_segments(
    solver: SegmentSolver,
    w: np.ndarray,
    sub_paths: list[np.ndarray],
    blend: _Blend | None,
    level: float,
    lower: np.ndarray | None,
    upper: np.ndarray | None,
    tolerance: float,
) -> _Plan:
    """Solve all segments, repairing those that deviate or leave the position limits.

    A bad segment lowers the speed caps of its two waypoints (by sqrt(tolerance /
    deviation), deviation growing about as speed^2, else by half; zero after
    `_MAX_HALVINGS` reductions), the reachability passes are re-run so neighbours slow down
    consistently, and the segments whose end velocities changed are solved again.
    Terminates: every round lowers a cap, and all-zero velocities give exact segments.
    """
    k = len(w)
    # Sampling every h misses at most M h^2 / 8 of a maximum, where M bounds the second
    # derivative of the distance to a line: ||(I - u u^T) q''|| <= ||amax||.
    margin = 0.125 * float(np.linalg.norm(solver.used.acceleration)) * DEVIATION_STEP**2
    tolerance = max(0.0, tolerance - margin)
    caps = np.zeros(k) if blend is None else blend.caps * level
    halvings = np.zeros(k, dtype=int)
    vel = np.zeros_like(w) if blend is None else blend.velocities(caps)
    segs: list[Segment | None] = [None] * (k - 1)
    todo = set(range(k - 1))
    while todo:
        for i in sorted(todo):
            if vel[i].any() or vel[i + 1].any():
                seg = solver.solve(w[i], vel[i], w[i + 1], vel[i + 1])
                seg.deviation = segment_deviation(seg, sub_paths[i])
            else:
                seg = solver.solve_line(w[i], w[i + 1])  # on the line by construction
            segs[i] = seg
        reduce: dict[int, float] = {}
        for i in range(k - 1):
            seg = segs[i]
            assert seg is not None
            at_rest = not vel[i].any() and not vel[i + 1].any()
            bad = seg.deviation > (_EXACT_DEVIATION if at_rest else tolerance)
            if lower is not None and (np.any(seg.pos_min < lower) or np.any(seg.pos_max > upper)):
                bad = True
            if not bad:
                continue
            if at_rest:
                # A rest-to-rest segment is timed along its straight line between in-limit
                # waypoints; if it is not on the line, nothing more can be done here.
                raise RuckigFailure(
                    f"rest-to-rest segment {i} left its straight line by {seg.deviation:.3g} rad "
                    "or the position limits (numerical failure)"
                )
            # deviation grows about as speed^2: aim just below the tolerance
            ratio = 0.5
            if seg.deviation > tolerance > 0:
                ratio = float(np.clip(0.9 * np.sqrt(tolerance / seg.deviation), 0.1, 0.9))
            for wi in (i, i + 1):
                if vel[wi].any():
                    reduce[wi] = min(reduce.get(wi, 1.0), ratio)
        if not reduce:
            break
        assert blend is not None
        for wi, ratio in reduce.items():
            halvings[wi] += 1
            # relative to the actual speed (the cap may be above it, limited by reachability)
            speed = float(np.linalg.norm(vel[wi]))
            caps[wi] = 0.0 if halvings[wi] > _MAX_HALVINGS else min(caps[wi], speed) * ratio
        new_vel = blend.velocities(caps)
        changed = np.flatnonzero(np.any(new_vel != vel, axis=1))
        vel = new_vel
        todo = {x for wi in changed for x in (wi - 1, wi) if 0 <= x < k - 1}
    done = [s for s in segs if s is not None]
    return _Plan(done, vel, float(sum(s.duration for s in done)))


def time_waypoints(
    checked: Checked,
    *,
    mode: Literal["blend", "exact"],
    deviation_tolerance: float,
    stop_angle: float,
    dt: float,
    duration: float | None,
    t_start: float,
) -> TimingResult:
    """`time_parameterize` in modes "exact" and "blend", on validated inputs.

    Args:
        checked: the validated path and (scaled) limits (`check_inputs`).
        mode: "blend" or "exact" (see the module docstring).
        deviation_tolerance: blend: max distance of the motion from the path [rad], >= 0.
        stop_angle: blend: corners turning by more than this stop the motion [rad].
        dt: sample period of the trajectory [s].
        duration: desired total time [s], or None for the fastest.
        t_start: `time.perf_counter()` when the call began (for `compute_time`).
    """
    w, limits = checked
    vmax, amax, jmax, names = limits.velocity, limits.acceleration, limits.jerk, limits.joint_names
    lower, upper = limits.lower, limits.upper

    wp = _simplify(w)
    if len(wp) == 1:  # nothing to move
        return still_result(wp[0], dt, names, mode, wp, t_start)
    keep = np.arange(len(wp))
    if mode == "blend" and len(wp) > 2:
        # Dense paths (e.g. from trajectory optimisation): drop waypoints within half the
        # tolerance of their chord; the rest of the tolerance is for rounding corners.
        keep = _douglas_peucker(wp, 0.5 * deviation_tolerance)
    sub_paths = [wp[keep[i] : keep[i + 1] + 1] for i in range(len(keep) - 1)]
    wp = wp[keep]
    solver = SegmentSolver(limits)

    def fail(status: TimingStatus, msg: str, min_dur: float = float("nan")) -> TimingResult:
        return failure("time_parameterize", mode, status, msg, wp, t_start, min_dur)

    # -- fastest plan for the mode
    try:
        levels = (0.0,) if mode == "exact" else _SPEED_LEVELS
        blend = (
            _blend_data(wp, solver.used.velocity, solver.used.acceleration, stop_angle, 0.5 * deviation_tolerance)
            if mode == "blend"
            else None
        )
        best = None
        for level in levels:
            plan = _plan_segments(
                solver, wp, sub_paths, None if level == 0.0 else blend, level, lower, upper, deviation_tolerance,
            )
            if best is None or plan.duration < best.duration:
                best = plan
        assert best is not None
    except RuckigFailure as e:
        return fail(TimingStatus.RUCKIG_FAIL, str(e))

    # -- stretch to the requested duration and to a whole number of dt
    t_min = best.duration
    if t_min == 0.0:  # ruckig resolves no motion (the points differ by rounding, e.g. 1e-15 rad): stay at the start
        return still_result(wp[0], dt, names, mode, wp[:1], t_start)
    if msg := too_short(duration, t_min):
        return fail(TimingStatus.DURATION_TOO_SHORT, msg, t_min)
    profile = assemble(best.segments, wp[-1])
    factor = 1.0
    if t_min > 0:
        factor = stretch_factor(t_min, duration, dt)
        profile = profile.time_scaled(factor)
    traj = Trajectory.from_profile(profile, dt, names)

    # -- independent verification (analytic profile and samples), exact limits
    ext = profile.extrema()
    problems = []
    for key, lim, label in (
        ("max_abs_velocity", vmax, "velocity"),
        ("max_abs_acceleration", amax, "acceleration"),
        ("max_abs_jerk", jmax, "jerk"),
    ):
        if np.any(ext[key] > lim):
            problems.append(f"{label} {ext[key]} > {lim}")
    for arr, lim, label in (
        (traj.velocities, vmax, "sampled velocity"),
        (traj.accelerations, amax, "sampled acceleration"),
        (traj.jerks, jmax, "sampled jerk"),
    ):
        if np.any(np.abs(arr) > lim):
            problems.append(f"{label} above limit")
    if lower is not None and (np.any(ext["position_min"] < lower) or np.any(ext["position_max"] > upper)):
        problems.append("position limits")
    problems += endpoint_problems(traj, w)
    if problems:
        return fail(TimingStatus.LIMIT_VIOLATION, "verification failed: " + "; ".join(problems), t_min)

    seg_times = np.array([s.duration for s in best.segments]) * factor
    deviation = _path_deviation(profile, w, traj.times)
    elapsed = time.perf_counter() - t_start
    logger.debug(
        "time_parameterize: %d waypoints (%d used), %s, %.3f s, deviation %.3g rad, %.2f ms",
        len(w), len(wp), mode, traj.duration, deviation, elapsed * 1e3,
    )
    return TimingResult(
        True, TimingStatus.SUCCESS, traj, mode, t_min, deviation, wp, best.velocities / factor,
        seg_times, elapsed, "",
    )
