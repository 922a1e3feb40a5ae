"""The SCO loops' compiled steps (`planning.trajopt.sco_kernels`) give bit for bit what the NumPy/SciPy
expressions they replace gave (so the optimiser builds the same QPs and makes the same motions)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from manip import MotionGenerator
from manip.planning.trajopt import bspline, sco_kernels
from manip.planning.trajopt.optimizer import TrajOptSettings
from manip.planning.trajopt.sco import (
    SplineProblem,
    _csc,
    _csc_matvec,
    _csr_matvec,
    _limit_rows,
    _objective,
    _polygon_step,
    _row_limits,
)

LEFT = np.array([0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])
RIGHT = np.array([-0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])


def numpy_polygon_step(c: np.ndarray, limits) -> float:
    """`sco._polygon_step` as NumPy expressions (before the kernel)."""
    e1 = c[1:] - c[:-1]
    e2 = e1[1:] - e1[:-1]
    e3 = e2[1:] - e2[:-1]
    d1, d2, d3 = np.abs(e1).max(axis=0), np.abs(e2).max(axis=0), np.abs(e3).max(axis=0)
    return float(max(np.max(d1 / limits.velocity), np.sqrt(np.max(d2 / limits.acceleration)),
                     np.cbrt(np.max(d3 / limits.jerk)), 1e-9))


def random_controls(rng, prob: SplineProblem, count: int):
    """Control points of a real problem: a straight fit plus noise of every size, at rest at both ends."""
    n = prob.n
    line = bspline.control_from_samples(np.stack([LEFT, RIGHT]), np.array([0.0, 1.0]), 1.0, n)
    for k in range(count):
        c = line.copy()
        c[3:n] += rng.normal(size=(n - 3, 7)) * 10.0 ** rng.uniform(-6, 0)
        yield c


def test_the_polygon_step_is_numpy_s_to_the_bit():
    rng = np.random.default_rng(1)
    limits = MotionGenerator("franka").config.limits
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    for c in random_controls(rng, prob, 500):
        assert _polygon_step(c, limits) == numpy_polygon_step(c, limits)
    rest = np.tile(LEFT, (s.intervals + 3, 1))  # no motion at all: the floor
    assert _polygon_step(rest, limits) == numpy_polygon_step(rest, limits) == 1e-9


def test_the_limit_rows_in_use_are_scipy_s_to_the_bit():
    rng = np.random.default_rng(2)
    limits = MotionGenerator("franka").config.limits
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    used = []
    for c in random_controls(rng, prob, 200):
        h = float(rng.uniform(0.01, 0.5))
        row_lim = _row_limits(prob, h, limits)
        x0 = c[3 : prob.n]
        want_h = row_lim - prob.limit_fixed
        want = prob.limit_G_sparse @ x0.T.ravel() - want_h > -s.limit_row_slack * row_lim
        keep, h_lim = _limit_rows(prob, x0, row_lim, s)
        assert keep.dtype == bool and np.array_equal(keep, want) and np.array_equal(h_lim, want_h)
        used.append(keep.mean())
    assert min(used) < 0.1 and max(used) > 0.3  # both few and many rows in use were met


def test_the_qp_bounds_are_the_concatenated_numpy_bounds():
    rng = np.random.default_rng(3)
    limits = MotionGenerator("franka").config.limits
    lower, upper = limits.lower, limits.upper
    for _ in range(100):
        m, E, R, T = int(rng.integers(1, 20)), int(rng.integers(1, 22)), int(rng.integers(0, 5)), int(rng.integers(0, 60))
        x0 = np.clip(rng.normal(size=(m, 7)) * 2.0, lower, upper)
        radius = float(rng.uniform(0.01, 1.0))
        lb_extra, ub_extra = rng.normal(size=E), rng.normal(size=E) + 5.0
        lb, ub = sco_kernels.bounds(x0, radius, lower, upper, lb_extra, ub_extra, R, T)
        want_lb = np.concatenate([np.maximum(lower[None, :], x0 - radius).T.ravel(), lb_extra, np.zeros(R + T)])
        want_ub = np.concatenate([np.minimum(upper[None, :], x0 + radius).T.ravel(), ub_extra, np.ones(R),
                                  np.full(T, np.inf)])
        assert np.array_equal(lb, want_lb) and np.array_equal(ub, want_ub)


def test_the_sparse_products_are_scipy_s_to_the_bit():
    """The objective's P (CSC) and the limit rows (CSR) of a real problem times x, as SciPy multiplies."""
    rng = np.random.default_rng(4)
    limits = MotionGenerator("franka").config.limits
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    for c in random_controls(rng, prob, 100):
        P = _objective(prob, float(rng.uniform(0.01, 0.5)), limits, s)[0]
        x = c[3 : prob.n].T.ravel()
        assert np.array_equal(_csc_matvec(P, x), P @ x)
        assert np.array_equal(_csr_matvec(prob.limit_G_sparse, x), prob.limit_G_sparse @ x)


def test_the_end_rays_rows_are_scipy_s_csc_of_the_dense_rows():
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    d_start, d_goal = RIGHT - LEFT, LEFT - RIGHT
    d_start[2] = 0.0  # a joint that does not move: an exact zero left out
    prob.set_rays(d_start, d_goal, 2)
    for gap in (1, 21):
        for after in (0, 5):
            A, b = prob.ray_rows(gap, after)
            dense = np.zeros((4 * 7, prob.limit_G.shape[1] + gap + 4 + after))
            for r, (k, anchor, d) in enumerate(prob.rays):
                for i in range(7):
                    dense[r * 7 + i, i * prob.free.size + k - 3] = 1.0
                    dense[r * 7 + i, prob.limit_G.shape[1] + gap + r] = -d[i]
            want = sp.csc_matrix(dense)
            want.sort_indices()
            A.check_format(full_check=True)
            assert A.shape == want.shape and np.array_equal(A.indptr, want.indptr)
            assert np.array_equal(A.indices, want.indices) and np.array_equal(A.data, want.data)
            assert np.array_equal(b, np.tile(np.concatenate([LEFT, RIGHT]), 2))  # rays: start, goal, start, goal
            assert prob.ray_rows(gap, after)[0] is A  # built once per problem and size


def test_the_objective_is_scipy_s_csc_of_the_dense_block_diagonal_p():
    limits = MotionGenerator("franka").config.limits
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    m = prob.free.size
    for h in (0.013, 0.1, 0.37):
        P, q = _objective(prob, h, limits, s)
        dense = np.zeros((7 * m, 7 * m))  # the dense P, joint by joint (before it went straight to CSC)
        for i in range(7):
            block = np.zeros((m, m))
            for order, lim, w in ((1, limits.velocity * h, s.velocity_weight),
                                  (2, limits.acceleration * h**2, s.acceleration_weight),
                                  (3, limits.jerk * h**3, s.jerk_weight)):
                block += (2 * w / lim[i] ** 2) * prob.cost[order][0]
            dense[i * m : (i + 1) * m, i * m : (i + 1) * m] = block
        dense[np.diag_indices_from(dense)] += 1e-6
        want = sp.csc_matrix(dense)
        P.check_format(full_check=True)
        assert P.shape == want.shape and np.array_equal(P.indptr, want.indptr)
        assert np.array_equal(P.indices, want.indices) and np.array_equal(P.data, want.data)
        assert np.array_equal(_csc(dense).data, want.data) and q.shape == (7 * m,)
