"""`Trajectory`: a timed joint-space motion, sampled every `dt` and exact in between.

A trajectory produced by `manip.timing.time_parameterize` carries its underlying
piecewise-constant-jerk profile (`PiecewiseJerkProfile`, one cubic polynomial per phase
and joint, as computed by ruckig), so `at_time` and `resample` are exact rather than
interpolated. `time_parameterize_dense` gives a `PathProfile` instead: a cubic spline
`q(s)` through a dense path traversed by a 1-D constant-jerk profile `s(t)`, equally exact.
A trajectory built from samples alone (e.g. from another planner) falls
back to interpolation of its samples (documented on `Trajectory.at_time`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Sequence

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError

# Relative tolerance used to decide that two times are "the same" (sample grids).
_TIME_EPS = 1e-9
# PathProfile.extrema evaluates the motion at least this often [s].
_EXTREMA_STEP = 2.5e-4


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)  # copy
    a.setflags(write=False)
    return a


def _quadratic_roots(qa: np.ndarray, qb: np.ndarray, qc: np.ndarray) -> list[np.ndarray]:
    """Elementwise real roots of qa u^2 + qb u + qc = 0 (linear when qa = 0).

    Returns two arrays; entries without a (second) real root are -1 or non-finite, which
    callers drop by keeping finite roots inside their interval only.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = qb * qb - 4.0 * qa * qc
        sq = np.sqrt(np.maximum(disc, 0.0))
        quad = (qa != 0.0) & (disc >= 0.0)
        return [
            np.where(quad, (-qb + sq) / (2.0 * qa), np.where(qb != 0.0, -qc / qb, -1.0)),
            np.where(quad, (-qb - sq) / (2.0 * qa), -1.0),
        ]


def evaluate_pieces(
    knots: np.ndarray, p0: np.ndarray, v0: np.ndarray, a0: np.ndarray, j: np.ndarray, ts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Evaluate per-joint constant-jerk pieces (see `PiecewiseJerkProfile`) at times `ts`.

    Args:
        knots: (dof, M + 1) piece start times [s].
        p0, v0, a0, j: (dof, M) piece start states and jerks.
        ts: (N,) times [s] (not clamped here).

    Returns:
        (q, qd, qdd, qddd), each (N, dof); jerk is right-continuous.
    """
    dof, m = p0.shape
    if dof * ts.size * m <= 200_000:  # small: one broadcast comparison beats a loop of searchsorted
        idx = (ts[None, :, None] >= knots[:, None, 1:m]).sum(axis=2)
    else:
        idx = np.empty((dof, ts.size), dtype=int)
        for d in range(dof):
            idx[d] = np.searchsorted(knots[d], ts, side="right") - 1
        np.clip(idx, 0, m - 1, out=idx)
    rows = np.arange(dof)[:, None]
    tau = ts[None, :] - knots[rows, idx]
    jj = j[rows, idx]
    aa = a0[rows, idx]
    vv = v0[rows, idx]
    q = p0[rows, idx] + tau * (vv + tau * (aa / 2.0 + tau * jj / 6.0))
    qd = vv + tau * (aa + tau * jj / 2.0)
    qdd = aa + tau * jj
    return q.T, qd.T, qdd.T, jj.T.copy()


@dataclass(frozen=True, eq=False)
class PiecewiseJerkProfile:
    """Per-joint piecewise cubic motion with constant jerk on each piece (ruckig's form).

    Joint `d` has pieces `k = 0..M-1` starting at `knots[d, k]` [s] with start state
    `p0[d, k]` [rad], `v0[d, k]` [rad/s], `a0[d, k]` [rad/s^2] and constant jerk
    `j[d, k]` [rad/s^3]; on `tau = t - knots[d, k]`:
    `q = p0 + v0 tau + a0 tau^2 / 2 + j tau^3 / 6`. `knots[d, M]` is the end time.
    Joints may have different knots; unused trailing pieces have zero length. After the
    end the motion holds the final state with zero jerk (this final state is stored as
    the last piece, so `knots[:, -2] == knots[:, -1] == duration`).

    Args:
        knots: (dof, M + 1) non-decreasing piece start times [s]; column 0 is 0.
        p0: (dof, M) piece start positions [rad].
        v0: (dof, M) piece start velocities [rad/s].
        a0: (dof, M) piece start accelerations [rad/s^2].
        j: (dof, M) piece jerks [rad/s^3].
    """

    knots: np.ndarray
    p0: np.ndarray
    v0: np.ndarray
    a0: np.ndarray
    j: np.ndarray

    def __post_init__(self) -> None:
        knots = np.asarray(self.knots, dtype=float)
        if knots.ndim != 2 or knots.shape[1] < 2:
            raise InvalidInputError(f"PiecewiseJerkProfile.knots must be (dof, M + 1); got {knots.shape}")
        shape = (knots.shape[0], knots.shape[1] - 1)
        for name in ("p0", "v0", "a0", "j"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.shape != shape:
                raise InvalidInputError(f"PiecewiseJerkProfile.{name} must have shape {shape}; got {a.shape}")
            object.__setattr__(self, name, _readonly(a))
        if np.any(np.diff(knots, axis=1) < 0):
            raise InvalidInputError("PiecewiseJerkProfile.knots must be non-decreasing along each row")
        object.__setattr__(self, "knots", _readonly(knots))

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.knots.shape[0])

    @property
    def duration(self) -> float:
        """End time [s] (the largest knot)."""
        return float(self.knots[:, -1].max())

    def evaluate(self, t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Exact state at times `t`, clamped to [0, duration].

        Jerk is right-continuous: at a knot it is the jerk of the piece that starts there,
        and at `t >= duration` it is 0 (the motion has ended).

        Args:
            t: scalar or (N,) times [s].

        Returns:
            (q, qd, qdd, qddd): each (dof,) for scalar `t`, else (N, dof).
        """
        scalar = np.ndim(t) == 0
        ts = np.clip(np.atleast_1d(np.asarray(t, dtype=float)), 0.0, self.duration)
        out = evaluate_pieces(self.knots, self.p0, self.v0, self.a0, self.j, ts)
        if scalar:
            return tuple(o[0] for o in out)  # type: ignore[return-value]
        return out

    def time_scaled(self, factor: float) -> PiecewiseJerkProfile:
        """The same path traversed `factor` times slower (`factor` > 0).

        q'(t) = q(t / factor): velocities scale by 1/factor, accelerations by
        1/factor^2, jerks by 1/factor^3, so a factor >= 1 never breaks a limit.
        """
        if not (np.isfinite(factor) and factor > 0):
            raise InvalidInputError(f"time scale factor must be finite and > 0; got {factor}")
        return PiecewiseJerkProfile(
            knots=self.knots * factor,
            p0=self.p0,
            v0=self.v0 / factor,
            a0=self.a0 / factor**2,
            j=self.j / factor**3,
        )

    def extrema(self) -> dict[str, np.ndarray]:
        """Exact per-joint extremes over the whole profile (analytic, not sampled).

        Returns:
            dict with `position_min`, `position_max` [rad], `max_abs_velocity` [rad/s],
            `max_abs_acceleration` [rad/s^2], `max_abs_jerk` [rad/s^3], each (dof,).
            Jerk counts only pieces of non-zero length.
        """
        h = np.diff(self.knots, axis=1)
        p0, v0, a0, j = self.p0, self.v0, self.a0, self.j
        live = h > 0
        # acceleration is linear on a piece
        a1 = a0 + j * h
        max_a = np.maximum(np.abs(a0), np.where(live, np.abs(a1), 0.0)).max(axis=1)
        # velocity is quadratic: ends and the stationary point tau* = -a0 / j
        v1 = v0 + h * (a0 + h * j / 2.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ts = np.where(j != 0.0, -a0 / j, -1.0)
        inside = live & (ts > 0) & (ts < h)
        vs = np.where(inside, v0 + ts * (a0 + ts * j / 2.0), 0.0)
        max_v = np.maximum.reduce([np.abs(v0), np.where(live, np.abs(v1), 0.0), np.abs(vs)]).max(axis=1)
        # position is cubic: ends and the roots of the velocity in (0, h)
        p1 = p0 + h * (v0 + h * (a0 / 2.0 + h * j / 6.0))
        cands = [p0, np.where(live, p1, p0)]
        qa, qb, qc = j / 2.0, a0, v0
        roots = _quadratic_roots(qa, qb, qc)
        for r in roots:
            ok = live & np.isfinite(r) & (r > 0) & (r < h)
            rr = np.where(ok, r, 0.0)
            pr = p0 + rr * (v0 + rr * (a0 / 2.0 + rr * j / 6.0))
            cands.append(np.where(ok, pr, p0))
        pc = np.stack(cands)
        max_j = np.where(live, np.abs(j), 0.0).max(axis=1)
        return {
            "position_min": pc.min(axis=(0, 2)),
            "position_max": pc.max(axis=(0, 2)),
            "max_abs_velocity": max_v,
            "max_abs_acceleration": max_a,
            "max_abs_jerk": max_j,
        }

@dataclass(frozen=True, eq=False)
class CubicSplinePath:
    """A C2 joint-space curve `q(s)`: one cubic polynomial per piece and joint.

    Piece `i` covers `s` in `[breaks[i], breaks[i + 1]]`; on `u = s - breaks[i]`:
    `q = c0 + c1 u + c2 u^2 + c3 u^3` (coefficient `ck` is `coeffs[k, i, :]`). Built by
    `CubicSplinePath.fit` through a dense path, `s` being the cumulative joint-space
    (Euclidean) chord length [rad].

    Args:
        breaks: (P + 1,) increasing curve parameters [rad]; breaks[0] == 0.
        coeffs: (4, P, dof) polynomial coefficients.
        end: (dof,) the curve's end point, returned exactly for `s >= breaks[-1]`.
    """

    breaks: np.ndarray
    coeffs: np.ndarray
    end: np.ndarray

    def __post_init__(self) -> None:
        breaks = np.asarray(self.breaks, dtype=float)
        coeffs = np.asarray(self.coeffs, dtype=float)
        end = np.asarray(self.end, dtype=float)
        if breaks.ndim != 1 or breaks.size < 2 or breaks[0] != 0.0 or np.any(np.diff(breaks) <= 0):
            raise InvalidInputError("CubicSplinePath.breaks must be (P + 1,), P >= 1, start at 0 and increase")
        if coeffs.ndim != 3 or coeffs.shape[:2] != (4, breaks.size - 1):
            raise InvalidInputError(
                f"CubicSplinePath.coeffs must have shape (4, {breaks.size - 1}, dof); got {coeffs.shape}"
            )
        if end.shape != (coeffs.shape[2],):
            raise InvalidInputError(f"CubicSplinePath.end must have shape ({coeffs.shape[2]},); got {end.shape}")
        if not (np.all(np.isfinite(coeffs)) and np.all(np.isfinite(end))):
            raise InvalidInputError("CubicSplinePath has non-finite coefficients")
        object.__setattr__(self, "breaks", _readonly(breaks))
        object.__setattr__(self, "coeffs", _readonly(coeffs))
        object.__setattr__(self, "end", _readonly(end))

    @classmethod
    def fit(cls, points: np.ndarray) -> CubicSplinePath:
        """The not-a-knot cubic spline through `points`, parameterised by chord length.

        Each joint is interpolated separately over the cumulative Euclidean chord length
        `s`. Not-a-knot ends (third derivative continuous at the second and second-to-last
        points) keep the derivatives small near the ends, unlike a natural spline, which
        forces zero curvature there. Three points give a parabola, two a line.

        Args:
            points: (K, dof) points [rad], K >= 2, consecutive points distinct.

        Returns:
            the spline; it passes exactly through every point.
        """
        y = np.asarray(points, dtype=float)
        if y.ndim != 2 or y.shape[0] < 2:
            raise InvalidInputError(f"CubicSplinePath.fit needs (K, dof) points with K >= 2; got {y.shape}")
        h = np.linalg.norm(np.diff(y, axis=0), axis=1)
        if np.any(h <= 0):
            raise InvalidInputError("CubicSplinePath.fit needs distinct consecutive points")
        n, dof = h.size, y.shape[1]
        slope = np.diff(y, axis=0) / h[:, None]  # (n, dof)
        m = np.zeros((n + 1, dof))  # second derivatives at the points
        if n == 2:
            m[:] = 2.0 * (slope[1] - slope[0]) / (h[0] + h[1])  # the parabola
        elif n >= 3:
            a = np.zeros((n + 1, n + 1))
            r = np.zeros((n + 1, dof))
            i = np.arange(1, n)
            a[i, i - 1] = h[:-1]
            a[i, i] = 2.0 * (h[:-1] + h[1:])
            a[i, i + 1] = h[1:]
            r[1:n] = 6.0 * (slope[1:] - slope[:-1])
            # not-a-knot: (m1 - m0) / h0 == (m2 - m1) / h1, and the same at the other end
            a[0, :3] = [h[1], -(h[0] + h[1]), h[0]]
            a[n, n - 2 :] = [h[n - 1], -(h[n - 2] + h[n - 1]), h[n - 2]]
            m = np.linalg.solve(a, r)
        hc = h[:, None]
        coeffs = np.stack(
            [
                y[:-1],
                slope - hc * (2.0 * m[:-1] + m[1:]) / 6.0,
                m[:-1] / 2.0,
                (m[1:] - m[:-1]) / (6.0 * hc),
            ]
        )
        breaks = np.concatenate([[0.0], np.cumsum(h)])
        return cls(breaks, coeffs, y[-1].copy())

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.coeffs.shape[2])

    @property
    def length(self) -> float:
        """Parameter range `L` = breaks[-1] [rad] (the chord length of the fitted points)."""
        return float(self.breaks[-1])

    def evaluate(self, s: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Curve and its derivatives with respect to `s`, at `s` clamped to [0, L].

        Args:
            s: scalar or (N,) curve parameters [rad].

        Returns:
            (q, dq/ds, d2q/ds2, d3q/ds3), each (N, dof) (a scalar `s` counts as N = 1);
            the third derivative is right-continuous, and `q` is exactly `end` for `s >= L`.
        """
        s = np.clip(np.atleast_1d(np.asarray(s, dtype=float)), 0.0, self.length)
        p = self.coeffs.shape[1]
        i = np.clip(np.searchsorted(self.breaks, s, side="right") - 1, 0, p - 1)
        u = (s - self.breaks[i])[:, None]
        c0, c1, c2, c3 = (self.coeffs[k, i] for k in range(4))
        q = c0 + u * (c1 + u * (c2 + u * c3))
        q[s >= self.length] = self.end
        return q, c1 + u * (2.0 * c2 + 3.0 * u * c3), 2.0 * c2 + 6.0 * u * c3, 6.0 * c3

    def piece_bounds(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Exact per-piece maxima of |dq/ds|, |d2q/ds2|, |d3q/ds3|, each (P, dof)."""
        _, c1, c2, c3 = self.coeffs
        h = np.diff(self.breaks)[:, None]
        d1_end = c1 + h * (2.0 * c2 + 3.0 * h * c3)
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(c3 != 0.0, -c2 / (3.0 * c3), -1.0)  # stationary point of dq/ds
        inside = (u > 0) & (u < h)
        uu = np.where(inside, u, 0.0)
        d1_mid = np.where(inside, c1 + uu * (2.0 * c2 + 3.0 * uu * c3), 0.0)
        m1 = np.maximum.reduce([np.abs(c1), np.abs(d1_end), np.abs(d1_mid)])
        m2 = np.maximum(np.abs(2.0 * c2), np.abs(2.0 * c2 + 6.0 * h * c3))
        m3 = np.abs(6.0 * c3)
        return m1, m2, m3

    def position_range(self) -> tuple[np.ndarray, np.ndarray]:
        """((dof,), (dof,)) exact smallest and largest position of each joint over [0, L] [rad]."""
        c0, c1, c2, c3 = self.coeffs
        h = np.diff(self.breaks)[:, None]
        cands = [c0, c0 + h * (c1 + h * (c2 + h * c3))]
        # roots of dq/ds = c1 + 2 c2 u + 3 c3 u^2 inside the piece
        qa, qb, qc = 3.0 * c3, 2.0 * c2, c1
        roots = _quadratic_roots(qa, qb, qc)
        for r in roots:
            ok = np.isfinite(r) & (r > 0) & (r < h)
            rr = np.where(ok, r, 0.0)
            cands.append(np.where(ok, c0 + rr * (c1 + rr * (c2 + rr * c3)), c0))
        pc = np.stack(cands)
        return np.minimum(pc.min(axis=(0, 1)), self.end), np.maximum(pc.max(axis=(0, 1)), self.end)


@dataclass(frozen=True, eq=False)
class PathProfile:
    """A motion along a fixed curve: `q(t) = path(s(t))`, `s(t)` a 1-D constant-jerk profile.

    Made by `manip.timing.time_parameterize_dense`. The joint derivatives follow from the
    chain rule (primes are derivatives in `s`): `qd = q' sd`,
    `qdd = q' sdd + q'' sd^2`, `qddd = q' sddd + 3 q'' sd sdd + q''' sd^3`. It offers the
    interface of `PiecewiseJerkProfile` (`dof`, `duration`, `evaluate`, `time_scaled`,
    `extrema`), so a `Trajectory` carrying it evaluates the motion exactly.

    Args:
        path: the curve `q(s)`, s in [0, L].
        timing: 1-D profile `s(t)` (dof 1) from 0 to `path.length`, at rest at both ends,
            with `s` non-decreasing.
    """

    path: CubicSplinePath
    timing: PiecewiseJerkProfile

    def __post_init__(self) -> None:
        if not isinstance(self.path, CubicSplinePath):
            raise InvalidInputError("PathProfile.path must be a CubicSplinePath")
        if not isinstance(self.timing, PiecewiseJerkProfile) or self.timing.dof != 1:
            raise InvalidInputError("PathProfile.timing must be a PiecewiseJerkProfile with one degree of freedom")

    @property
    def dof(self) -> int:
        """Number of joints."""
        return self.path.dof

    @property
    def duration(self) -> float:
        """End time [s]."""
        return self.timing.duration

    def evaluate(self, t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Exact state at times `t`, clamped to [0, duration] (see `PiecewiseJerkProfile.evaluate`).

        Args:
            t: scalar or (N,) times [s].

        Returns:
            (q, qd, qdd, qddd): each (dof,) for scalar `t`, else (N, dof).
        """
        scalar = np.ndim(t) == 0
        s, sd, sdd, sddd = self.timing.evaluate(np.atleast_1d(np.asarray(t, dtype=float)))
        q, d1, d2, d3 = self.path.evaluate(s[:, 0])
        qd = d1 * sd
        qdd = d1 * sdd + d2 * sd**2
        qddd = d1 * sddd + 3.0 * d2 * sd * sdd + d3 * sd**3
        out = (q, qd, qdd, qddd)
        if scalar:
            return tuple(o[0] for o in out)  # type: ignore[return-value]
        return out

    def time_scaled(self, factor: float) -> PathProfile:
        """The same path traversed `factor` times slower (see `PiecewiseJerkProfile.time_scaled`)."""
        return PathProfile(self.path, self.timing.time_scaled(factor))

    def dense_times(self, step: float = _EXTREMA_STEP) -> np.ndarray:
        """(N,) times [s] every <= `step` [s] plus every knot of the timing profile."""
        n = max(2, int(np.ceil(self.duration / step)) + 1)
        return np.union1d(np.linspace(0.0, self.duration, n), self.timing.knots[0])

    @cached_property
    def _extrema(self) -> dict[str, np.ndarray]:
        lo, hi = self.path.position_range()
        _, qd, qdd, qddd = self.evaluate(self.dense_times())
        return {
            "position_min": lo,
            "position_max": hi,
            "max_abs_velocity": np.abs(qd).max(axis=0),
            "max_abs_acceleration": np.abs(qdd).max(axis=0),
            "max_abs_jerk": np.abs(qddd).max(axis=0),
        }

    def extrema(self) -> dict[str, np.ndarray]:
        """Per-joint extremes (the keys of `PiecewiseJerkProfile.extrema`).

        Positions are exact (the range of the curve, which `s` covers entirely);
        velocity, acceleration and jerk maxima are the largest values at times every
        <= h = 0.25 ms and at every knot of the timing profile, not analytic: with `J` the
        largest jerk, the velocity maximum is within `J h^2 / 8` (about 4e-6 rad/s for
        J = 500 rad/s^3) and the acceleration maximum within `J h / 2` of the true one.
        (The timing guarantees the limits by construction, not by these values.)
        """
        return {k: v.copy() for k, v in self._extrema.items()}


def sample_times(duration: float, dt: float) -> np.ndarray:
    """The sample grid of a trajectory: 0, dt, 2 dt, ..., ending exactly at `duration`.

    If `duration` is not a multiple of `dt` (within 1e-9 relative), the last step is
    shorter than `dt`.

    Args:
        duration: total time [s], >= 0.
        dt: sample period [s], > 0.

    Returns:
        (T,) times [s], T >= 1.
    """
    if not (np.isfinite(dt) and dt > 0):
        raise InvalidInputError(f"dt must be finite and > 0 [s]; got {dt}")
    if not (np.isfinite(duration) and duration >= 0):
        raise InvalidInputError(f"duration must be finite and >= 0 [s]; got {duration}")
    n = int(np.ceil(duration / dt - _TIME_EPS))
    times = np.arange(n + 1, dtype=float) * dt
    times[-1] = duration
    return times


def _as_matrix(values: Any, name: str, shape: tuple[int, int]) -> np.ndarray:
    a = np.array(values, dtype=float)
    if a.shape != shape:
        raise InvalidInputError(f"Trajectory.{name} must have shape {shape} (T, dof); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"Trajectory.{name} has non-finite entries")
    return _readonly(a)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A timed joint-space trajectory sampled every `dt`, starting at t = 0.

    Arrays are read-only copies. `times[-1] == duration`; all steps equal `dt` except
    possibly the last, which may be shorter.

    Args:
        times: (T,) sample times [s], starting at 0, increasing.
        positions: (T, dof) joint positions [rad].
        velocities: (T, dof) joint velocities [rad/s].
        accelerations: (T, dof) joint accelerations [rad/s^2].
        jerks: (T, dof) joint jerks [rad/s^3] (right-continuous values of the profile:
            at a sample that falls on a jerk switch, the jerk that starts there; 0 at the
            final sample, where the motion has ended).
        dt: sample period [s].
        joint_names: (dof,) names of the joints, in column order.
        profile: the exact motion the samples were taken from (a `PiecewiseJerkProfile`
            from `time_parameterize`, or a `PathProfile` from `time_parameterize_dense`),
            or None for a trajectory known only by its samples.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    jerks: np.ndarray
    dt: float
    joint_names: tuple[str, ...]
    profile: PiecewiseJerkProfile | PathProfile | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        times = np.array(self.times, dtype=float)
        if times.ndim != 1 or times.size < 1:
            raise InvalidInputError(f"Trajectory.times must have shape (T,), T >= 1; got {times.shape}")
        if not np.all(np.isfinite(times)):
            raise InvalidInputError("Trajectory.times has non-finite entries")
        dt = float(self.dt)
        if not (np.isfinite(dt) and dt > 0):
            raise InvalidInputError(f"Trajectory.dt must be finite and > 0 [s]; got {self.dt}")
        if times[0] != 0.0:
            raise InvalidInputError(f"Trajectory.times must start at 0; got {times[0]}")
        steps = np.diff(times)
        if np.any(steps <= 0):
            raise InvalidInputError("Trajectory.times must be strictly increasing")
        tol = _TIME_EPS * max(1.0, float(times[-1])) + 1e-12
        if steps.size and (np.any(np.abs(steps[:-1] - dt) > tol) or steps[-1] > dt + tol):
            raise InvalidInputError(
                f"Trajectory.times must be spaced by dt = {dt} s (the last step may be shorter); "
                f"got steps in [{steps.min()}, {steps.max()}]"
            )
        names = tuple(str(n) for n in self.joint_names)
        pos = np.array(self.positions, dtype=float)
        if pos.ndim != 2 or pos.shape[0] != times.size:
            raise InvalidInputError(
                f"Trajectory.positions must have shape (T, dof) = ({times.size}, dof); got {pos.shape}"
            )
        shape = (times.size, pos.shape[1])
        if len(names) != shape[1]:
            raise InvalidInputError(
                f"Trajectory.joint_names has {len(names)} names for {shape[1]} joints: {names}"
            )
        if len(set(names)) != len(names):
            raise InvalidInputError(f"Trajectory.joint_names has duplicates: {names}")
        object.__setattr__(self, "times", _readonly(times))
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "joint_names", names)
        for name in ("positions", "velocities", "accelerations", "jerks"):
            object.__setattr__(self, name, _as_matrix(getattr(self, name), name, shape))
        if self.profile is not None:
            if not isinstance(self.profile, (PiecewiseJerkProfile, PathProfile)) or self.profile.dof != shape[1]:
                raise InvalidInputError(
                    f"Trajectory.profile must be a PiecewiseJerkProfile or PathProfile with {shape[1]} joints"
                )
            if abs(self.profile.duration - times[-1]) > tol:
                raise InvalidInputError(
                    f"Trajectory.profile lasts {self.profile.duration} s but the samples end at {times[-1]} s"
                )

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_profile(
        cls, profile: PiecewiseJerkProfile | PathProfile, dt: float, joint_names: Sequence[str]
    ) -> Trajectory:
        """Sample an exact profile every `dt` (last sample at its end).

        Args:
            profile: the motion.
            dt: sample period [s].
            joint_names: (dof,) joint names.
        """
        times = sample_times(profile.duration, dt)
        q, qd, qdd, qddd = profile.evaluate(times)
        return cls(times, q, qd, qdd, qddd, dt, tuple(joint_names), profile)

    # ------------------------------------------------------------------ properties
    @property
    def duration(self) -> float:
        """Total time [s] (= times[-1])."""
        return float(self.times[-1])

    @property
    def dof(self) -> int:
        """Number of joints."""
        return int(self.positions.shape[1])

    @property
    def num_samples(self) -> int:
        """Number of samples T."""
        return int(self.times.size)

    @property
    def start(self) -> np.ndarray:
        """(dof,) first configuration [rad]."""
        return self.positions[0]

    @property
    def goal(self) -> np.ndarray:
        """(dof,) last configuration [rad]."""
        return self.positions[-1]

    # ------------------------------------------------------------------ evaluation
    def at_time(self, t: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint state at time `t`, clamped to [0, duration].

        Exact (from the trajectory's profile) when the trajectory has one;
        otherwise positions are cubic Hermite interpolated from the sampled positions and
        velocities, and velocities/accelerations linearly interpolated.

        Args:
            t: scalar or (N,) times [s]; values outside [0, duration] are clamped (the
                robot is at rest at both ends, so this is the physical state).

        Returns:
            (q, qd, qdd): each (dof,) for scalar `t`, else (N, dof), in [rad], [rad/s],
            [rad/s^2].
        """
        t_arr = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(t_arr)):
            raise InvalidInputError(f"at_time needs finite times; got {t}")
        if self.profile is not None:
            q, qd, qdd, _ = self.profile.evaluate(t_arr)
            return q, qd, qdd
        return self._interpolate(t_arr)

    def _interpolate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        scalar = t.ndim == 0
        ts = np.clip(np.atleast_1d(t), 0.0, self.duration)
        if self.times.size == 1:
            reps = (ts.size, 1)
            out = tuple(np.tile(a[0], reps) for a in (self.positions, self.velocities, self.accelerations))
        else:
            i = np.clip(np.searchsorted(self.times, ts, side="right") - 1, 0, self.times.size - 2)
            h = (self.times[i + 1] - self.times[i])[:, None]
            s = ((ts - self.times[i])[:, None]) / h
            p0, p1 = self.positions[i], self.positions[i + 1]
            m0, m1 = self.velocities[i] * h, self.velocities[i + 1] * h
            h00 = 2 * s**3 - 3 * s**2 + 1
            h10 = s**3 - 2 * s**2 + s
            h01 = -2 * s**3 + 3 * s**2
            h11 = s**3 - s**2
            q = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1
            qd = (1 - s) * self.velocities[i] + s * self.velocities[i + 1]
            qdd = (1 - s) * self.accelerations[i] + s * self.accelerations[i + 1]
            out = (q, qd, qdd)
        if scalar:
            return tuple(o[0] for o in out)  # type: ignore[return-value]
        return out  # type: ignore[return-value]

    def resample(self, dt: float) -> Trajectory:
        """The same motion sampled every `dt` [s] (same duration; last step may be shorter).

        Exact when the trajectory has a profile; otherwise interpolated as in `at_time`
        (jerks then come from finite differences of the interpolated accelerations).
        """
        if self.profile is not None:
            return Trajectory.from_profile(self.profile, dt, self.joint_names)
        times = sample_times(self.duration, dt)
        q, qd, qdd = self._interpolate(times)
        jerk = np.zeros_like(qdd)
        if times.size > 1:
            jerk[:-1] = np.diff(qdd, axis=0) / np.diff(times)[:, None]
        return Trajectory(times, q, qd, qdd, jerk, dt, self.joint_names, None)

    # ------------------------------------------------------------------ quality measures
    def path_length(self) -> float:
        """Sum of joint-space Euclidean step lengths between samples [rad]."""
        return float(np.linalg.norm(np.diff(self.positions, axis=0), axis=1).sum())

    def _extreme(self, key: str, samples: np.ndarray) -> np.ndarray:
        if self.profile is not None:
            return self.profile.extrema()[key]
        return np.abs(samples).max(axis=0)

    def max_abs_velocity(self) -> np.ndarray:
        """(dof,) largest |velocity| [rad/s] (exact over the profile when present, else over samples)."""
        return self._extreme("max_abs_velocity", self.velocities)

    def max_abs_acceleration(self) -> np.ndarray:
        """(dof,) largest |acceleration| [rad/s^2] (exact over the profile when present)."""
        return self._extreme("max_abs_acceleration", self.accelerations)

    def max_abs_jerk(self) -> np.ndarray:
        """(dof,) largest |jerk| [rad/s^3] (exact over the profile when present)."""
        return self._extreme("max_abs_jerk", self.jerks)

    def position_range(self) -> tuple[np.ndarray, np.ndarray]:
        """((dof,), (dof,)) smallest and largest position of each joint [rad] (exact over the profile when present)."""
        if self.profile is not None:
            e = self.profile.extrema()
            return e["position_min"], e["position_max"]
        return self.positions.min(axis=0), self.positions.max(axis=0)

    # ------------------------------------------------------------------ bridges
    def joint_indices_for(self, robot: Any) -> np.ndarray:
        """(dof,) indices of `joint_names` among a robot's degrees of freedom.

        `robot` is duck-typed: it has a `dof_names` sequence (Isaac's `Articulation` and
        `manip.sim` robots do) and/or a `get_dof_index(name)` method.

        Raises:
            UnknownNameError: a joint of the trajectory is not a DoF of the robot (the
                message lists the robot's DoFs).
            InvalidInputError: `robot` has neither `dof_names` nor `get_dof_index`.
        """
        dof_names = getattr(robot, "dof_names", None)
        if dof_names is not None and not callable(dof_names):
            names = [str(n) for n in dof_names]
            out = []
            for n in self.joint_names:
                if n not in names:
                    raise UnknownNameError("joint", n, names)
                out.append(names.index(n))
            return np.asarray(out, dtype=int)
        getter = getattr(robot, "get_dof_index", None)
        if getter is None:
            raise InvalidInputError(
                f"robot must have a `dof_names` list or a `get_dof_index(name)` method; got {type(robot).__name__}"
            )
        out = []
        for n in self.joint_names:
            try:
                i = getter(n)
            except (KeyError, ValueError, IndexError):
                i = None
            if i is None or int(i) < 0:
                raise UnknownNameError("joint", n, [])
            out.append(int(i))
        return np.asarray(out, dtype=int)

    def to_articulation_actions(self, robot: Any, physics_dt: float | None = None) -> list[ArticulationAction]:
        """One `ArticulationAction` per step, for a simulated robot.

        The actions are for the samples after t = 0 (the robot is assumed to be at the
        start already), so applying one action per step of period `dt` replays the
        trajectory. With `physics_dt` given, the trajectory is first resampled at the
        simulator's step, giving one action per physics step.

        Args:
            robot: duck-typed articulation with `dof_names` and/or `get_dof_index(name)`.
            physics_dt: the simulator's step [s]; None uses this trajectory's `dt`.

        Returns:
            T - 1 actions with `joint_positions` [rad], `joint_velocities` [rad/s] and
            `joint_indices` (the robot's indices of `joint_names`).

        Raises:
            UnknownNameError: a joint of the trajectory is not a DoF of the robot.
        """
        traj = self if physics_dt is None else self.resample(physics_dt)
        idx = self.joint_indices_for(robot)
        return [
            ArticulationAction(joint_positions=traj.positions[k], joint_velocities=traj.velocities[k], joint_indices=idx)
            for k in range(1, traj.num_samples)
        ]

    def __repr__(self) -> str:
        return (
            f"Trajectory(duration={self.duration:.4f} s, samples={self.num_samples}, dt={self.dt:.6g} s, "
            f"joints={list(self.joint_names)})"
        )
