"""Uniform cubic B-splines at rest at both ends: the trajectory optimiser's representation.

A motion of duration `T = N h` is `q(t) = sum_k B_k(t / h) c_k` over control points
`c_0 .. c_{N+2}` (N + 3, dof), with `c_0 = c_1 = c_2 = start` and `c_N = c_{N+1} = c_{N+2}
= goal`, so the motion starts and ends at rest (zero velocity and acceleration). Its
derivatives are B-splines of the differences of the control points, which bounds the
continuous motion by linear functions of the control points (the convex-hull property):

- position: within the range of the control points;
- velocity: a quadratic B-spline, |qd| <= max_k |c_{k+1} - c_k| / h (the constraint the
  optimiser uses); its exact maximum is cheap too (`max_speed`, used to re-time);
- acceleration: piecewise linear through (c_k - 2 c_{k+1} + c_{k+2}) / h^2 at the knots (exact);
- jerk: constant (-c_k + 3 c_{k+1} - 3 c_{k+2} + c_{k+3}) / h^3 on piece k (exact).

So limits imposed on the control points hold for the whole motion, not only at samples.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from manip.limits import JointLimits
from manip.trajectory import PiecewiseJerkProfile

#: Rows: coefficients of u^3, u^2, u, 1; columns: control points k .. k+3 of one piece.
_M = np.array([[-1.0, 3.0, -3.0, 1.0], [3.0, -6.0, 3.0, 0.0], [-3.0, 0.0, 3.0, 0.0], [1.0, 4.0, 1.0, 0.0]]) / 6.0


def difference_matrix(n_points: int, order: int) -> np.ndarray:
    """(n_points - order, n_points) forward differences of the given order (1, 2 or 3)."""
    D = np.eye(n_points)
    for _ in range(order):
        D = D[1:] - D[:-1]
    return D


@lru_cache(maxsize=16)
def basis_matrix(intervals: int, samples_per_interval: int) -> tuple[np.ndarray, np.ndarray]:
    """Sample matrix B (M, N + 3) with q(t_m) = B[m] @ c, and the sample times in units of h (M,)
    (read-only: shared by every call of the same sizes).

    Samples: `samples_per_interval` evenly spaced per piece, plus the end.
    """
    s = samples_per_interval
    u = np.arange(s) / s
    U = np.stack([u**3, u**2, u, np.ones_like(u)], axis=1) @ _M  # (s, 4)
    n = intervals
    B = np.zeros((n * s + 1, n + 3))
    for k in range(n):
        B[k * s : (k + 1) * s, k : k + 4] = U
    B[-1, n : n + 3] = np.array([1.0, 4.0, 1.0]) / 6.0
    times = np.concatenate([np.arange(n * s) / s, [float(n)]])
    B.flags.writeable = times.flags.writeable = False
    return B, times


def max_speed(control: np.ndarray) -> np.ndarray:
    """(dof,) exact max |dq/du| over the spline (u = t / h), from each piece's quadratic.

    On piece k, with d_i = c_{i+1} - c_i: dq/du = ((1-u)^2 d_k + (1 + 2u - 2u^2) d_{k+1} + u^2 d_{k+2}) / 2,
    largest at an end of the piece or at its vertex.
    """
    d = np.diff(control, axis=0)  # (N + 2, dof)
    d0, d1, d2 = d[:-2], d[1:-1], d[2:]
    ends = np.abs(0.5 * (d0 + d1))
    best = np.maximum(ends.max(axis=0), np.abs(0.5 * (d1[-1] + d2[-1])))
    curv = d0 - 2 * d1 + d2
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(curv != 0, (d0 - d1) / curv, -1.0)
    inside = (u > 0) & (u < 1)
    u = np.where(inside, u, 0.0)
    vertex = 0.5 * ((1 - u) ** 2 * d0 + (1 + 2 * u - 2 * u**2) * d1 + u**2 * d2)
    return np.maximum(best, np.where(inside, np.abs(vertex), 0.0).max(axis=0))


def limit_step(control: np.ndarray, limits: JointLimits) -> float:
    """The shortest knot spacing h [s] at which the spline with control points (N + 3, dof)
    respects the velocity, acceleration and jerk limits of `limits` (exact: velocity from each
    piece's quadratic, acceleration at the knots, jerk per piece)."""
    vmax, amax, jmax = limits.velocity, limits.acceleration, limits.jerk
    d1 = max_speed(control)
    d2 = np.abs(np.diff(control, 2, axis=0)).max(axis=0)
    d3 = np.abs(np.diff(control, 3, axis=0)).max(axis=0)
    return float(max(np.max(d1 / vmax), np.sqrt(np.max(d2 / amax)), np.cbrt(np.max(d3 / jmax)), 1e-9))


def to_profile(control: np.ndarray, h: float) -> PiecewiseJerkProfile:
    """The exact piecewise-constant-jerk profile of the spline with control points (N + 3, dof), step h [s]."""
    c = np.asarray(control, dtype=float)
    n = c.shape[0] - 3
    p0 = (c[:-3] + 4 * c[1:-2] + c[2:-1]) / 6.0  # (N, dof) at the knots 0..N-1
    v0 = (c[2:-1] - c[:-3]) / (2 * h)
    a0 = (c[:-3] - 2 * c[1:-2] + c[2:-1]) / h**2
    j = (-c[:-3] + 3 * c[1:-2] - 3 * c[2:-1] + c[3:]) / h**3
    end = (c[-3] + 4 * c[-2] + c[-1]) / 6.0
    if np.array_equal(c[0], c[1]) and np.array_equal(c[1], c[2]):
        p0[0] = c[0]  # exactly the start (the weighted mean may differ in the last bit)
    if np.array_equal(c[-3], c[-2]) and np.array_equal(c[-2], c[-1]):
        end = c[-1].copy()
    knots = np.append(np.arange(n + 1) * h, n * h)
    knots[-2] = n * h
    dof = c.shape[1]
    zeros = np.zeros((1, dof))
    return PiecewiseJerkProfile(
        knots=np.repeat(knots[None, :], dof, axis=0),
        p0=np.concatenate([p0, end[None]]).T,
        v0=np.concatenate([v0, zeros]).T,
        a0=np.concatenate([a0, zeros]).T,
        j=np.concatenate([j, zeros]).T,
    )


def control_from_samples(positions: np.ndarray, times: np.ndarray, duration: float, intervals: int) -> np.ndarray:
    """Control points (N + 3, dof) of the rest-to-rest spline closest to a sampled motion.

    The three first and last control points are the start and the goal; the interior ones
    are the least-squares fit of the spline to the motion's positions (linearly
    interpolated) at 8 points per piece, so the spline keeps the motion's timing.
    """
    n = intervals
    B, u = basis_matrix(n, 8)
    t = u * duration / n
    q = np.stack([np.interp(t, times, positions[:, i]) for i in range(positions.shape[1])], axis=1)
    c = np.empty((n + 3, positions.shape[1]))
    c[:3] = positions[0]
    c[n:] = positions[-1]
    free = np.arange(3, n)
    fixed = np.setdiff1d(np.arange(n + 3), free)
    rhs = q - B[:, fixed] @ c[fixed]
    c[free] = np.linalg.lstsq(B[:, free], rhs, rcond=None)[0]
    return c
