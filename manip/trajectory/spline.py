"""A curve through a dense path and a motion along it: `CubicSplinePath`, `PathProfile`.

The curve parameter `s` is the joint-space chord length [rad]; times in [s].
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from manip.errors import InvalidInputError
from manip.trajectory.profiles import PiecewiseJerkProfile, quadratic_roots, readonly

# PathProfile.extrema evaluates the motion at least this often [s].
_EXTREMA_STEP = 2.5e-4
#: At most this many times in `PathProfile.dense_times` (~11 MB per array of a 7-joint arm): a motion
#: longer than 50 s (a slow velocity_scale, a long `duration`) is sampled every duration / this.
MAX_DENSE_TIMES = 200_000

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
        object.__setattr__(self, "breaks", readonly(breaks))
        object.__setattr__(self, "coeffs", readonly(coeffs))
        object.__setattr__(self, "end", readonly(end))

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
        roots = quadratic_roots(qa, qb, qc)
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
        """(N,) times [s] every <= max(`step`, duration / MAX_DENSE_TIMES) [s] plus every knot of the
        timing profile (a motion of hours took gigabytes at 0.25 ms)."""
        n = max(2, min(int(np.ceil(self.duration / step)), MAX_DENSE_TIMES) + 1)
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
        <= h = 0.25 ms (duration / MAX_DENSE_TIMES beyond 50 s) and at every knot of the timing
        profile, not analytic: with `J` the largest jerk, the velocity maximum is within
        `J h^2 / 8` (about 4e-6 rad/s for J = 500 rad/s^3 and 0.25 ms) and the acceleration
        maximum within `J h / 2` of the true one.
        (The timing guarantees the limits by construction, not by these values.)
        """
        return {k: v.copy() for k, v in self._extrema.items()}
