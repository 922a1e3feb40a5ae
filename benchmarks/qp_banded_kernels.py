"""The structure of a QP and the block kernels for `qp_banded`'s interior point (issue 33; split from benchmarks/qp_banded.py
to keep each module under 600 lines): G and A by rows, the kind of each variable, the band, the
clearance rows as Kronecker products and their groups, and where each constant entry of the reduced
matrix is kept (module docstring of `qp_banded`)."""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(nogil=True)
def _row_spread(rptr, ridx, rows, nx, nb):
    """The largest distance in blocks of two control points one row couples (rows in CSR form
    rptr, ridx; columns >= nx are not control points; point of column c: c % nb)."""
    spread = 0
    for r in range(rows):
        lo, hi = nb, -1
        for k in range(rptr[r], rptr[r + 1]):
            if ridx[k] < nx:
                lo = min(lo, ridx[k] % nb)
                hi = max(hi, ridx[k] % nb)
        spread = max(spread, hi - lo)
    return spread


@numba.njit(nogil=True)
def _by_rows(data, indices, indptr, n, rows):
    """(rptr (rows + 1,), column indices, values) of an (rows, n) CSC matrix in CSR, columns ascending."""
    rptr = np.zeros(rows + 1, np.int64)
    for k in range(indptr[n]):
        rptr[indices[k] + 1] += 1
    for r in range(rows):
        rptr[r + 1] += rptr[r]
    ridx = np.empty(indptr[n], np.int64)
    rval = np.empty(indptr[n])
    fill = rptr[:rows].copy()
    for c in range(n):
        for k in range(indptr[c], indptr[c + 1]):
            r = indices[k]
            ridx[fill[r]] = c
            rval[fill[r]] = data[k]
            fill[r] += 1
    return rptr, ridx, rval


@numba.njit(nogil=True, fastmath={"reassoc", "contract"})
def structure(P_data, P_indices, P_indptr, G_data, G_indices, G_indptr, A_data, A_indices, A_indptr, n, m, e, bs, nb,
              delta):
    """P (n, n), G (m, n), A (e, n) CSC; the first bs * nb variables are control points (joint-major).
    Returns (BW, Kaa0, Kb0, Kc0, P_diag, a_ridx, a_rptr, a_rval, g_elim, g_ridx, g_rptr, g_rval, group, idx,
    k_b, k_g, k_p0, kind, kron, n_pair, na, pair_j, pair_k1, pair_k2, row_elim, slot_f, slot_w)."""
    nx = bs * nb
    # --- G and A by rows (CSR), columns ascending
    g_rptr, g_ridx, g_rval = _by_rows(G_data, G_indices, G_indptr, n, m)
    a_rptr, a_ridx, a_rval = _by_rows(A_data, A_indices, A_indptr, n, e)
    # --- kinds: 0 control point (time-major position idx), 1 arrow (idx), 2 eliminated into its
    # G row (one row, no A row, P diagonal only), 3 isolated (no G or A row, P diagonal only)
    P_diag = np.zeros(n)
    diag_only = np.ones(n, np.bool_)
    for c in range(n):
        for k in range(P_indptr[c], P_indptr[c + 1]):
            if P_indices[k] == c:
                P_diag[c] += P_data[k]
            else:
                diag_only[c] = False
                diag_only[P_indices[k]] = False
    kind = np.zeros(n, np.int64)
    idx = np.zeros(n, np.int64)
    row_elim = np.full(m, -1, np.int64)
    g_elim = np.zeros(m)
    na = 0
    for c in range(n):
        if c < nx:
            idx[c] = (c % nb) * bs + c // nb
            continue
        ng = G_indptr[c + 1] - G_indptr[c]
        no_a = A_indptr[c + 1] == A_indptr[c]
        if diag_only[c] and no_a and ng == 0:
            kind[c] = 3
        elif (diag_only[c] and no_a and ng == 1 and row_elim[G_indices[G_indptr[c]]] < 0
              and G_data[G_indptr[c]] != 0.0):
            kind[c] = 2
            j = G_indices[G_indptr[c]]
            row_elim[j] = c
            g_elim[j] = G_data[G_indptr[c]]
            idx[c] = j
        else:
            kind[c] = 1
            idx[c] = na
            na += 1
    # --- the band in blocks: the largest distance of two points one row or P couples
    BW = 0
    for c in range(nx):
        for k in range(P_indptr[c], P_indptr[c + 1]):
            if P_indices[k] < nx:
                BW = max(BW, abs(P_indices[k] % nb - c % nb))
    BW = max(BW, _row_spread(g_rptr, g_ridx, m, nx, nb), _row_spread(a_rptr, a_ridx, e, nx, nb))
    BW = min(BW, nb - 1)
    nbw = BW + 1
    bsq = bs * bs
    # --- clearance rows as Kronecker products: row = b (points p0..p0+BW) x g (joints); rows of
    # one group share p0 and b (one sample), so their G^T W G is (b b^T) x (sum w g g^T)
    kron = np.zeros(m, np.bool_)
    k_p0 = np.zeros(m, np.int64)
    k_b = np.zeros(m * nbw)
    k_g = np.zeros(m * bs)
    tmp = np.zeros(nbw * bs)
    for j in range(m):
        lo, hi, big, kbig, other = nb, -1, 0.0, -1, False
        for k in range(g_rptr[j], g_rptr[j + 1]):
            c = g_ridx[k]
            if c < nx:
                lo = min(lo, c % nb)
                hi = max(hi, c % nb)
                if abs(g_rval[k]) > big:
                    big, kbig = abs(g_rval[k]), k
            elif kind[c] != 2:
                other = True
        if other or kbig < 0 or hi - lo > BW:
            continue
        tmp[:] = 0.0
        for k in range(g_rptr[j], g_rptr[j + 1]):
            c = g_ridx[k]
            if c < nx:
                tmp[(c % nb - lo) * bs + c // nb] = g_rval[k]
        ps, js = g_ridx[kbig] % nb - lo, g_ridx[kbig] // nb
        vs = g_rval[kbig]
        for i in range(bs):
            k_g[j * bs + i] = tmp[ps * bs + i]
        for a in range(nbw):
            k_b[j * nbw + a] = tmp[a * bs + js] / vs
        ok = True
        for a in range(nbw):
            for i in range(bs):
                if abs(tmp[a * bs + i] - k_b[j * nbw + a] * k_g[j * bs + i]) > 1e-13 * big:
                    ok = False
        kron[j] = ok
        k_p0[j] = lo
    group = np.full(m, -1, np.int64)  # each Kronecker row's group (its first row)
    for j in range(m):
        if not kron[j]:
            continue
        group[j] = j
        for jj in range(j):
            if group[jj] == jj and k_p0[jj] == k_p0[j]:
                same = True
                for a in range(nbw):
                    if k_b[jj * nbw + a] != k_b[j * nbw + a]:
                        same = False
                if same:
                    group[j] = jj
                    break
    # --- where each entry K[v1, v2] is kept: x-x in blocks (p1, p1 - p2) for p1 >= p2 (the
    # diagonal blocks full), x-arrow in Kc (x, arrow), arrow-arrow in Kaa (full); the constant
    # part K0 = P + A^T A / delta, then the pairs of the rows of G that are not Kronecker rows
    n_const = P_indptr[n]
    for r in range(e):
        n_const += (a_rptr[r + 1] - a_rptr[r]) ** 2
    n_pair = 0
    for j in range(m):
        if not kron[j]:
            c = 0
            for k in range(g_rptr[j], g_rptr[j + 1]):
                if kind[g_ridx[k]] < 2:
                    c += 1
            n_pair += c * c
    tv1 = np.empty(n_const + n_pair, np.int64)
    tv2 = np.empty(n_const + n_pair, np.int64)
    tval = np.empty(n_const)
    pair_j = np.empty(n_pair, np.int64)
    pair_k1 = np.empty(n_pair, np.int64)
    pair_k2 = np.empty(n_pair, np.int64)
    t = 0
    for c in range(n):
        for k in range(P_indptr[c], P_indptr[c + 1]):
            tv1[t], tv2[t], tval[t] = P_indices[k], c, P_data[k]
            t += 1
    for r in range(e):
        for k1 in range(a_rptr[r], a_rptr[r + 1]):
            for k2 in range(a_rptr[r], a_rptr[r + 1]):
                tv1[t], tv2[t], tval[t] = a_ridx[k1], a_ridx[k2], a_rval[k1] * a_rval[k2] / delta
                t += 1
    for j in range(m):
        if not kron[j]:
            for k1 in range(g_rptr[j], g_rptr[j + 1]):
                if kind[g_ridx[k1]] < 2:
                    for k2 in range(g_rptr[j], g_rptr[j + 1]):
                        if kind[g_ridx[k2]] < 2:
                            tv1[t], tv2[t] = g_ridx[k1], g_ridx[k2]
                            pair_j[t - n_const], pair_k1[t - n_const], pair_k2[t - n_const] = j, k1, k2
                            t += 1
    Kb0 = np.zeros(nb * nbw * bsq)
    Kc0 = np.zeros(nx * na)
    Kaa0 = np.zeros(na * na)
    slot_w = np.full(n_pair, -1, np.int64)  # 0: Kb, 1: Kc, 2: Kaa, -1: not kept
    slot_f = np.zeros(n_pair, np.int64)
    for t in range(n_const + n_pair):
        v1, v2 = tv1[t], tv2[t]
        w, f = -1, 0
        if kind[v1] == 0 and kind[v2] == 0:
            p1, p2 = idx[v1] // bs, idx[v2] // bs
            if p1 >= p2:
                w, f = 0, ((p1 * nbw + p1 - p2) * bs + idx[v1] % bs) * bs + idx[v2] % bs
        elif kind[v1] == 0 and kind[v2] == 1:
            w, f = 1, idx[v1] * na + idx[v2]
        elif kind[v1] == 1 and kind[v2] == 1:
            w, f = 2, idx[v1] * na + idx[v2]
        if t >= n_const:
            slot_w[t - n_const], slot_f[t - n_const] = w, f
        elif w == 0:
            Kb0[f] += tval[t]
        elif w == 1:
            Kc0[f] += tval[t]
        elif w == 2:
            Kaa0[f] += tval[t]
    return (BW, Kaa0, Kb0, Kc0, P_diag, a_ridx, a_rptr, a_rval, g_elim, g_ridx, g_rptr, g_rval, group, idx, k_b,
            k_g, k_p0, kind, kron, n_pair, na, pair_j, pair_k1, pair_k2, row_elim, slot_f, slot_w)


def make_block_kernels(BS):
    """(add_kronecker, cholesky) compiled for the block size BS (the dof) as a constant: loops of BS unrolled."""

    @numba.njit(nogil=True, fastmath={"reassoc", "contract"})
    def add_kronecker(Kb, M, Weff, kron, group, k_g, k_b, k_p0, wg, nbw):
        """Kb += each group's (b b^T) x (sum over its rows of Weff g g^T); M (m * BS^2) and wg (BS,) scratch."""
        bs = BS
        bsq = bs * bs
        m = kron.shape[0]
        for j in range(m):
            if kron[j]:
                gj = group[j]
                if gj == j:
                    for t in range(bsq):
                        M[j * bsq + t] = 0.0
                for i in range(bs):
                    wg[i] = Weff[j] * k_g[j * bs + i]
                for r in range(bs):  # the lower triangle
                    f = k_g[j * bs + r]
                    o = gj * bsq + r * bs
                    for c2 in range(r + 1):
                        M[o + c2] += f * wg[c2]
        for j in range(m):
            if kron[j] and group[j] == j:
                for r in range(bs):  # M's upper triangle from its lower
                    for c2 in range(r):
                        M[j * bsq + c2 * bs + r] = M[j * bsq + r * bs + c2]
                p0 = k_p0[j]
                for a1 in range(nbw):
                    b1 = k_b[j * nbw + a1]
                    if b1 == 0.0:
                        continue
                    f = b1 * b1  # a diagonal block: its lower triangle only (the Cholesky reads no more)
                    o = (p0 + a1) * nbw * bsq
                    for r in range(bs):
                        for c2 in range(r + 1):
                            Kb[o + r * bs + c2] += f * M[j * bsq + r * bs + c2]
                    for a2 in range(a1):
                        f = b1 * k_b[j * nbw + a2]
                        if f == 0.0:
                            continue
                        o = ((p0 + a1) * nbw + a1 - a2) * bsq
                        for t in range(bsq):
                            Kb[o + t] += f * M[j * bsq + t]

    @numba.njit(nogil=True, fastmath={"reassoc", "contract"})
    def cholesky(Kb, Kc, Kaa, dK, inv_x, inv_a, nb, BW, na):
        """Factor the reduced matrix in place: the block band Kb (nb points, BW blocks below the diagonal),
        the arrow Kc (nx, na) solved, its Schur complement Kaa (na, na); inv_x, inv_a the pivots' inverses,
        dK the diagonal before. Returns False on a non-finite pivot (a lost pivot is replaced by dK's)."""
        bs = BS
        bsq = bs * bs
        nbw = BW + 1
        nx = bs * nb
        # block Cholesky: L[p, d] = the block (p, p - d); Y = Kc's columns solved (the arrow)
        for i in range(nx):
            dK[i] = Kb[(i // bs) * nbw * bsq + (i % bs) * (bs + 1)]
        for i in range(na):
            dK[nx + i] = Kaa[i * (na + 1)]
        ok = True
        for p in range(nb):
            for d in range(min(BW, p), -1, -1):
                qq = p - d
                o = (p * nbw + d) * bsq
                for kk in range(max(p - BW, 0), qq):
                    oa = (p * nbw + p - kk) * bsq
                    ob = (qq * nbw + qq - kk) * bsq
                    if d > 0:  # loops of constant length: unrolled
                        for r in range(bs):
                            for c2 in range(bs):
                                acc = 0.0
                                for t in range(bs):
                                    acc += Kb[oa + r * bs + t] * Kb[ob + c2 * bs + t]
                                Kb[o + r * bs + c2] -= acc
                    else:  # the lower triangle
                        for r in range(bs):
                            for c2 in range(r + 1):
                                acc = 0.0
                                for t in range(bs):
                                    acc += Kb[oa + r * bs + t] * Kb[ob + c2 * bs + t]
                                Kb[o + r * bs + c2] -= acc
                od = qq * nbw * bsq
                if d > 0:  # X L_qq^{-T}, by rows
                    for r in range(bs):
                        for c2 in range(bs):
                            acc = Kb[o + r * bs + c2]
                            for t in range(c2):
                                acc -= Kb[o + r * bs + t] * Kb[od + c2 * bs + t]
                            Kb[o + r * bs + c2] = acc * inv_x[qq * bs + c2]
                else:  # dense Cholesky of the diagonal block (lower)
                    for r in range(bs):
                        for c2 in range(r + 1):
                            acc = Kb[o + r * bs + c2]
                            for t in range(c2):
                                acc -= Kb[o + r * bs + t] * Kb[o + c2 * bs + t]
                            if c2 < r:
                                Kb[o + r * bs + c2] = acc * inv_x[p * bs + c2]
                            else:
                                if not acc > 1e-12 * dK[p * bs + r]:
                                    if not math.isfinite(acc):
                                        ok = False
                                    acc = dK[p * bs + r]
                                dd = math.sqrt(acc)
                                Kb[o + r * bs + r] = dd
                                inv_x[p * bs + r] = 1.0 / dd
            if na:  # Y_p = L_pp^{-1} (Kc_p - sum_k L[p, k] Y_k)
                for kk in range(max(p - BW, 0), p):
                    oa = (p * nbw + p - kk) * bsq
                    for r in range(bs):
                        for t in range(bs):
                            f = Kb[oa + r * bs + t]
                            for a in range(na):
                                Kc[(p * bs + r) * na + a] -= f * Kc[(kk * bs + t) * na + a]
                od = p * nbw * bsq
                for r in range(bs):
                    for t in range(r):
                        f = Kb[od + r * bs + t]
                        for a in range(na):
                            Kc[(p * bs + r) * na + a] -= f * Kc[(p * bs + t) * na + a]
                    for a in range(na):
                        Kc[(p * bs + r) * na + a] *= inv_x[p * bs + r]
        for x in range(nx):  # S = Kaa - Y^T Y, then its Cholesky (lower)
            for a1 in range(na):
                f = Kc[x * na + a1]
                for a2 in range(a1 + 1):
                    Kaa[a1 * na + a2] -= f * Kc[x * na + a2]
        for r in range(na):
            for c2 in range(r + 1):
                acc = Kaa[r * na + c2]
                for t in range(c2):
                    acc -= Kaa[r * na + t] * Kaa[c2 * na + t]
                if c2 < r:
                    Kaa[r * na + c2] = acc * inv_a[c2]
                else:
                    if not acc > 1e-12 * dK[nx + r]:
                        if not math.isfinite(acc):
                            ok = False
                        acc = dK[nx + r]
                    dd = math.sqrt(acc)
                    Kaa[r * na + r] = dd
                    inv_a[r] = 1.0 / dd
        return ok

    return add_kronecker, cholesky
