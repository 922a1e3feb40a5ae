"""Compiled steps of the SCO loops (`planning.trajopt.sco`): the same floating-point operations,
in the same order, as the NumPy/SciPy expressions they replace (so the same QPs and motions),
without their per-call overhead (a dozen array operations per SCO iteration, ~1-2 us each).
"""

from __future__ import annotations

import numpy as np

from manip.jit import kernel


@kernel
def polygon_ratios(c, velocity, acceleration, jerk):
    """(max_i d1_i / v_i, max_i d2_i / a_i, max_i d3_i / j_i) of control points c (K, dof):
    d_k (dof,) the largest |k-th difference| of each joint (k-th differences taken from the
    (k-1)-th, as `np.diff` does), v, a, j (dof,) the limits."""
    K, dof = c.shape
    r1 = r2 = r3 = -np.inf
    for i in range(dof):
        d1 = d2 = d3 = 0.0
        for t in range(K - 3):
            e1a = c[t + 1, i] - c[t, i]
            e1b = c[t + 2, i] - c[t + 1, i]
            e1c = c[t + 3, i] - c[t + 2, i]
            e2a = e1b - e1a
            e2b = e1c - e1b
            d1 = max(d1, abs(e1a))
            d2 = max(d2, abs(e2a))
            d3 = max(d3, abs(e2b - e2a))
        # the last differences of orders 1 and 2 (not reached by t above)
        if K >= 2:
            d1 = max(d1, abs(c[K - 1, i] - c[K - 2, i]))
        if K >= 3:
            d1 = max(d1, abs(c[K - 2, i] - c[K - 3, i]))
            d2 = max(d2, abs((c[K - 1, i] - c[K - 2, i]) - (c[K - 2, i] - c[K - 3, i])))
        r1 = max(r1, d1 / velocity[i])
        r2 = max(r2, d2 / acceleration[i])
        r3 = max(r3, d3 / jerk[i])
    return r1, r2, r3


@kernel
def limit_rows(indptr, indices, data, x, row_lim, limit_fixed, row_slack):
    """(keep (L,) bool, h_lim (L,)) of the limit rows G (CSR: indptr, indices, data; L rows) at x:
    h_lim = row_lim - limit_fixed, keep = G x - h_lim > -row_slack * row_lim (G x summed per row
    in index order from 0, as SciPy's CSR product)."""
    L = indptr.shape[0] - 1
    keep = np.empty(L, np.bool_)
    h_lim = np.empty(L)
    neg = -row_slack
    for r in range(L):
        s = 0.0
        for p in range(indptr[r], indptr[r + 1]):
            s += data[p] * x[indices[p]]
        h_lim[r] = row_lim[r] - limit_fixed[r]
        keep[r] = s - h_lim[r] > neg * row_lim[r]
    return keep, h_lim


@kernel
def bounds(x0, radius, lower, upper, lb_extra, ub_extra, n_rays, n_terms):
    """(lb, ub) of a QP's variables [x (joint-major, of x0 (m, dof)), extras, rays, clearance
    slacks]: max(lower, x0 - radius), min(upper, x0 + radius) on x; the extras' own bounds;
    [0, 1] on the rays, [0, inf) on the slacks."""
    m, dof = x0.shape
    E = lb_extra.shape[0]
    nz = m * dof + E + n_rays + n_terms
    lb = np.zeros(nz)
    ub = np.empty(nz)
    for i in range(dof):
        for j in range(m):
            lb[i * m + j] = max(lower[i], x0[j, i] - radius)
            ub[i * m + j] = min(upper[i], x0[j, i] + radius)
    k = m * dof
    for e in range(E):
        lb[k + e] = lb_extra[e]
        ub[k + e] = ub_extra[e]
    k += E
    for e in range(n_rays):
        ub[k + e] = 1.0
    k += n_rays
    for t in range(n_terms):
        ub[k + t] = np.inf
    return lb, ub


@kernel
def csc_matvec(indptr, indices, data, x, rows):
    """M x (rows,) of a CSC matrix M (indptr, indices, data) and x (columns,): each product added
    to its row in column order, as SciPy's CSC product."""
    y = np.zeros(rows)
    for j in range(indptr.shape[0] - 1):
        xj = x[j]
        for p in range(indptr[j], indptr[j + 1]):
            y[indices[p]] += data[p] * xj
    return y


@kernel
def csr_matvec(indptr, indices, data, x):
    """M x (rows,) of a CSR matrix M (indptr, indices, data) and x (columns,): each row's products
    summed in index order from 0, as SciPy's CSR product."""
    rows = indptr.shape[0] - 1
    y = np.empty(rows)
    for r in range(rows):
        s = 0.0
        for p in range(indptr[r], indptr[r + 1]):
            s += data[p] * x[indices[p]]
        y[r] = s
    return y
