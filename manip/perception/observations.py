"""Compiled (numba) kernels that merge observations into a map's state (`manip.perception.integrate`).

Cells are named by their int64 keys (`manip.perception.kernels.pack`). One image's rows (a run of
pixels in one cell each) are merged per cell with their points (`reduce_points`); the cells seen
before and not now are found by `difference`; `merge_observation` merges an observation into
the cells seen before (the union of each cell's bounds and points, less the cells it freed).
"""

from __future__ import annotations

import numpy as np

from manip.jit import kernel


@kernel
def reduce_points(keys, bounds, pts, prow):
    """The rows of keys (P,) merged per key: (sorted distinct keys (C,), the union of their
    bounds (P, 6) [m] (lo, hi) (C, 6), start (C + 1,) int64, points (N, 3) [m]: the points of
    key c are points[start[c]:start[c + 1]], those pts (N, 3) of its rows (prow (N,)))."""
    order = np.argsort(keys)
    out = np.empty(keys.shape[0], dtype=np.int64)
    ob = np.empty((keys.shape[0], 6))
    of_row = np.empty(keys.shape[0], dtype=np.int64)
    n = -1
    for m in range(order.shape[0]):
        r = order[m]
        if n < 0 or keys[r] != out[n]:
            n += 1
            out[n] = keys[r]
            for a in range(6):
                ob[n, a] = bounds[r, a]
        else:
            for a in range(3):
                ob[n, a] = min(ob[n, a], bounds[r, a])
                ob[n, 3 + a] = max(ob[n, 3 + a], bounds[r, 3 + a])
        of_row[r] = n
    C = n + 1
    start = np.zeros(C + 1, dtype=np.int64)
    for i in range(prow.shape[0]):
        start[of_row[prow[i]] + 1] += 1
    for c in range(C):
        start[c + 1] += start[c]
    fill = start[:C].copy()
    P = np.empty((prow.shape[0], 3))
    for i in range(prow.shape[0]):
        c = of_row[prow[i]]
        for a in range(3):
            P[fill[c], a] = pts[i, a]
        fill[c] += 1
    return out[:C].copy(), ob[:C].copy(), start, P


@kernel
def difference(a, b):
    """The values of sorted a (A,) not in sorted b (B,) (both distinct), sorted."""
    out = np.empty_like(a)
    n = 0
    j = 0
    for m in range(a.shape[0]):
        while j < b.shape[0] and b[j] < a[m]:
            j += 1
        if j < b.shape[0] and b[j] == a[m]:
            continue
        out[n] = a[m]
        n += 1
    return out[:n].copy()


@kernel(inline="always")
def _copy_points(dst, n, src, s0, s1):
    """src[s0:s1] (K, 3) into dst (cap, 3) from row n (room for them)."""
    for i in range(s0, s1):
        for a in range(3):
            dst[n + i - s0, a] = src[i, a]


@kernel(inline="always")
def _holds_run(A, a0, a1, B, b0, b1):
    """True when the points B[b0:b1] appear, in order and bit for bit, as a run of A[a0:a1]
    (an unchanged view integrated again)."""
    n = b1 - b0
    for k in range(a0, a1 - n + 1):
        same = True
        for i in range(n):
            if A[k + i, 0] != B[b0 + i, 0] or A[k + i, 1] != B[b0 + i, 1] or A[k + i, 2] != B[b0 + i, 2]:
                same = False
                break
        if same:
            return True
    return False


@kernel
def merge_observation(seen, seen_bounds, seen_start, seen_pts, freed, keys, bounds, start, pts, max_points):
    """The cells seen occupied after an observation: (sorted keys (C,), bounds (C, 6) [m],
    start (C + 1,), points (N, 3) [m]) of the cells of seen (S,) (sorted; bounds (S, 6), points
    seen_pts[seen_start[s]:seen_start[s + 1]]) not in freed (sorted, a subset of seen) and of
    keys (K,) (sorted, distinct; bounds (K, 6), points pts[start[k]:start[k + 1]]); a cell in
    both takes the union of its bounds and of its points (its new points are not added again
    when they already are a run of its points: the same view integrated again). A cell
    without points (a box) stays one, and so does a cell whose points would exceed max_points."""
    out = np.empty(seen.shape[0] + keys.shape[0], dtype=np.int64)
    ob = np.empty((out.shape[0], 6))
    ostart = np.zeros(out.shape[0] + 1, dtype=np.int64)
    op = np.empty((seen_pts.shape[0] + pts.shape[0], 3))
    i = 0
    j = 0
    f = 0
    n = 0
    N = 0
    while i < seen.shape[0] or j < keys.shape[0]:
        if i < seen.shape[0]:
            while f < freed.shape[0] and freed[f] < seen[i]:
                f += 1
            if f < freed.shape[0] and freed[f] == seen[i] and (j == keys.shape[0] or keys[j] != seen[i]):
                i += 1   # freed (and not seen occupied again)
                continue
        if j == keys.shape[0] or (i < seen.shape[0] and seen[i] < keys[j]):
            out[n] = seen[i]
            for a in range(6):
                ob[n, a] = seen_bounds[i, a]
            _copy_points(op, N, seen_pts, seen_start[i], seen_start[i + 1])
            N += seen_start[i + 1] - seen_start[i]
            i += 1
        elif i == seen.shape[0] or keys[j] < seen[i]:
            out[n] = keys[j]
            for a in range(6):
                ob[n, a] = bounds[j, a]
            _copy_points(op, N, pts, start[j], start[j + 1])
            N += start[j + 1] - start[j]
            j += 1
        else:
            out[n] = seen[i]
            for a in range(3):
                ob[n, a] = min(seen_bounds[i, a], bounds[j, a])
                ob[n, 3 + a] = max(seen_bounds[i, 3 + a], bounds[j, 3 + a])
            old = seen_start[i + 1] - seen_start[i]
            new = start[j + 1] - start[j]
            if old > 0 and new > 0:
                if _holds_run(seen_pts, seen_start[i], seen_start[i + 1], pts, start[j], start[j + 1]):
                    _copy_points(op, N, seen_pts, seen_start[i], seen_start[i + 1])
                    N += old
                elif old + new <= max_points:
                    _copy_points(op, N, seen_pts, seen_start[i], seen_start[i + 1])
                    _copy_points(op, N + old, pts, start[j], start[j + 1])
                    N += old + new
            i += 1
            j += 1
        n += 1
        ostart[n] = N
    return out[:n].copy(), ob[:n].copy(), ostart[:n + 1].copy(), op[:N].copy()
