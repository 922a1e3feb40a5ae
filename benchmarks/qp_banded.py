#!/usr/bin/env python3
"""A structured interior-point solver for the optimiser's QPs against PIQP (issue 33, rounds six
and seven; not wired into the planner: 1.1-1.3 x PIQP's speed per QP, BENCHMARKS.md, "The
optimiser's QP, a structured solver (issue 33, round six)" and its "Round seven").

    python benchmarks/qp_banded.py [--limit-per-scene 6] [--save QPS.pkl | --load QPS.pkl]

Records the QPs of MotionBenchMaker plans (`qp_record.record`: both goal kinds, seed 0), then
solves each with PIQP as the planner does (`qp.solve(..., "piqp")`) and with `solve` below, and
prints how often the statuses differ, how far the control points are apart (relative to their
size), the iterations and each solver's CPU time per QP (`time.thread_time`, alternating).

`solve`: minimise 1/2 z^T P z + q^T z subject to G z <= h, A z = b, lb <= z <= ub, with
z = [x (dof * points, joint-major control points), others] (`planning.trajopt.qp`). Mehrotra's
predictor-corrector on the reduced KKT system (P + G^T W G + bound terms + A^T A / delta +
rho I) dz = r with PIQP's proximal regularisation (rho, delta; the residuals are the true
ones). A variable in one row of G, in no row of A and only on P's diagonal (a clearance slack)
is eliminated (a diagonal Schur complement); one in no row at all is solved on its own. The
control points are blocked by time (dof x dof blocks; the rows touch 4 consecutive points, so
3 blocks below the diagonal), the other variables (the step h or the limit slacks that rows
touch, the ray parameters) form an arrow solved by a Schur complement. A clearance row is a
Kronecker product (its gradient (dof,) times its sample's basis weights on 4 points): the rows
of one sample give one (b b^T) x (sum w g g^T) update. Everything is computed from the CSC
matrices, so a QP of another shape is solved too (more slowly). The kernel is compiled once per
dof with the block size a constant (loops of dof unrolled); the structure, the Kronecker update
and the block Cholesky live in `qp_banded_kernels.py`.
"""

from __future__ import annotations

import argparse
import math
import pickle
import sys
import time
from pathlib import Path

import numba
import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from qp_banded_kernels import make_block_kernels, structure

from manip.errors import InvalidInputError
from manip.jit import kernel_array
from manip.planning.trajopt import qp

#: Status codes of `solve`.
SOLVED, MAX_ITERATIONS, NUMERICAL = 0, 1, 2

#: Interior-point iterations at most (the recorded QPs take 15 median; a planner would then call PIQP).
MAX_ITER = 40

#: Proximal regularisation of the primal variables and of the equality duals.
RHO, DELTA = 1e-9, 1e-7

_BIG = 1e300  # bounds beyond this are none


def _make_interior_point(BS):
    """`_interior_point` compiled for the block size BS (the dof) as a constant: loops of BS unrolled."""
    add_kronecker, cholesky = make_block_kernels(BS)

    # no disk cache (the tests load this file as a dynamic module); no "ninf"/"nnan": the bounds may be +-inf
    @numba.njit(nogil=True, fastmath={"reassoc", "contract"})
    def _interior_point(P_data, P_indices, P_indptr, q, G_data, G_indices, G_indptr, h, A_data, A_indices, A_indptr, b,
                        lb, ub, dof, points, eps_abs, eps_rel, max_iter, rho, delta, z):
        """Solve the QP (module docstring); P (n, n) both triangles, G (m, n), A (e, n), all CSC;
        x = the first dof * points variables. Writes the solution into z (n,); returns
        (status, iterations)."""
        n = q.shape[0]
        m = h.shape[0]
        e = b.shape[0]
        bs, nb = BS, points  # BS a compile-time constant
        nx = bs * nb
        # --- the structure (qp_banded_kernels.structure)
        (BW, Kaa0, Kb0, Kc0, P_diag, a_ridx, a_rptr, a_rval, g_elim, g_ridx, g_rptr, g_rval, group, idx, k_b, k_g,
         k_p0, kind, kron, n_pair, na, pair_j, pair_k1, pair_k2, row_elim, slot_f, slot_w) = structure(
            P_data, P_indices, P_indptr, G_data, G_indices, G_indptr, A_data, A_indices, A_indptr, n, m, e, bs, nb, delta)
        nbw = BW + 1
        bsq = bs * bs
        Kb = np.zeros(nb * nbw * bsq)
        Kc = np.zeros(nx * na)
        Kaa = np.zeros(na * na)
        M = np.zeros(m * bsq)  # per group: sum w g g^T
        inv_x = np.empty(nx)
        inv_a = np.empty(na)
        dK = np.empty(nx + na)  # K's diagonal before the factorisation
        # --- starting point: mid-box, slacks at least 0.03, duals at the scale of q
        has_lb = np.empty(n, np.bool_)
        has_ub = np.empty(n, np.bool_)
        for v in range(n):
            has_lb[v] = lb[v] > -_BIG
            has_ub[v] = ub[v] < _BIG
        q_norm = 0.0
        for v in range(n):
            q_norm = max(q_norm, abs(q[v]))
        dual0 = max(1.0, q_norm)
        slack0 = 0.03  # 1.0: 10 of 150 recorded QPs stalled, 19 iterations mean; 0.03: 1, 16
        for v in range(n):
            if has_lb[v] and has_ub[v]:
                z[v] = 0.5 * (lb[v] + ub[v])
            elif has_lb[v]:
                z[v] = max(0.0, lb[v] + 1.0)
            elif has_ub[v]:
                z[v] = min(0.0, ub[v] - 1.0)
            else:
                z[v] = 0.0
        y = np.zeros(e)
        s = np.empty(m)
        lam = np.full(m, dual0)
        for j in range(m):
            acc = 0.0
            for k in range(g_rptr[j], g_rptr[j + 1]):
                acc += g_rval[k] * z[g_ridx[k]]
            s[j] = max(h[j] - acc, slack0)
        sl = np.ones(n)
        nul = np.zeros(n)
        su = np.ones(n)
        nuu = np.zeros(n)
        n_comp = m
        for v in range(n):
            if has_lb[v]:
                sl[v] = max(z[v] - lb[v], slack0)
                nul[v] = dual0
                n_comp += 1
            if has_ub[v]:
                su[v] = max(ub[v] - z[v], slack0)
                nuu[v] = dual0
                n_comp += 1
        Pz = np.empty(n)
        Gz = np.empty(m)
        Glam = np.empty(n)
        Aty = np.empty(n)
        rd = np.empty(n)
        rp = np.empty(e)
        ri = np.empty(m)
        rl = np.zeros(n)
        ru = np.zeros(n)
        rx = np.empty(nx)
        ra = np.empty(na)
        ta = np.empty(na)
        dz = np.empty(n)
        dy = np.empty(e)
        dlam = np.empty(m)
        ds = np.empty(m)
        dsl = np.zeros(n)
        dsu = np.zeros(n)
        dnul = np.zeros(n)
        dnuu = np.zeros(n)
        rc = np.empty(m)
        rcl = np.zeros(n)
        rcu = np.zeros(n)
        W = np.empty(m)
        Weff = np.empty(m)
        Htt = np.ones(m)
        dv = np.empty(n)
        base = np.empty(n)
        coef = np.empty(m)
        r_el = np.zeros(m)
        wg = np.empty(bs)
        h_norm = 0.0
        for j in range(m):
            h_norm = max(h_norm, abs(h[j]))
        for r in range(e):
            h_norm = max(h_norm, abs(b[r]))
        status = MAX_ITERATIONS
        it = 0
        for it in range(max_iter + 1):
            # --- residuals
            for v in range(n):
                Pz[v] = 0.0
            for c in range(n):
                zc = z[c]
                for k in range(P_indptr[c], P_indptr[c + 1]):
                    Pz[P_indices[k]] += P_data[k] * zc
            for j in range(m):
                acc = 0.0
                for k in range(g_rptr[j], g_rptr[j + 1]):
                    acc += g_rval[k] * z[g_ridx[k]]
                Gz[j] = acc
            for c in range(n):
                acc = 0.0
                for k in range(G_indptr[c], G_indptr[c + 1]):
                    acc += G_data[k] * lam[G_indices[k]]
                Glam[c] = acc
                acc = 0.0
                for k in range(A_indptr[c], A_indptr[c + 1]):
                    acc += A_data[k] * y[A_indices[k]]
                Aty[c] = acc
            dual_scale = q_norm
            dual_res = 0.0
            for v in range(n):
                rd[v] = Pz[v] + q[v] + Aty[v] + Glam[v] - nul[v] + nuu[v]
                dual_scale = max(dual_scale, abs(Pz[v]), abs(Glam[v]), abs(Aty[v]))
                dual_res = max(dual_res, abs(rd[v]))
            primal_res = 0.0
            for r in range(e):
                acc = -b[r]
                for k in range(a_rptr[r], a_rptr[r + 1]):
                    acc += a_rval[k] * z[a_ridx[k]]
                rp[r] = acc
                primal_res = max(primal_res, abs(acc))
            mu = 0.0
            for j in range(m):
                ri[j] = Gz[j] + s[j] - h[j]
                primal_res = max(primal_res, abs(ri[j]))
                mu += s[j] * lam[j]
            for v in range(n):
                if has_lb[v]:
                    rl[v] = z[v] - lb[v] - sl[v]
                    primal_res = max(primal_res, abs(rl[v]))
                    mu += sl[v] * nul[v]
                if has_ub[v]:
                    ru[v] = z[v] + su[v] - ub[v]
                    primal_res = max(primal_res, abs(ru[v]))
                    mu += su[v] * nuu[v]
            mu /= max(n_comp, 1)
            if not (math.isfinite(primal_res) and math.isfinite(dual_res) and math.isfinite(mu)):
                status = NUMERICAL
                break
            if primal_res <= eps_abs + eps_rel * h_norm and dual_res <= eps_abs + eps_rel * dual_scale and mu <= eps_abs:
                status = SOLVED
                break
            if it == max_iter:
                break
            # --- the reduced matrix in blocks
            Kb[:] = Kb0
            Kc[:] = Kc0
            Kaa[:] = Kaa0
            for j in range(m):
                W[j] = lam[j] / s[j]
            for v in range(n):
                d = rho
                if has_lb[v]:
                    d += nul[v] / sl[v]
                if has_ub[v]:
                    d += nuu[v] / su[v]
                dv[v] = P_diag[v] + d
                if kind[v] == 0:
                    Kb[(idx[v] // bs) * nbw * bsq + (idx[v] % bs) * (bs + 1)] += d
                elif kind[v] == 1:
                    Kaa[idx[v] * (na + 1)] += d
                elif kind[v] == 2:
                    j = idx[v]
                    Htt[j] = dv[v] + g_elim[j] * g_elim[j] * W[j]
            for j in range(m):
                if row_elim[j] >= 0:
                    Weff[j] = W[j] - (g_elim[j] * W[j]) ** 2 / Htt[j]
                else:
                    Weff[j] = W[j]
            for t in range(n_pair):
                w = slot_w[t]
                if w >= 0:
                    val = Weff[pair_j[t]] * g_rval[pair_k1[t]] * g_rval[pair_k2[t]]
                    if w == 0:
                        Kb[slot_f[t]] += val
                    elif w == 1:
                        Kc[slot_f[t]] += val
                    else:
                        Kaa[slot_f[t]] += val
            add_kronecker(Kb, M, Weff, kron, group, k_g, k_b, k_p0, wg, nbw)
            ok = cholesky(Kb, Kc, Kaa, dK, inv_x, inv_a, nb, BW, na)
            if not ok:
                status = NUMERICAL
                break
            # --- predictor, then corrector (one factor)
            alpha = 0.0
            sigma_mu = 0.0
            for phase in range(2):
                if phase == 0:
                    for j in range(m):
                        rc[j] = s[j] * lam[j]
                    for v in range(n):
                        rcl[v] = sl[v] * nul[v] if has_lb[v] else 0.0
                        rcu[v] = su[v] * nuu[v] if has_ub[v] else 0.0
                else:
                    for j in range(m):
                        rc[j] = s[j] * lam[j] + ds[j] * dlam[j] - sigma_mu
                    for v in range(n):
                        rcl[v] = sl[v] * nul[v] + dsl[v] * dnul[v] - sigma_mu if has_lb[v] else 0.0
                        rcu[v] = su[v] * nuu[v] + dsu[v] * dnuu[v] - sigma_mu if has_ub[v] else 0.0
                # right-hand side: -rd - bound terms - A^T rp / delta - G^T (W ri - rc / s), with
                # the eliminated columns' share folded into each row's coefficient
                for v in range(n):
                    acc = -rd[v]
                    if has_lb[v]:
                        acc -= (rcl[v] + nul[v] * rl[v]) / sl[v]
                    if has_ub[v]:
                        acc -= (-rcu[v] + nuu[v] * ru[v]) / su[v]
                    for k in range(A_indptr[v], A_indptr[v + 1]):
                        acc -= A_data[k] * rp[A_indices[k]] / delta
                    base[v] = acc
                for j in range(m):
                    t = W[j] * ri[j] - rc[j] / s[j]
                    v = row_elim[j]
                    if v >= 0:
                        r_el[j] = base[v] - g_elim[j] * t
                        t += g_elim[j] * W[j] * r_el[j] / Htt[j]
                    coef[j] = t
                for v in range(n):
                    if kind[v] < 2:
                        acc = base[v]
                        for k in range(G_indptr[v], G_indptr[v + 1]):
                            acc -= G_data[k] * coef[G_indices[k]]
                        if kind[v] == 0:
                            rx[idx[v]] = acc
                        else:
                            ra[idx[v]] = acc
                # L L^T dz = rhs: forward
                for p in range(nb):
                    for kk in range(max(p - BW, 0), p):
                        oa = (p * nbw + p - kk) * bsq
                        for r in range(bs):
                            acc = 0.0
                            for t in range(bs):
                                acc += Kb[oa + r * bs + t] * rx[kk * bs + t]
                            rx[p * bs + r] -= acc
                    od = p * nbw * bsq
                    for r in range(bs):
                        acc = rx[p * bs + r]
                        for t in range(r):
                            acc -= Kb[od + r * bs + t] * rx[p * bs + t]
                        rx[p * bs + r] = acc * inv_x[p * bs + r]
                for a in range(na):
                    ta[a] = 0.0
                for x in range(nx):
                    f = rx[x]
                    for a in range(na):
                        ta[a] += Kc[x * na + a] * f
                for r in range(na):
                    acc = ra[r] - ta[r]
                    for t in range(r):
                        acc -= Kaa[r * na + t] * ra[t]
                    ra[r] = acc * inv_a[r]
                # backward
                for r in range(na - 1, -1, -1):
                    xr = ra[r] * inv_a[r]
                    ra[r] = xr
                    for t in range(r):
                        ra[t] -= Kaa[r * na + t] * xr
                for x in range(nx):
                    acc = rx[x]
                    for a in range(na):
                        acc -= Kc[x * na + a] * ra[a]
                    rx[x] = acc
                for p in range(nb - 1, -1, -1):
                    od = p * nbw * bsq
                    for r in range(bs - 1, -1, -1):
                        xr = rx[p * bs + r] * inv_x[p * bs + r]
                        rx[p * bs + r] = xr
                        for t in range(r):
                            rx[p * bs + t] -= Kb[od + r * bs + t] * xr
                    for kk in range(max(p - BW, 0), p):  # L[p, kk]^T x_p out of block kk
                        oa = (p * nbw + p - kk) * bsq
                        for r in range(bs):
                            f = rx[p * bs + r]
                            for t in range(bs):
                                rx[kk * bs + t] -= Kb[oa + r * bs + t] * f
                for v in range(n):
                    if kind[v] == 0:
                        dz[v] = rx[idx[v]]
                    elif kind[v] == 1:
                        dz[v] = ra[idx[v]]
                    elif kind[v] == 3:
                        dz[v] = base[v] / dv[v]
                for j in range(m):
                    acc = 0.0
                    v = row_elim[j]
                    for k in range(g_rptr[j], g_rptr[j + 1]):
                        if g_ridx[k] != v:
                            acc += g_rval[k] * dz[g_ridx[k]]
                    if v >= 0:
                        dz[v] = (r_el[j] - g_elim[j] * W[j] * acc) / Htt[j]
                        acc += g_elim[j] * dz[v]
                    ds[j] = -ri[j] - acc
                    dlam[j] = W[j] * (acc + ri[j]) - rc[j] / s[j]
                for r in range(e):
                    acc = rp[r]
                    for k in range(a_rptr[r], a_rptr[r + 1]):
                        acc += a_rval[k] * dz[a_ridx[k]]
                    dy[r] = acc / delta
                alpha = 1.0  # the longest step keeping s, lam, sl, nul, su, nuu positive
                for j in range(m):
                    if ds[j] < 0.0:
                        alpha = min(alpha, -s[j] / ds[j])
                    if dlam[j] < 0.0:
                        alpha = min(alpha, -lam[j] / dlam[j])
                for v in range(n):
                    if has_lb[v]:
                        dsl[v] = dz[v] + rl[v]
                        dnul[v] = (-rcl[v] - nul[v] * dsl[v]) / sl[v]
                        if dsl[v] < 0.0:
                            alpha = min(alpha, -sl[v] / dsl[v])
                        if dnul[v] < 0.0:
                            alpha = min(alpha, -nul[v] / dnul[v])
                    if has_ub[v]:
                        dsu[v] = -ru[v] - dz[v]
                        dnuu[v] = (-rcu[v] - nuu[v] * dsu[v]) / su[v]
                        if dsu[v] < 0.0:
                            alpha = min(alpha, -su[v] / dsu[v])
                        if dnuu[v] < 0.0:
                            alpha = min(alpha, -nuu[v] / dnuu[v])
                if phase == 0:
                    mu_aff = 0.0
                    for j in range(m):
                        mu_aff += (s[j] + alpha * ds[j]) * (lam[j] + alpha * dlam[j])
                    for v in range(n):
                        if has_lb[v]:
                            mu_aff += (sl[v] + alpha * dsl[v]) * (nul[v] + alpha * dnul[v])
                        if has_ub[v]:
                            mu_aff += (su[v] + alpha * dsu[v]) * (nuu[v] + alpha * dnuu[v])
                    mu_aff /= max(n_comp, 1)
                    sigma_mu = min(1.0, mu_aff / mu) ** 3 * mu
            alpha = min(1.0, 0.99 * alpha)
            for v in range(n):
                z[v] += alpha * dz[v]
                if has_lb[v]:
                    sl[v] += alpha * dsl[v]
                    nul[v] += alpha * dnul[v]
                if has_ub[v]:
                    su[v] += alpha * dsu[v]
                    nuu[v] += alpha * dnuu[v]
            for j in range(m):
                s[j] += alpha * ds[j]
                lam[j] += alpha * dlam[j]
            for r in range(e):
                y[r] += alpha * dy[r]
        return status, it
    return _interior_point


_KERNELS: dict = {}  # dof -> `_interior_point` compiled for it


def _kernel(dof: int):
    if dof not in _KERNELS:
        _KERNELS[dof] = _make_interior_point(dof)
    return _KERNELS[dof]


def _csc(M: sp.csc_matrix, rows: int, cols: int, name: str) -> sp.csc_matrix:
    if not sp.issparse(M) or M.format != "csc" or M.shape != (rows, cols):
        raise InvalidInputError(f"{name} must be a ({rows}, {cols}) CSC matrix; got "
                                f"{type(M).__name__} of shape {getattr(M, 'shape', None)}")
    return M


def solve(P: sp.csc_matrix, q: np.ndarray, G: sp.csc_matrix, h: np.ndarray, A: sp.csc_matrix | None,
          b: np.ndarray | None, lb: np.ndarray, ub: np.ndarray, dof: int, points: int, *,
          eps_abs: float = 1e-6, eps_rel: float = 1e-7, max_iter: int = MAX_ITER) -> tuple[int, np.ndarray, int]:
    """argmin 1/2 z^T P z + q^T z subject to G z <= h, A z = b, lb <= z <= ub (module docstring).

    Args:
        P: (n, n) positive semidefinite, both triangles (CSC).
        q: (n,).
        G: (k, n) (CSC); h: (k,).
        A, b: (e, n) (CSC), (e,); None for no equalities.
        lb, ub: (n,) bounds (+-inf for none).
        dof, points: the first dof * points variables are control points, joint-major.
        eps_abs, eps_rel: tolerances of the residuals and the complementarity (PIQP's meaning).
        max_iter: interior-point iterations at most.

    Returns:
        (status: SOLVED, MAX_ITERATIONS or NUMERICAL; z (n,), meaningful when SOLVED; iterations).
    """
    n = np.shape(q)[0] if np.ndim(q) == 1 else -1
    if n < 0:
        raise InvalidInputError(f"q must be a 1-D array; got shape {np.shape(q)}")
    if not (isinstance(dof, (int, np.integer)) and isinstance(points, (int, np.integer)) and dof >= 1 and points >= 1
            and dof * points <= n):
        raise InvalidInputError(f"dof and points must be positive integers with dof * points <= {n} variables; "
                                f"got {dof!r}, {points!r}")
    _csc(P, n, n, "P")
    k = np.shape(h)[0] if np.ndim(h) == 1 else -1
    _csc(G, k, n, "G")
    if A is None:
        A = sp.csc_matrix((0, n))
        b = np.zeros(0)
    elif b is None or np.ndim(b) != 1:
        raise InvalidInputError(f"b must be a 1-D array with A; got {b!r}")
    _csc(A, np.shape(b)[0], n, "A")
    for name, v in (("lb", lb), ("ub", ub)):
        if np.shape(v) != (n,):
            raise InvalidInputError(f"{name} must have shape ({n},); got {np.shape(v)}")
    arrays = [kernel_array(a) for a in (P.data, q, G.data, h, A.data, b, lb, ub)]
    if not all(np.isfinite(a).all() for a in arrays[:6]) or np.isnan(arrays[6]).any() or np.isnan(arrays[7]).any():
        raise InvalidInputError("P, q, G, h, A, b must be finite and lb, ub not NaN")
    if not isinstance(max_iter, (int, np.integer)) or max_iter < 0:
        raise InvalidInputError(f"max_iter must be an integer >= 0; got {max_iter!r}")
    P_data, q, G_data, h, A_data, b, lb, ub = arrays
    z = np.empty(n)
    status, iterations = _kernel(int(dof))(
        P_data, kernel_array(P.indices, np.int32), kernel_array(P.indptr, np.int32), q, G_data,
        kernel_array(G.indices, np.int32), kernel_array(G.indptr, np.int32), h, A_data,
        kernel_array(A.indices, np.int32), kernel_array(A.indptr, np.int32), b, lb, ub, int(dof), int(points),
        float(eps_abs), float(eps_rel), int(max_iter), RHO, DELTA, z)
    return int(status), z, int(iterations)


def points_of(P: sp.csc_matrix, dof: int = 7) -> int:
    """The control points per joint of a recorded QP: the objective couples only the control points."""
    C = P.tocoo()
    off = C.row != C.col
    return (int(max(C.row[off].max(), C.col[off].max())) + 1) // dof


def compare(qps: list[dict]) -> dict:
    """Statuses, solution distance, iterations and CPU per QP of `solve` against PIQP:
    {"qps", "mismatched", "errors" (relative, of the QPs both solved), "iterations", "ms_banded",
    "ms_piqp", "text"}."""
    errors, iterations, t_b, t_p, mismatched = [], [], [], [], 0
    for i, r in enumerate(qps):
        P = r["P"]
        m = points_of(P)
        G = sp.csc_matrix(np.ascontiguousarray(r["G_T"].T))  # as the planner gives it to `qp.solve`
        t0 = time.thread_time()
        status, z, it = solve(P, r["q"], G, r["h"], r["A"], r["b"], r["lb"], r["ub"], 7, m)
        t1 = time.thread_time()
        zp = qp.solve(P, r["q"], G, r["h"], r["A"], r["b"], r["lb"], r["ub"], "piqp")
        t2 = time.thread_time()
        if i:  # the first call compiles
            t_b.append(t1 - t0)
            t_p.append(t2 - t1)
        iterations.append(it)
        if (zp is None) != (status != SOLVED):
            mismatched += 1
        elif zp is not None:
            nx = 7 * m
            errors.append(np.max(np.abs(z[:nx] - zp[:nx])) / max(1.0, np.max(np.abs(zp[:nx]))))
    errors = np.array(errors)
    text = (f"{len(qps)} QPs: status differs on {mismatched}; control points apart (relative) median "
            f"{np.median(errors):.1e}, p98 {np.percentile(errors, 98):.1e}, max {errors.max():.1e}; iterations "
            f"median {np.median(iterations):.0f}, mean {np.mean(iterations):.1f}, max {max(iterations)}; CPU per QP: "
            f"banded {np.mean(t_b) * 1e3:.3f} ms mean / {np.median(t_b) * 1e3:.3f} median, PIQP "
            f"{np.mean(t_p) * 1e3:.3f} / {np.median(t_p) * 1e3:.3f} ms (setup included); PIQP / banded "
            f"{np.mean(t_p) / np.mean(t_b):.2f} (means)")
    return {"qps": len(qps), "mismatched": mismatched, "errors": errors, "iterations": np.array(iterations),
            "ms_banded": 1e3 * float(np.mean(t_b)), "ms_piqp": 1e3 * float(np.mean(t_p)), "text": text}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit-per-scene", type=int, default=6)
    ap.add_argument("--scenes", nargs="*", default=None, help="MBM scenes (default: all)")
    ap.add_argument("--save", default=None, help="write the recorded QPs here (pickle)")
    ap.add_argument("--load", default=None, help="read recorded QPs from here instead of planning")
    args = ap.parse_args(argv)
    if args.load:
        qps = pickle.loads(Path(args.load).read_bytes())
    else:
        import qp_record

        qps = qp_record.record(args.limit_per_scene, args.scenes)
        if args.save:
            Path(args.save).write_bytes(pickle.dumps(qps))
    print(compare(qps)["text"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
