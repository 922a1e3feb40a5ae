"""Exact piecewise-constant-jerk motion: `PiecewiseJerkProfile` (ruckig's form) and helpers.

Times in [s], positions in [rad] (and their derivatives in [rad/s], [rad/s^2], [rad/s^3]).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip.errors import InvalidInputError
from manip.validation import positive


def readonly(a: np.ndarray) -> np.ndarray:
    """A read-only float copy of `a`."""
    a = np.array(a, dtype=float)  # copy
    a.setflags(write=False)
    return a


def quadratic_roots(qa: np.ndarray, qb: np.ndarray, qc: np.ndarray) -> list[np.ndarray]:
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
            object.__setattr__(self, name, readonly(a))
        if np.any(np.diff(knots, axis=1) < 0):
            raise InvalidInputError("PiecewiseJerkProfile.knots must be non-decreasing along each row")
        object.__setattr__(self, "knots", readonly(knots))

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
        factor = positive(factor, "time scale factor")
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
        roots = quadratic_roots(qa, qb, qc)
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
