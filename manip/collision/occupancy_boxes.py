"""Compiled (numba) kernels of an occupancy map's boxes (`manip.collision.occupancy`).

Each occupied cell holds a box within it (`cell_boxes`: what was measured in it, extended to
the faces it shares with occupied cells); `merge_boxes` tiles their union with fewer disjoint
boxes (the exact geometry coal tests); `boxes_near_balls` and `near_boxes` pick the boxes a
part may touch (through the map's grid `idx`, of `manip.collision.occupancy_kernels`).
"""

from __future__ import annotations

import math

import numpy as np

from manip.jit import kernel

#: Cell boxes are rounded outwards to multiples of this [m] (`cell_boxes`).
QUANTUM = 1e-4


@kernel
def cell_boxes(cells, bounds, idx, origin, res):
    """The box (C, 6) [m] (lo, hi) of each occupied cell: `bounds` (C, 6) (what the cell
    holds, e.g. the bounds of the points measured in it) rounded outwards to QUANTUM, clamped
    to the cell and extended to each face the cell shares with an occupied cell (so the boxes
    of a surface's cells meet; a flat surface's cells get equal boxes, which merge).

    Args:
        cells: (C, 3) int64 lattice indices; idx: the grid of `OccupancyMap` (row of each cell).
    """
    C = cells.shape[0]
    out = np.empty((C, 6))
    for m in range(C):
        for a in range(3):
            f0 = cells[m, a] * res
            f1 = (cells[m, a] + 1) * res
            lo_ = min(max(math.floor(bounds[m, a] / QUANTUM) * QUANTUM, f0), f1)
            hi_ = min(max(math.ceil(bounds[m, 3 + a] / QUANTUM) * QUANTUM, lo_), f1)
            if lo_ - f0 < 1e-12:   # on a face: the face itself (merged boxes compare faces exactly)
                lo_ = f0
            if f1 - hi_ < 1e-12:
                hi_ = f1
            for side in range(2):
                ii = cells[m, 0] - origin[0]
                jj = cells[m, 1] - origin[1]
                kk = cells[m, 2] - origin[2]
                step = -1 if side == 0 else 1
                if a == 0:
                    ii += step
                elif a == 1:
                    jj += step
                else:
                    kk += step
                inside = 0 <= ii < idx.shape[0] and 0 <= jj < idx.shape[1] and 0 <= kk < idx.shape[2]
                if inside and idx[ii, jj, kk] >= 0:
                    if side == 0:
                        lo_ = f0
                    else:
                        hi_ = f1
            out[m, a] = lo_
            out[m, 3 + a] = hi_
    return out


@kernel
def cell_range(cells):
    """(origin (3,), shape (3,)) int64: the first cell and the extent of the grid holding cells (C, 3) (C > 0)."""
    lo = cells[0].copy()
    hi = cells[0].copy()
    for m in range(1, cells.shape[0]):
        for a in range(3):
            lo[a] = min(lo[a], cells[m, a])
            hi[a] = max(hi[a], cells[m, a])
    return lo, hi - lo + 1


@kernel
def grid_tables(cells, bounds, whole, origin, shape, res, B):
    """The tables of `OccupancyMap` for cells (C, 3) (distinct) in the grid (origin, shape):
    idx (shape) int32 (the row of each occupied cell, -1 elsewhere), the cells' boxes (C, 6)
    (`cell_boxes` of bounds (C, 6) [m], or of whole cells when `whole`), the box (lo, hi) (3,)
    holding them, and the grid of blocks of B^3 cells: the box (6,) (lo, hi) holding each
    block's cells' boxes (lo > hi: an empty block), and occupied or next to an occupied block
    (26-neighbours)."""
    C = cells.shape[0]
    idx = np.full((shape[0], shape[1], shape[2]), -1, dtype=np.int32)
    nb0, nb1, nb2 = -(-shape[0] // B), -(-shape[1] // B), -(-shape[2] // B)
    blocks = np.zeros((nb0, nb1, nb2), dtype=np.bool_)
    for m in range(C):
        i, j, k = cells[m, 0] - origin[0], cells[m, 1] - origin[1], cells[m, 2] - origin[2]
        idx[i, j, k] = m
        blocks[i // B, j // B, k // B] = True
    if whole:
        b = np.empty((C, 6))
        for m in range(C):
            for a in range(3):
                b[m, a] = cells[m, a] * res
                b[m, 3 + a] = (cells[m, a] + 1) * res
    else:
        b = bounds
    cb = cell_boxes(cells, b, idx, origin, res)
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for m in range(C):
        for a in range(3):
            lo[a] = min(lo[a], cb[m, a])
            hi[a] = max(hi[a], cb[m, 3 + a])
    content = np.empty((nb0, nb1, nb2, 6))   # per block the box holding its cells' boxes
    content[..., :3] = np.inf
    content[..., 3:] = -np.inf
    for m in range(C):
        I, J, K = (cells[m, 0] - origin[0]) // B, (cells[m, 1] - origin[1]) // B, (cells[m, 2] - origin[2]) // B
        for a in range(3):
            content[I, J, K, a] = min(content[I, J, K, a], cb[m, a])
            content[I, J, K, 3 + a] = max(content[I, J, K, 3 + a], cb[m, 3 + a])
    grown = np.zeros((nb0, nb1, nb2), dtype=np.bool_)
    for i in range(nb0):
        for j in range(nb1):
            for k in range(nb2):
                if not blocks[i, j, k]:
                    continue
                for a in range(max(i - 1, 0), min(i + 2, nb0)):
                    for e in range(max(j - 1, 0), min(j + 2, nb1)):
                        for f in range(max(k - 1, 0), min(k + 2, nb2)):
                            grown[a, e, f] = True
    return idx, cb, lo, hi, content, grown


@kernel(inline="always")
def _fits(m, used, cb, lo_a, hi_a, face_lo, face_hi, first, last, L, H):
    """True when the cell box m (unused) spans [face_lo, face_hi] along axis `lo_a` (lo column
    index; hi column `hi_a`), or from L (first cell) / to H (last cell) of a growing box."""
    if m < 0 or used[m]:
        return False
    want_lo = L if first else face_lo
    want_hi = H if last else face_hi
    return cb[m, lo_a] == want_lo and cb[m, hi_a] == want_hi


@kernel
def merge_boxes(idx, cb, origin, res):
    """The cells' boxes as fewer disjoint boxes whose union is the same: (M, 6) [m] (lo, hi)
    and the box of each cell (C,) int64 (greedy in grid order: runs along z, grown along y,
    then along x, while the cells' boxes tile a box)."""
    nx, ny, nz = idx.shape
    C = cb.shape[0]
    used = np.zeros(C, dtype=np.bool_)
    of_cell = np.empty(C, dtype=np.int64)
    out = np.empty((64, 6))
    M = 0
    L = np.empty(3)
    H = np.empty(3)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                m0 = idx[i, j, k]
                if m0 < 0 or used[m0]:
                    continue
                for a in range(3):
                    L[a] = cb[m0, a]
                    H[a] = cb[m0, 3 + a]
                k1 = k + 1
                while k1 < nz:
                    f = (origin[2] + k1) * res
                    m = idx[i, j, k1]
                    if (H[2] != f or m < 0 or used[m] or cb[m, 2] != f or cb[m, 0] != L[0] or cb[m, 3] != H[0]
                            or cb[m, 1] != L[1] or cb[m, 4] != H[1]):
                        break
                    H[2] = cb[m, 5]
                    k1 += 1
                j1 = j + 1
                while j1 < ny:
                    f = (origin[1] + j1) * res
                    if H[1] != f:
                        break
                    m = idx[i, j1, k]
                    if m < 0:
                        break
                    top = cb[m, 4]
                    ok = True
                    for kk in range(k, k1):
                        m = idx[i, j1, kk]
                        if not (_fits(m, used, cb, 2, 5, (origin[2] + kk) * res, (origin[2] + kk + 1) * res,
                                      kk == k, kk == k1 - 1, L[2], H[2])
                                and cb[m, 1] == f and cb[m, 4] == top and cb[m, 0] == L[0] and cb[m, 3] == H[0]):
                            ok = False
                            break
                    if not ok:
                        break
                    H[1] = top
                    j1 += 1
                i1 = i + 1
                while i1 < nx:
                    f = (origin[0] + i1) * res
                    if H[0] != f:
                        break
                    m = idx[i1, j, k]
                    if m < 0:
                        break
                    top = cb[m, 3]
                    ok = True
                    for jj in range(j, j1):
                        for kk in range(k, k1):
                            m = idx[i1, jj, kk]
                            if not (_fits(m, used, cb, 2, 5, (origin[2] + kk) * res, (origin[2] + kk + 1) * res,
                                          kk == k, kk == k1 - 1, L[2], H[2])
                                    and _fits(m, used, cb, 1, 4, (origin[1] + jj) * res, (origin[1] + jj + 1) * res,
                                              jj == j, jj == j1 - 1, L[1], H[1])
                                    and cb[m, 0] == f and cb[m, 3] == top):
                                ok = False
                                break
                        if not ok:
                            break
                    if not ok:
                        break
                    H[0] = top
                    i1 += 1
                if M == out.shape[0]:
                    out = np.concatenate((out, np.empty((M, 6))))
                for ii in range(i, i1):
                    for jj in range(j, j1):
                        for kk in range(k, k1):
                            m = idx[ii, jj, kk]
                            used[m] = True
                            of_cell[m] = M
                for a in range(3):
                    out[M, a] = L[a]
                    out[M, 3 + a] = H[a]
                M += 1
    return out[:M].copy(), of_cell


@kernel
def near_boxes(boxes, lo, hi, limit):
    """The boxes (M, 6) [m] within `limit` [m] of the box [lo, hi] (3,): (ids (T,) int64,
    distances (T,) [m] between the two boxes: lower bounds of any geometry's inside [lo, hi])."""
    ids = np.empty(boxes.shape[0], dtype=np.int64)
    d = np.empty(boxes.shape[0])
    T = 0
    for m in range(boxes.shape[0]):
        a = max(boxes[m, 0] - hi[0], 0.0, lo[0] - boxes[m, 3])
        b = max(boxes[m, 1] - hi[1], 0.0, lo[1] - boxes[m, 4])
        c = max(boxes[m, 2] - hi[2], 0.0, lo[2] - boxes[m, 5])
        e = math.sqrt(a * a + b * b + c * c)
        if e < limit:
            ids[T] = m
            d[T] = e
            T += 1
    return ids[:T].copy(), d[:T].copy()


@kernel(inline="always")
def index_span(lo, hi, res, o, n):
    """(first, last) indices (inclusive) along one axis of the grid's cells (edge res [m], the
    first at cell o, n of them) that meet [lo, hi] [m]; first > last when none does."""
    return max(int(math.floor(lo / res)) - o, 0), min(int(math.floor(hi / res)) - o, n - 1)


@kernel
def boxes_near_balls(boxes, idx, of_cell, origin, res, X, r, margin):
    """The boxes (M, 6) [m] within `margin` [m] of a ball (centres X (K, 3), radii r (K,)),
    among those of the cells within reach (idx: the map's grid, of_cell (C,): the box of each
    cell): ids (T,) int64 and the smallest ball-to-box distance (T,) [m] of each."""
    best = np.full(boxes.shape[0], np.inf)
    cand = np.empty(64, dtype=np.int64)
    nc = 0
    for s in range(X.shape[0]):
        reach = r[s] + margin
        lo0, hi0 = index_span(X[s, 0] - reach, X[s, 0] + reach, res, origin[0], idx.shape[0])
        lo1, hi1 = index_span(X[s, 1] - reach, X[s, 1] + reach, res, origin[1], idx.shape[1])
        lo2, hi2 = index_span(X[s, 2] - reach, X[s, 2] + reach, res, origin[2], idx.shape[2])
        for i in range(lo0, hi0 + 1):
            for j in range(lo1, hi1 + 1):
                for k in range(lo2, hi2 + 1):
                    cell = idx[i, j, k]
                    if cell < 0:
                        continue
                    b = of_cell[cell]
                    a = max(boxes[b, 0] - X[s, 0], 0.0, X[s, 0] - boxes[b, 3])
                    e = max(boxes[b, 1] - X[s, 1], 0.0, X[s, 1] - boxes[b, 4])
                    f = max(boxes[b, 2] - X[s, 2], 0.0, X[s, 2] - boxes[b, 5])
                    d = math.sqrt(a * a + e * e + f * f) - r[s]
                    if d >= margin or d >= best[b]:
                        continue
                    if best[b] == np.inf:
                        if nc == cand.shape[0]:
                            cand = np.concatenate((cand, np.empty(nc, dtype=np.int64)))
                        cand[nc] = b
                        nc += 1
                    best[b] = d
    ids = cand[:nc].copy()
    out = np.empty(nc)
    for n in range(nc):
        out[n] = best[ids[n]]
    return ids, out
