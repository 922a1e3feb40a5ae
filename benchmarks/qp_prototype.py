#!/usr/bin/env python3
"""A banded interior-point QP solver prototype against PIQP, on the optimiser's QPs recorded from
MotionBenchMaker plans (issue 33, lever 2: "check first with a quick prototype").

    python benchmarks/qp_prototype.py [--limit-per-scene 6] [--save QPS.pkl | --load QPS.pkl]

Records every `planning.trajopt.qp.solve` call of the plans (both goal kinds, seed 0), then solves
each QP with PIQP as the planner does (`qp.solve(..., "piqp")`) and with `interior_point` below,
and prints how often the two agree on the status, how far the control points are apart (relative
to their size), the prototype's iterations and each solver's CPU time per QP (`time.thread_time`).

`interior_point`: Mehrotra's predictor-corrector on the reduced KKT system
(P + G^T W G + bound terms + A^T A / delta + rho I) dz = r, with proximal regularisation as PIQP
has it (the residuals are the true ones); a variable in exactly one inequality row, no equality
row and only on P's diagonal (the clearance slacks) is eliminated (a diagonal Schur complement);
the others are ordered by a key (the control points time-major) and the Cholesky factor is
computed inside each row's envelope (banded rows cost their bandwidth squared, the dense columns
of the limit slacks / the step / the ray parameters the bandwidth times the size).

Measured (BENCHMARKS.md, "Where a plan's time goes"): it agrees with PIQP to PIQP's own accuracy but
costs as much per QP (~0.07-0.12 ms per iteration, 14 iterations median): not wired in.
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

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.planning.trajopt import qp

#: Status codes of `interior_point`.
SOLVED, MAX_ITERATIONS, NUMERICAL = 0, 1, 2


@numba.njit(nogil=True)  # no disk cache: the tests load this file as a dynamic module
def _row_products(ptr, idx, val, x):
    """M x for M (r, c) by rows (CSR: ptr (r + 1,), idx, val)."""
    r = ptr.shape[0] - 1
    out = np.zeros(r)
    for j in range(r):
        acc = 0.0
        for k in range(ptr[j], ptr[j + 1]):
            acc += val[k] * x[idx[k]]
        out[j] = acc
    return out


@numba.njit(nogil=True)  # no disk cache: the tests load this file as a dynamic module
def interior_point(P_data, P_indices, P_indptr, q, G, h, A, b, lb, ub, key, eps_abs, eps_rel, max_iter, rho, delta,
                   dual0=1.0, slack0=1.0):
    """Solve the QP (module docstring). P (n, n) CSC (data, indices, indptr; both triangles),
    G (m, n) and A (e, n) dense, key (n,) the order of the kept variables (smallest first);
    rho, delta: the proximal regularisations; dual0, slack0: the starting duals and least slacks
    (an infeasible start: duals near the scale of q converge in far fewer iterations).

    Returns:
        (status (SOLVED, MAX_ITERATIONS or NUMERICAL), z (n,), iterations).
    """
    n = q.shape[0]
    m = h.shape[0]
    e = b.shape[0]
    # --- structure: eliminable columns (one G row, no A row, P diagonal only)
    g_count = np.zeros(n, np.int64)
    g_row = np.full(n, -1, np.int64)
    for j in range(m):
        for v in range(n):
            if G[j, v] != 0.0:
                g_count[v] += 1
                g_row[v] = j
    elim = g_count == 1
    f_ptr = np.zeros(m + 1, np.int64)
    for j in range(m):
        c = 0
        for v in range(n):
            if G[j, v] != 0.0:
                c += 1
        f_ptr[j + 1] = f_ptr[j] + c
    f_idx = np.empty(f_ptr[m], np.int64)
    f_val = np.empty(f_ptr[m])
    for j in range(m):
        k = f_ptr[j]
        for v in range(n):
            if G[j, v] != 0.0:
                f_idx[k] = v
                f_val[k] = G[j, v]
                k += 1
    for r in range(e):
        for v in range(n):
            if A[r, v] != 0.0:
                elim[v] = False
    P_diag = np.zeros(n)
    for c in range(n):
        for k in range(P_indptr[c], P_indptr[c + 1]):
            if P_indices[k] == c:
                P_diag[c] += P_data[k]
            else:
                elim[c] = False
                elim[P_indices[k]] = False
    row_elim = np.full(m, -1, np.int64)  # the eliminated column of row j (at most one kept)
    for v in range(n):
        if elim[v]:
            if row_elim[g_row[v]] >= 0:
                elim[v] = False  # one eliminated column per row
            else:
                row_elim[g_row[v]] = v
    kept = np.flatnonzero(~elim)
    order = kept[np.argsort(key[kept], kind="mergesort")]
    nk = order.shape[0]
    pos = np.full(n, -1, np.int64)
    for i in range(nk):
        pos[order[i]] = i
    # rows' kept nonzeros (positions) as lists
    g_ptr = np.zeros(m + 1, np.int64)
    for j in range(m):
        c = 0
        for v in range(n):
            if G[j, v] != 0.0 and pos[v] >= 0:
                c += 1
        g_ptr[j + 1] = g_ptr[j] + c
    g_pos = np.empty(g_ptr[m], np.int64)
    g_val = np.empty(g_ptr[m])
    for j in range(m):
        k = g_ptr[j]
        for v in range(n):
            if G[j, v] != 0.0 and pos[v] >= 0:
                g_pos[k] = pos[v]
                g_val[k] = G[j, v]
                k += 1
    for j in range(m):  # each row's entries by position (the products below fill K's lower triangle)
        lo, hi = g_ptr[j], g_ptr[j + 1]
        o = np.argsort(g_pos[lo:hi])
        g_pos[lo:hi] = g_pos[lo:hi][o]
        g_val[lo:hi] = g_val[lo:hi][o]
    g_elim = np.zeros(m)  # coefficient of the row's eliminated column
    for j in range(m):
        if row_elim[j] >= 0:
            g_elim[j] = G[j, row_elim[j]]
    a_ptr = np.zeros(e + 1, np.int64)
    for r in range(e):
        c = 0
        for v in range(n):
            if A[r, v] != 0.0:
                c += 1
        a_ptr[r + 1] = a_ptr[r] + c
    a_pos = np.empty(a_ptr[e], np.int64)
    a_val = np.empty(a_ptr[e])
    for r in range(e):
        k = a_ptr[r]
        for v in range(n):
            if A[r, v] != 0.0:
                a_pos[k] = pos[v]
                a_val[k] = A[r, v]
                k += 1
    # envelope: first[i] = the smallest column of row i's pattern (the factor stays inside)
    first = np.arange(nk)
    for c in range(n):
        pc = pos[c]
        if pc < 0:
            continue
        for k in range(P_indptr[c], P_indptr[c + 1]):
            pr = pos[P_indices[k]]
            if pr >= 0:
                lo, hi = min(pr, pc), max(pr, pc)
                first[hi] = min(first[hi], lo)
    for j in range(m):
        lo = nk
        for k in range(g_ptr[j], g_ptr[j + 1]):
            lo = min(lo, g_pos[k])
        for k in range(g_ptr[j], g_ptr[j + 1]):
            first[g_pos[k]] = min(first[g_pos[k]], lo)
    for r in range(e):
        lo = nk
        for k in range(a_ptr[r], a_ptr[r + 1]):
            lo = min(lo, a_pos[k])
        for k in range(a_ptr[r], a_ptr[r + 1]):
            first[a_pos[k]] = min(first[a_pos[k]], lo)
    has_lb = lb > -np.inf
    has_ub = ub < np.inf
    # --- starting point (infeasible start)
    z = np.zeros(n)
    for v in range(n):
        if has_lb[v] and has_ub[v]:
            z[v] = 0.5 * (lb[v] + ub[v])
        elif has_lb[v]:
            z[v] = max(0.0, lb[v] + 1.0)
        elif has_ub[v]:
            z[v] = min(0.0, ub[v] - 1.0)
    y = np.zeros(e)
    Gz = _row_products(f_ptr, f_idx, f_val, z)
    s = np.empty(m)
    lam = np.full(m, dual0)
    for j in range(m):
        s[j] = max(h[j] - Gz[j], slack0)
    sl = np.ones(n)
    nul = np.zeros(n)
    su = np.ones(n)
    nuu = np.zeros(n)
    for v in range(n):
        if has_lb[v]:
            sl[v] = max(z[v] - lb[v], slack0)
            nul[v] = dual0
        if has_ub[v]:
            su[v] = max(ub[v] - z[v], slack0)
            nuu[v] = dual0
    n_comp = m + np.sum(has_lb) + np.sum(has_ub)
    K = np.zeros((nk, nk))
    rd = np.empty(n)
    rp = np.empty(e)
    ri = np.empty(m)
    rl = np.zeros(n)
    ru = np.zeros(n)
    rhs_k = np.empty(nk)
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
    r_full = np.empty(n)
    q_norm = np.max(np.abs(q)) if n else 0.0
    h_norm = np.max(np.abs(h)) if m else 0.0
    b_norm = np.max(np.abs(b)) if e else 0.0
    status = MAX_ITERATIONS
    it = 0
    for it in range(max_iter + 1):
        # --- residuals
        Pz = np.zeros(n)
        for c in range(n):
            for k in range(P_indptr[c], P_indptr[c + 1]):
                Pz[P_indices[k]] += P_data[k] * z[c]
        Gz = _row_products(f_ptr, f_idx, f_val, z)
        Glam = np.zeros(n)
        for j in range(m):
            for k in range(f_ptr[j], f_ptr[j + 1]):
                Glam[f_idx[k]] += f_val[k] * lam[j]
        Aty = A.T @ y
        for v in range(n):
            rd[v] = Pz[v] + q[v] + Aty[v] + Glam[v] - nul[v] + nuu[v]
        Az = A @ z
        for r in range(e):
            rp[r] = Az[r] - b[r]
        for j in range(m):
            ri[j] = Gz[j] + s[j] - h[j]
        mu = 0.0
        for j in range(m):
            mu += s[j] * lam[j]
        for v in range(n):
            if has_lb[v]:
                rl[v] = z[v] - lb[v] - sl[v]
                mu += sl[v] * nul[v]
            if has_ub[v]:
                ru[v] = z[v] + su[v] - ub[v]
                mu += su[v] * nuu[v]
        mu /= max(n_comp, 1)
        dual_scale = max(q_norm, np.max(np.abs(Pz)) if n else 0.0, np.max(np.abs(Glam)) if n else 0.0,
                         np.max(np.abs(Aty)) if n else 0.0)
        primal_res = 0.0
        if m:
            primal_res = max(primal_res, np.max(np.abs(ri)))
        if e:
            primal_res = max(primal_res, np.max(np.abs(rp)))
        primal_res = max(primal_res, np.max(np.abs(rl)), np.max(np.abs(ru)))
        dual_res = np.max(np.abs(rd)) if n else 0.0
        if (primal_res <= eps_abs + eps_rel * max(h_norm, b_norm) and dual_res <= eps_abs + eps_rel * dual_scale
                and mu <= eps_abs):
            status = SOLVED
            break
        if it == max_iter:
            break
        # --- the reduced matrix (kept variables, envelope lower triangle)
        for j in range(m):
            W[j] = lam[j] / s[j]
        for i in range(nk):
            for k in range(first[i], i + 1):
                K[i, k] = 0.0
        for c in range(n):
            pc = pos[c]
            if pc < 0:
                continue
            for k in range(P_indptr[c], P_indptr[c + 1]):
                pr = pos[P_indices[k]]
                if pr >= 0 and pr <= pc:
                    K[pc, pr] += P_data[k]
        for v in range(n):
            d = rho
            if has_lb[v]:
                d += nul[v] / sl[v]
            if has_ub[v]:
                d += nuu[v] / su[v]
            if pos[v] >= 0:
                K[pos[v], pos[v]] += d
            else:
                Htt[g_row[v]] = P_diag[v] + d + g_elim[g_row[v]] ** 2 * W[g_row[v]]
        for j in range(m):
            if row_elim[j] >= 0:
                Weff[j] = W[j] - (g_elim[j] * W[j]) ** 2 / Htt[j]
            else:
                Weff[j] = W[j]
            for k1 in range(g_ptr[j], g_ptr[j + 1]):
                p1 = g_pos[k1]
                w1 = Weff[j] * g_val[k1]
                for k2 in range(g_ptr[j], k1 + 1):
                    K[p1, g_pos[k2]] += w1 * g_val[k2]
        for r in range(e):
            for k1 in range(a_ptr[r], a_ptr[r + 1]):
                p1 = a_pos[k1]
                for k2 in range(a_ptr[r], a_ptr[r + 1]):
                    p2 = a_pos[k2]
                    if p2 <= p1:
                        K[p1, p2] += a_val[k1] * a_val[k2] / delta
        # envelope Cholesky in place
        ok = True
        for i in range(nk):
            fi = first[i]
            for jj in range(fi, i + 1):
                acc = K[i, jj]
                k0 = max(fi, first[jj])
                for k in range(k0, jj):
                    acc -= K[i, k] * K[jj, k]
                if jj < i:
                    K[i, jj] = acc / K[jj, jj]
                else:
                    if not acc > 1e-300:
                        ok = False
                        acc = 1e-300
                    K[i, i] = math.sqrt(acc)
        if not ok:
            status = NUMERICAL
            break
        # --- predictor, then corrector (same factor)
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
            # r = -rd - G^T (W ri - rc / s) - bound terms - A^T rp / delta
            for v in range(n):
                acc = -rd[v]
                if has_lb[v]:
                    acc -= (rcl[v] + nul[v] * rl[v]) / sl[v]
                if has_ub[v]:
                    acc -= (-rcu[v] + nuu[v] * ru[v]) / su[v]
                r_full[v] = acc
            for j in range(m):
                t = W[j] * ri[j] - rc[j] / s[j]
                for k in range(f_ptr[j], f_ptr[j + 1]):
                    r_full[f_idx[k]] -= f_val[k] * t
            for r in range(e):
                for k in range(a_ptr[r], a_ptr[r + 1]):
                    rhs_k[a_pos[k]] = 0.0
            for i in range(nk):
                rhs_k[i] = r_full[order[i]]
            for r in range(e):
                for k in range(a_ptr[r], a_ptr[r + 1]):
                    rhs_k[a_pos[k]] -= a_val[k] * rp[r] / delta
            for j in range(m):  # the eliminated columns' share
                v = row_elim[j]
                if v >= 0:
                    f = g_elim[j] * W[j] * r_full[v] / Htt[j]
                    for k in range(g_ptr[j], g_ptr[j + 1]):
                        rhs_k[g_pos[k]] -= g_val[k] * f
            # solve L L^T x = rhs
            for i in range(nk):
                acc = rhs_k[i]
                for k in range(first[i], i):
                    acc -= K[i, k] * rhs_k[k]
                rhs_k[i] = acc / K[i, i]
            for i in range(nk - 1, -1, -1):
                xi = rhs_k[i] / K[i, i]
                rhs_k[i] = xi
                for k in range(first[i], i):
                    rhs_k[k] -= K[i, k] * xi
            for i in range(nk):
                dz[order[i]] = rhs_k[i]
            for j in range(m):
                v = row_elim[j]
                if v >= 0:
                    gx = 0.0
                    for k in range(g_ptr[j], g_ptr[j + 1]):
                        gx += g_val[k] * rhs_k[g_pos[k]]
                    dz[v] = (r_full[v] - g_elim[j] * W[j] * gx) / Htt[j]
            for r in range(e):
                acc = rp[r]
                for k in range(a_ptr[r], a_ptr[r + 1]):
                    acc += a_val[k] * rhs_k[a_pos[k]]
                dy[r] = acc / delta
            Gdz = _row_products(f_ptr, f_idx, f_val, dz)
            for j in range(m):
                ds[j] = -ri[j] - Gdz[j]
                dlam[j] = W[j] * (Gdz[j] + ri[j]) - rc[j] / s[j]
            for v in range(n):
                if has_lb[v]:
                    dsl[v] = dz[v] + rl[v]
                    dnul[v] = (-rcl[v] - nul[v] * dsl[v]) / sl[v]
                if has_ub[v]:
                    dsu[v] = -ru[v] - dz[v]
                    dnuu[v] = (-rcu[v] - nuu[v] * dsu[v]) / su[v]
            # the longest step keeping s, lam, sl, nul, su, nuu positive
            alpha = 1.0
            for j in range(m):
                if ds[j] < 0.0:
                    alpha = min(alpha, -s[j] / ds[j])
                if dlam[j] < 0.0:
                    alpha = min(alpha, -lam[j] / dlam[j])
            for v in range(n):
                if has_lb[v]:
                    if dsl[v] < 0.0:
                        alpha = min(alpha, -sl[v] / dsl[v])
                    if dnul[v] < 0.0:
                        alpha = min(alpha, -nul[v] / dnul[v])
                if has_ub[v]:
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
    return status, z, it


def record(limit_per_scene: int, scenes: list[str] | None = None) -> list[dict]:
    """The QPs of the first `limit_per_scene` valid problems of each scene (all, or `scenes`; both goal kinds)."""
    recorded = []
    solve = qp.solve

    def recording(P, q, G, h, A, b, lb, ub, solver):
        recorded.append({"P": P.copy(), "q": q.copy(), "G_T": G.toarray().T, "h": h.copy(),
                         "A": None if A is None else A.copy(), "b": None if b is None else b.copy(),
                         "lb": lb.copy(), "ub": ub.copy()})
        return solve(P, q, G, h, A, b, lb, ub, solver)

    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    problems = [p for p in load_mbm_problems(limit_per_scene=limit_per_scene)
                if (scenes is None or p.scene in scenes) and verifier.check_problem(p).valid]
    qp.solve = recording
    try:
        for p in problems:
            mg.update_world(WorldConfig.from_dict(p.world))
            mg.plan_joints(p.start, p.goal, seed=0)
            mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0)
    finally:
        qp.solve = solve
    return recorded


def _key(P, n: int, dof: int = 7) -> tuple[np.ndarray, int]:
    """The order of the variables (the control points time-major, the others after) and their count."""
    C = P.tocoo()
    off = C.row != C.col
    nx = int(max(C.row[off].max(), C.col[off].max())) + 1
    points = nx // dof
    v = np.arange(n)
    return np.where(v < nx, (v % points) * dof + v // points, nx + v).astype(np.int64), nx


def compare(qps: list[dict]) -> dict:
    """Status agreement, solution distance, iterations and CPU per QP of the prototype against PIQP:
    {"qps", "mismatched", "errors" (relative, of the QPs both solved), "iterations", "ms_prototype",
    "ms_piqp", "text"}."""
    errors, iterations, t_ipm, t_piqp, mismatched = [], [], [], [], 0
    for i, r in enumerate(qps):
        P = r["P"]
        n = P.shape[0]
        key, nx = _key(P, n)
        G = np.ascontiguousarray(r["G_T"].T)
        G_csc = sp.csc_matrix(G)  # as the planner gives it to `qp.solve`
        A = np.zeros((0, n)) if r["A"] is None else r["A"].toarray()
        b = np.zeros(0) if r["b"] is None else r["b"]
        t0 = time.thread_time()
        status, z, it = interior_point(P.data, P.indices.astype(np.int64), P.indptr.astype(np.int64), r["q"], G,
                                       r["h"], A, b, r["lb"], r["ub"], key, qp.PIQP_EPS, 0.1 * qp.PIQP_EPS, 60, 1e-9,
                                       1e-7, max(1.0, float(np.abs(r["q"]).max())), 1.0)
        t1 = time.thread_time()
        zp = qp.solve(P, r["q"], G_csc, r["h"], r["A"], r["b"], r["lb"], r["ub"], "piqp")
        t2 = time.thread_time()
        if i:  # the first call compiles
            t_ipm.append(t1 - t0)
            t_piqp.append(t2 - t1)
        iterations.append(it)
        if (zp is None) != (status != SOLVED):
            mismatched += 1
        elif zp is not None:
            errors.append(np.max(np.abs(z[:nx] - zp[:nx])) / max(1.0, np.max(np.abs(zp[:nx]))))
    errors = np.array(errors)
    text = (f"{len(qps)} QPs: status differs on {mismatched}; control points apart (relative) median "
            f"{np.median(errors):.1e}, p98 {np.percentile(errors, 98):.1e}, max {errors.max():.1e}; prototype "
            f"iterations median {np.median(iterations):.0f}, max {max(iterations)}; CPU per QP: prototype "
            f"{np.mean(t_ipm) * 1e3:.3f} ms mean / {np.median(t_ipm) * 1e3:.3f} median, PIQP {np.mean(t_piqp) * 1e3:.3f} / "
            f"{np.median(t_piqp) * 1e3:.3f} ms (setup included)")
    return {"qps": len(qps), "mismatched": mismatched, "errors": errors, "iterations": np.array(iterations),
            "ms_prototype": 1e3 * float(np.mean(t_ipm)), "ms_piqp": 1e3 * float(np.mean(t_piqp)), "text": text}


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
        qps = record(args.limit_per_scene, args.scenes)
        if args.save:
            Path(args.save).write_bytes(pickle.dumps(qps))
    print(compare(qps)["text"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
