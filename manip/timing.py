"""Time-parameterisation of a joint-space path with ruckig (state-to-state only).

`time_parameterize(path, ...)` turns the piecewise-linear, collision-checked joint path of
a planner into a `Trajectory` at rest at both ends that respects velocity, acceleration
and jerk limits everywhere (checked analytically on the profile and on the samples).

How it works: the waypoints are joined by ruckig's exact time-optimal, jerk-limited
state-to-state segments (`Ruckig.calculate` with one target state; ruckig's waypoint
feature, `intermediate_positions`, calls a cloud service and is never used). Each segment
starts and ends with zero acceleration, so the acceleration is continuous across segments.

Three modes:

* ``"exact"``: stop at every corner of the path. Each segment is rest-to-rest along its
  straight line, timed as a 1-D ruckig problem in the arc length with the joint limits
  projected onto the line (ruckig's own `Synchronization.Phase` falls back to time
  synchronisation, which leaves the line, whenever the slowest joint's scaled profile
  would break another joint's limit). The motion is on the segments up to round-off and
  time-optimal for each straight segment. Repeated and collinear waypoints are merged
  first, so straight runs are not interrupted.
* ``"blend"`` (default): first, waypoints within half of `deviation_tolerance` of the
  chord of their neighbours are dropped (Douglas-Peucker; dense paths from an optimiser
  become a few waypoints). The motion then passes through the remaining interior
  waypoints with a non-zero velocity along the bisector of the corner (heuristic below),
  which is faster but leaves the straight segments. Every segment whose deviation from
  the input path exceeds `deviation_tolerance`, or whose position range leaves the
  position limits, has the speed caps of its ends lowered (zero after a few reductions,
  which gives an exact segment) until all segments pass. Stopping everywhere is also
  tried and the faster result kept, so blending is never slower than exact. The caller
  should collision-check the timed motion (its samples or `at_time` densely) and fall
  back to ``mode="exact"`` if it collides.
* ``"along_path"`` (`time_parameterize_dense`, or `time_parameterize(mode="along_path")`):
  for DENSE paths sampled from a smooth curve (incremental IK along a Cartesian line, an
  optimiser's output), where the other modes slow down at nearly every point. A C2
  not-a-knot cubic spline `q(s)` through all the points (s = chord length) is traversed by
  ONE rest-to-rest ruckig profile `s(t)`, whose limits are chosen so the chain rule keeps
  every joint within its limits; the motion flows along the whole path. Paths with sharp
  corners make it slow everywhere (its speed is set by the worst stretch): use it for
  smooth dense paths, with "blend" as the fallback.

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

Speed and duration control: `velocity_scale`, `acceleration_scale` and `jerk_scale`
scale the limits (MoveIt-style scaling factors in (0, 1]); `duration` stretches the
fastest trajectory uniformly in time to a chosen duration (uniform time scaling by a
factor `k >= 1` divides velocities by `k`, accelerations by `k^2` and jerks by `k^3`,
so limits still hold and the geometric path is unchanged). The total duration is always
rounded up to a whole number of `dt` (by the same uniform stretch), so samples are
evenly spaced and the last one is exactly at the goal, at rest.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace
from enum import Enum
from typing import TYPE_CHECKING, Any, Literal, Sequence

import numpy as np
import ruckig

from manip.errors import InvalidInputError
from manip.trajectory import CubicSplinePath, PathProfile, PiecewiseJerkProfile, Trajectory, evaluate_pieces

if TYPE_CHECKING:
    from manip.robot_config import RobotConfig

logger = logging.getLogger(__name__)

# Ruckig is given limits shrunk by this relative margin so that its round-off never
# crosses the caller's limits, which are then checked exactly (no tolerance).
_LIMIT_MARGIN = 1e-9
# A segment whose ends are at rest is "exact" when it stays this close to its line [rad].
_EXACT_DEVIATION = 1e-9
# Blend mode: reductions of a waypoint's speed cap before it is set to zero.
_MAX_HALVINGS = 4
# Blend mode: global speed levels tried (0 = stop everywhere = exact). Measured on random
# and smooth 7-DoF paths, lower levels (0.8 ... 0.2) beat 1.0 by < 1 % on average.
_SPEED_LEVELS = (1.0, 0.0)
# Position limits are checked to within this round-off [rad] (a motion along a segment that
# ends exactly on a limit computes its end as start + direction * length).
_POSITION_ROUNDOFF = 1e-12
# Deviation is measured on each segment every this many seconds (at most).
_DEVIATION_STEP = 0.01
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


class TimingStatus(Enum):
    """Outcome of `time_parameterize`."""

    SUCCESS = "success"
    DURATION_TOO_SHORT = "duration_too_short"  # requested duration < fastest feasible; see minimum_duration
    RUCKIG_FAIL = "ruckig_fail"  # ruckig could not compute a segment (should not happen for valid input)
    LIMIT_VIOLATION = "limit_violation"  # final verification failed (a bug: please report)
    POSITION_LIMIT = "position_limit"  # along_path: the curve through the points leaves a position limit
    DEVIATION_TOO_LARGE = "deviation_too_large"  # along_path: the curve strays beyond deviation_tolerance


@dataclass(frozen=True, eq=False)
class TimingResult:
    """Result of `time_parameterize`.

    Attributes:
        success: True iff `trajectory` is valid (within all limits, at rest at both ends,
            ending exactly at the last waypoint).
        status: why it failed, if it did.
        trajectory: the timed trajectory, or None on failure.
        mode: "exact" or "blend" (`time_parameterize`), "along_path" (`time_parameterize_dense`).
        minimum_duration: duration of the fastest trajectory found for this mode and these
            (scaled) limits [s], before stretching to `duration` / a multiple of `dt`.
        max_deviation: largest joint-space distance between the timed motion and the
            input path (the polyline through the given waypoints) [rad], Euclidean (an
            upper bound of the L-inf distance), measured at the samples and every
            <= 10 ms; ~0 in exact mode, <= `deviation_tolerance` in blend mode. In
            along_path mode: how far the spline strays from the polyline between the
            points it passes through (each piece vs. its chord, 17 samples per piece).
        waypoints: (K', dof) the waypoints used (duplicates and collinear points removed) [rad].
        waypoint_velocities: (K', dof) velocity at each waypoint [rad/s] (after time scaling).
        segment_durations: (K' - 1,) time between consecutive waypoints [s] (after scaling).
        compute_time: wall-clock time spent [s].
        message: human-readable detail.
    """

    success: bool
    status: TimingStatus
    trajectory: Trajectory | None
    mode: str
    minimum_duration: float
    max_deviation: float
    waypoints: np.ndarray
    waypoint_velocities: np.ndarray
    segment_durations: np.ndarray
    compute_time: float
    message: str = ""


# ---------------------------------------------------------------------------- validation
def _vector(values: Sequence[float] | np.ndarray, name: str, dof: int, positive: bool) -> np.ndarray:
    a = np.array(values, dtype=float)
    if a.ndim == 0:
        a = np.full(dof, float(a))
    if a.shape != (dof,):
        raise InvalidInputError(f"{name} must have shape ({dof},) (one per joint); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{name} has non-finite entries: {a}")
    if positive and np.any(a <= 0):
        raise InvalidInputError(f"{name} must be > 0; got {a}")
    return a


def _scale(value: float, name: str) -> float:
    v = float(value)
    if not (np.isfinite(v) and 0.0 < v <= 1.0):
        raise InvalidInputError(f"{name} must be in (0, 1]; got {value}")
    return v


def _check_inputs(
    path: Any,
    velocity_limits: Any,
    acceleration_limits: Any,
    jerk_limits: Any,
    dt: float,
    joint_names: Sequence[str] | None,
    lower_limits: Any,
    upper_limits: Any,
    position_tolerance: float,
    velocity_scale: float,
    acceleration_scale: float,
    jerk_scale: float,
    duration: float | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[str, ...], np.ndarray | None, np.ndarray | None]:
    """Validated (path, vmax, amax, jmax (scaled), names, lower, upper (widened or None))."""
    w = np.array(path, dtype=float)
    if w.ndim != 2 or w.shape[0] < 1 or w.shape[1] < 1:
        raise InvalidInputError(f"path must have shape (K, dof) with K >= 1; got {w.shape}")
    if not np.all(np.isfinite(w)):
        bad = np.argwhere(~np.isfinite(w))[0]
        raise InvalidInputError(f"path has a non-finite value at waypoint {bad[0]}, joint {bad[1]}")
    dof = w.shape[1]
    vmax = _vector(velocity_limits, "velocity_limits", dof, True) * _scale(velocity_scale, "velocity_scale")
    amax = _vector(acceleration_limits, "acceleration_limits", dof, True) * _scale(
        acceleration_scale, "acceleration_scale"
    )
    jmax = _vector(jerk_limits, "jerk_limits", dof, True) * _scale(jerk_scale, "jerk_scale")
    if not (np.isfinite(dt) and dt > 0):
        raise InvalidInputError(f"dt must be finite and > 0 [s]; got {dt}")
    if not (np.isfinite(position_tolerance) and position_tolerance >= 0):
        raise InvalidInputError(f"position_tolerance must be finite and >= 0 [rad]; got {position_tolerance}")
    if duration is not None and not (np.isfinite(duration) and duration >= 0):
        raise InvalidInputError(f"duration must be finite and >= 0 [s] (or None); got {duration}")
    names = tuple(joint_names) if joint_names is not None else tuple(f"joint_{i}" for i in range(dof))
    if len(names) != dof:
        raise InvalidInputError(f"joint_names has {len(names)} names for {dof} joints")
    lower = upper = None
    if (lower_limits is None) != (upper_limits is None):
        raise InvalidInputError("give both lower_limits and upper_limits, or neither")
    if lower_limits is not None:
        lower = _vector(lower_limits, "lower_limits", dof, False) - position_tolerance - _POSITION_ROUNDOFF
        upper = _vector(upper_limits, "upper_limits", dof, False) + position_tolerance + _POSITION_ROUNDOFF
        if np.any(lower > upper):
            raise InvalidInputError(f"lower_limits must be <= upper_limits; got {lower_limits}, {upper_limits}")
        outside = np.argwhere((w < lower) | (w > upper))
        if outside.size:
            i, jj = outside[0]
            raise InvalidInputError(
                f"path waypoint {i} joint {jj} ({names[jj]}) = {w[i, jj]:.6f} rad is outside the position "
                f"limits [{lower_limits[jj]:.6f}, {upper_limits[jj]:.6f}] (+- {position_tolerance} rad); "
                f"{len(outside)} violation(s) in total"
            )
    return w, vmax, amax, jmax, names, lower, upper


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


# ---------------------------------------------------------------------------- segments
@dataclass
class _Segment:
    duration: float
    knots: np.ndarray  # (dof, 9) local times
    p: np.ndarray  # (dof, 8)
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    pos_min: np.ndarray  # (dof,)
    pos_max: np.ndarray
    deviation: float = 0.0


class _RuckigFailure(RuntimeError):
    pass


class _SegmentSolver:
    """Reuses one ruckig instance for state-to-state segments with zero end accelerations."""

    def __init__(self, vmax: np.ndarray, amax: np.ndarray, jmax: np.ndarray):
        self.dof = vmax.size
        self.otg = ruckig.Ruckig(self.dof)
        self.inp = ruckig.InputParameter(self.dof)
        self.inp.max_velocity = (vmax * (1 - _LIMIT_MARGIN)).tolist()
        self.inp.max_acceleration = (amax * (1 - _LIMIT_MARGIN)).tolist()
        self.inp.max_jerk = (jmax * (1 - _LIMIT_MARGIN)).tolist()
        zeros = [0.0] * self.dof
        self.inp.current_acceleration = zeros
        self.inp.target_acceleration = zeros
        self.inp.synchronization = ruckig.Synchronization.Phase
        self.traj = ruckig.Trajectory(self.dof)
        self.vmax_used = vmax * (1 - _LIMIT_MARGIN)
        self.amax_used = amax * (1 - _LIMIT_MARGIN)
        self.jmax_used = jmax * (1 - _LIMIT_MARGIN)
        # 1-D problem along a straight line (rest to rest)
        self.otg1 = ruckig.Ruckig(1)
        self.inp1 = ruckig.InputParameter(1)
        for name in ("current_position", "current_velocity", "current_acceleration", "target_velocity",
                     "target_acceleration"):
            setattr(self.inp1, name, [0.0])
        self.traj1 = ruckig.Trajectory(1)

    def solve_line(self, p0: np.ndarray, p1: np.ndarray) -> _Segment:
        """Rest-to-rest along the straight line p0 -> p1 (exact; time-optimal for that line).

        Ruckig's phase synchronisation falls back to time synchronisation (which leaves
        the line) when the scaled profile of the slowest joint breaks another joint's
        limit, so the line is timed as a 1-D problem in its arc length `s` instead:
        `q = p0 + u s` with `|u| = 1` and the limits `min_d limit_d / |u_d|` on `s`.
        """
        d = p1 - p0
        length = float(np.linalg.norm(d))
        dof = self.dof
        if length == 0.0:
            z = np.zeros((dof, 8))
            return _Segment(0.0, np.zeros((dof, 9)), np.repeat(p0[:, None], 8, axis=1), z, z.copy(), z.copy(),
                            p0.copy(), p0.copy())
        u = d / length
        mag = np.abs(u)
        nz = mag > 0
        inp = self.inp1
        inp.target_position = [length]
        inp.max_velocity = [float(np.min(self.vmax_used[nz] / mag[nz]))]
        inp.max_acceleration = [float(np.min(self.amax_used[nz] / mag[nz]))]
        inp.max_jerk = [float(np.min(self.jmax_used[nz] / mag[nz]))]
        try:
            res = self.otg1.calculate(inp, self.traj1)
        except ruckig.RuckigError as e:
            raise _RuckigFailure(f"ruckig rejected a straight segment of length {length} rad: {e}") from e
        if res != ruckig.Result.Working:
            raise _RuckigFailure(f"ruckig returned {res} on a straight segment of length {length} rad")
        prof = self.traj1.profiles[0][0]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise _RuckigFailure("ruckig used a brake/accel pre-trajectory on a rest-to-rest segment")
        duration = float(self.traj1.duration)
        knots1 = np.zeros(9)
        knots1[1:8] = np.cumsum(prof.t)
        knots1[8] = max(duration, knots1[7])
        js = np.zeros(8)
        js[:7] = prof.j
        uc = u[:, None]
        seg = _Segment(
            duration,
            np.repeat(knots1[None, :], dof, axis=0),
            p0[:, None] + uc * np.asarray(prof.p)[None, :],
            uc * np.asarray(prof.v)[None, :],
            uc * np.asarray(prof.a)[None, :],
            uc * js[None, :],
            np.minimum(p0, p1),
            np.maximum(p0, p1),
        )
        return seg

    def solve(self, p0: np.ndarray, v0: np.ndarray, p1: np.ndarray, v1: np.ndarray) -> _Segment:
        inp = self.inp
        inp.current_position = p0.tolist()
        inp.current_velocity = v0.tolist()
        inp.target_position = p1.tolist()
        inp.target_velocity = v1.tolist()
        try:
            res = self.otg.calculate(inp, self.traj)
        except ruckig.RuckigError as e:
            raise _RuckigFailure(f"ruckig rejected the segment from {p0} / {v0} to {p1} / {v1}: {e}") from e
        if res != ruckig.Result.Working:
            raise _RuckigFailure(f"ruckig returned {res} from {p0} / {v0} to {p1} / {v1}")
        tr = self.traj
        duration = float(tr.duration)
        dof = self.dof
        t = np.empty((dof, 7))
        j = np.empty((dof, 8))
        a = np.empty((dof, 8))
        v = np.empty((dof, 8))
        p = np.empty((dof, 8))
        for d, prof in enumerate(tr.profiles[0]):
            if prof.brake.duration > 0 or prof.accel.duration > 0:
                raise _RuckigFailure("ruckig used a brake/accel pre-trajectory (input outside limits?)")
            t[d] = prof.t
            j[d, :7] = prof.j
            a[d] = prof.a
            v[d] = prof.v
            p[d] = prof.p
        j[:, 7] = 0.0  # after the profile: hold (ruckig integrates with zero jerk)
        knots = np.zeros((dof, 9))
        knots[:, 1:8] = np.cumsum(t, axis=1)
        knots[:, 8] = np.maximum(duration, knots[:, 7])
        ext = tr.position_extrema
        pos_min = np.array([b.min for b in ext])
        pos_max = np.array([b.max for b in ext])
        return _Segment(duration, knots, p, v, a, j, pos_min, pos_max)


def _polyline_distances(q: np.ndarray, path: np.ndarray) -> np.ndarray:
    """(N,) Euclidean distance of each row of `q` (N, dof) to the polyline `path` (P, dof) [rad].

    Euclidean (exact through the orthogonal projection, and symmetric enough for the
    triangle inequalities the blend relies on); it bounds the L-inf distance from above.
    """
    if len(path) < 2:
        return np.linalg.norm(q - path[0], axis=1)
    a = path[:-1]  # (S, dof)
    d = np.diff(path, axis=0)
    dd = np.einsum("sd,sd->s", d, d)
    rel = q[:, None, :] - a[None, :, :]  # (N, S, dof)
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(dd > 0, np.einsum("nsd,sd->ns", rel, d) / dd, 0.0)
    lam = np.clip(lam, 0.0, 1.0)
    return np.linalg.norm(rel - lam[:, :, None] * d[None, :, :], axis=2).min(axis=1)


def _deviation(seg: _Segment, sub_path: np.ndarray) -> float:
    """Distance of the segment's motion from the stretch `sub_path` of the input path [rad].

    Sampled every <= `_DEVIATION_STEP`; `_plan_segments` adds the sampling error bound.
    """
    if seg.duration <= 0:
        return 0.0
    n = max(8, int(np.ceil(seg.duration / _DEVIATION_STEP)) + 1)
    ts = np.linspace(0.0, seg.duration, n)
    q = evaluate_pieces(seg.knots, seg.p, seg.v, seg.a, seg.j, ts)[0]
    return float(_polyline_distances(q, sub_path).max())


def _path_deviation(profile: PiecewiseJerkProfile, path: np.ndarray, times: np.ndarray) -> float:
    """Max over time of the distance from the motion to the polyline `path` [rad].

    Measured at `times` and every <= `_DEVIATION_STEP` (see `_polyline_distances`).
    """
    if len(path) < 2 or profile.duration == 0:
        return 0.0
    n = int(np.ceil(profile.duration / _DEVIATION_STEP)) + 1
    ts = np.union1d(times, np.linspace(0.0, profile.duration, n))
    return float(_polyline_distances(profile.evaluate(ts)[0], path).max())


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
        dist = _polyline_distances(w[a + 1 : b], w[[a, b]])
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
    segments: list[_Segment]
    velocities: np.ndarray
    duration: float


def _plan_segments(
    solver: _SegmentSolver,
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
    margin = 0.125 * float(np.linalg.norm(solver.amax_used)) * _DEVIATION_STEP**2
    tolerance = max(0.0, tolerance - margin)
    caps = np.zeros(k) if blend is None else blend.caps * level
    halvings = np.zeros(k, dtype=int)
    vel = np.zeros_like(w) if blend is None else blend.velocities(caps)
    segs: list[_Segment | None] = [None] * (k - 1)
    todo = set(range(k - 1))
    while todo:
        for i in sorted(todo):
            if vel[i].any() or vel[i + 1].any():
                seg = solver.solve(w[i], vel[i], w[i + 1], vel[i + 1])
                seg.deviation = _deviation(seg, sub_paths[i])
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
                raise _RuckigFailure(
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


def _assemble(plan: _Plan, w: np.ndarray) -> PiecewiseJerkProfile:
    """Concatenate segments into one profile, ending with the exact goal at rest."""
    dof = w.shape[1]
    knots, p, v, a, j = [], [], [], [], []
    offset = 0.0
    for seg in plan.segments:
        knots.append(np.minimum(seg.knots[:, :8], seg.duration) + offset)
        p.append(seg.p)
        v.append(seg.v)
        a.append(seg.a)
        j.append(seg.j)
        offset += seg.duration
    zeros = np.zeros((dof, 1))
    knots += [np.full((dof, 1), offset), np.full((dof, 1), offset)]
    p.append(w[-1][:, None])
    v.append(zeros)
    a.append(zeros)
    j.append(zeros)
    return PiecewiseJerkProfile(
        knots=np.concatenate(knots, axis=1),
        p0=np.concatenate(p, axis=1),
        v0=np.concatenate(v, axis=1),
        a0=np.concatenate(a, axis=1),
        j=np.concatenate(j, axis=1),
    )


# ---------------------------------------------------------------------------- public API
def time_parameterize(
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
    mode: Literal["blend", "exact", "along_path"] = "blend",
    deviation_tolerance: float = 0.05,
    stop_angle: float = np.deg2rad(100.0),
    velocity_scale: float = 1.0,
    acceleration_scale: float = 1.0,
    jerk_scale: float = 1.0,
    duration: float | None = None,
) -> TimingResult:
    """Time-parameterise a piecewise-linear joint path with ruckig (see the module docstring).

    Args:
        path: (K, dof) waypoints [rad], K >= 1; the first is the start, the last the goal.
        velocity_limits: (dof,) max |velocity| [rad/s] (or a scalar for all joints).
        acceleration_limits: (dof,) max |acceleration| [rad/s^2].
        jerk_limits: (dof,) max |jerk| [rad/s^3].
        dt: sample period of the returned trajectory [s] (default 1/60, the simulator's).
        joint_names: (dof,) names; default "joint_0", "joint_1", ...
        lower_limits: (dof,) lower position limits [rad]; None = unchecked.
        upper_limits: (dof,) upper position limits [rad]; None = unchecked.
        position_tolerance: waypoints may lie this far outside the position limits [rad]
            (a start a hair outside a limit is accepted); the motion is checked against
            the limits widened by the same amount.
        mode: "blend" (default, round corners, faster), "exact" (stop at every corner,
            stay on the straight segments) or "along_path" (one smooth motion along a
            spline through dense points: `time_parameterize_dense`, which gets
            `deviation_tolerance`; `stop_angle` is unused).
        deviation_tolerance: blend and along_path modes: max distance of the motion from
            the input path [rad] (joint-space Euclidean, which bounds the L-inf distance).
        stop_angle: blend mode: corners turning by more than this stop the motion [rad].
        velocity_scale: factor in (0, 1] applied to the velocity limits.
        acceleration_scale: factor in (0, 1] applied to the acceleration limits.
        jerk_scale: factor in (0, 1] applied to the jerk limits.
        duration: desired total time [s]; the fastest trajectory is stretched uniformly
            in time to it (rounded up to a multiple of `dt`). If it is shorter than the
            fastest feasible, the result has status DURATION_TOO_SHORT and
            `minimum_duration` says what is feasible.

    Returns:
        TimingResult (`success`, `status`, `trajectory`, `max_deviation`, ...).

    Raises:
        InvalidInputError: wrong shapes, non-finite values, non-positive limits, scales
            outside (0, 1], waypoints outside the position limits, unknown mode.
    """
    t_start = time.perf_counter()
    if mode not in ("blend", "exact", "along_path"):
        raise InvalidInputError(f"mode must be 'blend', 'exact' or 'along_path'; got {mode!r}")
    if not (np.isfinite(deviation_tolerance) and deviation_tolerance >= 0):
        raise InvalidInputError(f"deviation_tolerance must be finite and >= 0 [rad]; got {deviation_tolerance}")
    if mode == "along_path":
        return time_parameterize_dense(
            path, velocity_limits, acceleration_limits, jerk_limits, dt=dt, joint_names=joint_names,
            lower_limits=lower_limits, upper_limits=upper_limits, position_tolerance=position_tolerance,
            deviation_tolerance=deviation_tolerance, velocity_scale=velocity_scale,
            acceleration_scale=acceleration_scale, jerk_scale=jerk_scale, duration=duration,
        )
    w, vmax, amax, jmax, names, lower, upper = _check_inputs(
        path, velocity_limits, acceleration_limits, jerk_limits, dt, joint_names, lower_limits, upper_limits,
        position_tolerance, velocity_scale, acceleration_scale, jerk_scale, duration,
    )

    wp = _simplify(w)
    keep = np.arange(len(wp))
    if mode == "blend" and len(wp) > 2:
        # Dense paths (e.g. from trajectory optimisation): drop waypoints within half the
        # tolerance of their chord; the rest of the tolerance is for rounding corners.
        keep = _douglas_peucker(wp, 0.5 * deviation_tolerance)
    sub_paths = [wp[keep[i] : keep[i + 1] + 1] for i in range(len(keep) - 1)]
    wp = wp[keep]
    solver = _SegmentSolver(vmax, amax, jmax)

    def fail(status: TimingStatus, msg: str, min_dur: float = float("nan")) -> TimingResult:
        logger.info("time_parameterize failed: %s", msg)
        return TimingResult(
            False, status, None, mode, min_dur, float("nan"), wp, np.zeros_like(wp),
            np.zeros(max(len(wp) - 1, 0)), time.perf_counter() - t_start, msg,
        )

    # -- fastest plan for the mode
    try:
        if len(wp) == 1:
            best = _Plan([], np.zeros_like(wp), 0.0)
        else:
            levels = (0.0,) if mode == "exact" else _SPEED_LEVELS
            blend = (
                _blend_data(wp, solver.vmax_used, solver.amax_used, stop_angle, 0.5 * deviation_tolerance)
                if mode == "blend"
                else None
            )
            best = None
            for level in levels:
                plan = _plan_segments(
                    solver, wp, sub_paths, None if level == 0.0 else blend, level, lower, upper,
                    deviation_tolerance,
                )
                if best is None or plan.duration < best.duration:
                    best = plan
            assert best is not None
    except _RuckigFailure as e:
        return fail(TimingStatus.RUCKIG_FAIL, str(e))

    # -- stretch to the requested duration and to a whole number of dt
    t_min = best.duration
    if duration is not None and duration < t_min * (1 - 1e-12):
        return fail(
            TimingStatus.DURATION_TOO_SHORT,
            f"requested duration {duration:.4f} s is shorter than the fastest feasible {t_min:.4f} s",
            t_min,
        )
    target = t_min if duration is None else float(duration)
    n_steps = int(np.ceil(target / dt - 1e-9))
    profile = _assemble(best, wp)
    factor = 1.0
    if t_min > 0:
        total = max(n_steps, 1) * dt
        factor = total / t_min
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
    if not (np.array_equal(traj.positions[0], w[0]) and np.array_equal(traj.positions[-1], w[-1])):
        problems.append("endpoints differ from the path's")
    if np.any(traj.velocities[[0, -1]] != 0) or np.any(traj.accelerations[[0, -1]] != 0):
        problems.append("not at rest at both ends")
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


# ---------------------------------------------------------------------------- dense paths
class _Rest1D:
    """Rest-to-rest 1-D ruckig problems from 0 to `length` (the time scaling `s(t)`)."""

    def __init__(self, length: float):
        self.length = length
        self.otg = ruckig.Ruckig(1)
        self.inp = ruckig.InputParameter(1)
        for name in ("current_position", "current_velocity", "current_acceleration", "target_velocity",
                     "target_acceleration"):
            setattr(self.inp, name, [0.0])
        self.inp.target_position = [length]
        self.traj = ruckig.Trajectory(1)

    def solve(self, v: float, a: float, j: float) -> float | None:
        """Duration [s] with limits (v, a, j) on s-dot, s-ddot, s-dddot (shrunk by the margin), or None."""
        self.inp.max_velocity = [v * (1 - _LIMIT_MARGIN)]
        self.inp.max_acceleration = [a * (1 - _LIMIT_MARGIN)]
        self.inp.max_jerk = [j * (1 - _LIMIT_MARGIN)]
        try:
            res = self.otg.calculate(self.inp, self.traj)
        except ruckig.RuckigError:
            return None
        if res != ruckig.Result.Working:
            return None
        return float(self.traj.duration)

    def profile(self, v: float, a: float, j: float) -> PiecewiseJerkProfile:
        """The 1-D profile for these limits, ending exactly at `length` at rest."""
        if self.solve(v, a, j) is None:
            raise _RuckigFailure(f"ruckig failed on the path parameter (L={self.length}, V={v}, A={a}, J={j})")
        prof = self.traj.profiles[0][0]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise _RuckigFailure("ruckig used a brake/accel pre-trajectory on a rest-to-rest problem")
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
        dist[i] = _polyline_distances(q[i], w[keep[i] : keep[i + 1] + 1]).max()
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
    if deviation_tolerance is not None and not (np.isfinite(deviation_tolerance) and deviation_tolerance >= 0):
        raise InvalidInputError(
            f"deviation_tolerance must be finite and >= 0 [rad] (or None); got {deviation_tolerance}"
        )
    w, vmax, amax, jmax, names, lower, upper = _check_inputs(
        path, velocity_limits, acceleration_limits, jerk_limits, dt, joint_names, lower_limits, upper_limits,
        position_tolerance, velocity_scale, acceleration_scale, jerk_scale, duration,
    )
    mode = "along_path"
    keep = _merge_close(w)
    wp = w[keep]

    def fail(status: TimingStatus, msg: str, min_dur: float = float("nan"), dev: float = float("nan")) -> TimingResult:
        logger.info("time_parameterize_dense failed: %s", msg)
        return TimingResult(
            False, status, None, mode, min_dur, dev, wp, np.zeros_like(wp), np.zeros(max(len(wp) - 1, 0)),
            time.perf_counter() - t_start, msg,
        )

    if len(wp) == 1:  # nothing to move: a still trajectory at the (exact) end point
        still = time_parameterize(
            w[-1:], vmax, amax, jmax, dt=dt, joint_names=names, mode="exact", duration=duration,
        )
        return replace(still, mode=mode, waypoints=wp, compute_time=time.perf_counter() - t_start)

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
        except _RuckigFailure as e:
            return fail(TimingStatus.RUCKIG_FAIL, str(e), dev=deviation)
        t_min = timing.duration
        if duration is not None and duration < t_min * (1 - 1e-12):
            return fail(
                TimingStatus.DURATION_TOO_SHORT,
                f"requested duration {duration:.4f} s is shorter than the fastest feasible {t_min:.4f} s",
                t_min, deviation,
            )
        target = t_min if duration is None else float(duration)
        n_steps = max(int(np.ceil(target / dt - 1e-9)), 1)
        factor = n_steps * dt / t_min
        profile = PathProfile(spline, timing).time_scaled(factor)
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
    if not (np.array_equal(traj.positions[0], w[0]) and np.array_equal(traj.positions[-1], w[-1])):
        return fail(TimingStatus.LIMIT_VIOLATION, "verification failed: endpoints differ from the path's", t_min,
                    deviation)
    if np.any(traj.velocities[[0, -1]] != 0) or np.any(traj.accelerations[[0, -1]] != 0):
        return fail(TimingStatus.LIMIT_VIOLATION, "verification failed: not at rest at both ends", t_min, deviation)

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


def time_parameterize_for_robot(
    path: np.ndarray | Sequence[Sequence[float]], config: RobotConfig, **options: Any
) -> TimingResult:
    """`time_parameterize` with the limits and joint names of a `RobotConfig`.

    Args:
        path: (K, dof) waypoints of the robot's arm joints [rad].
        config: `manip.RobotConfig` (velocity, acceleration, jerk and position limits,
            `arm_joints`).
        **options: any keyword of `time_parameterize` (overrides the config's values).
    """
    kwargs = dict(
        joint_names=list(config.arm_joints),
        lower_limits=config.lower_limits,
        upper_limits=config.upper_limits,
    )
    kwargs.update(options)
    return time_parameterize(
        path, config.velocity_limits, config.acceleration_limits, config.jerk_limits, **kwargs
    )
