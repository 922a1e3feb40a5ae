"""Compiled (numba) kernels of occupancy maps (`manip.collision.occupancy`).

A map is a dense grid `idx` (nx, ny, nz) int32 over cells of edge `res` [m]: cell (i, j, k)
is the box [(o + (i, j, k)) res, (o + (i, j, k) + 1) res] with `o` the grid's integer origin;
idx < 0 where the cell is free, else the row of the cell's own box in `cb` (C, 6) [m] (lo,
hi: a box within the cell, `cell_boxes`). The map is the union of the cells' boxes.
Distances are lower bounds of the distance from a point to that union:

- outside the box [lo, hi] holding every occupied cell: the distance to that box;
- in a block of B^3 cells: `blb[block]`, the distance between that block's box and the
  nearest occupied block's box (an exact Euclidean distance transform of the dilated block
  grid, `OccupancyMap`), which no point of the block can beat;
- near a ball: the exact distance from its centre to the box of every occupied cell within
  reach, visiting only the occupied blocks whose content box (`bocc` (nb0, nb1, nb2, 6) [m]:
  the box holding the block's cells' boxes; lo > hi when empty) can hold a nearer cell, and
  in them only the cells that box spans.

These kernels only filter (as `manip.collision.broadphase`): a pair they cannot clear goes
to coal's exact check on the cells' boxes (`manip.collision.occupancy_boxes`).
"""

from __future__ import annotations

import math

import numpy as np

from manip.jit import kernel

#: A ball whose reach spans more blocks than this per axis is bounded by the blocks only.
MAX_REACH_BLOCKS = 6


@kernel(inline="always")
def _box_distance(x0, x1, x2, lo, hi):
    """Distance [m] from the point (x0, x1, x2) to the box [lo, hi] (0 inside)."""
    a = max(lo[0] - x0, 0.0, x0 - hi[0])
    b = max(lo[1] - x1, 0.0, x1 - hi[1])
    c = max(lo[2] - x2, 0.0, x2 - hi[2])
    return math.sqrt(a * a + b * b + c * c)


@kernel(inline="always")
def _coarse(x0, x1, x2, res, origin, blb, B, lo, hi):
    """A lower bound [m] of the distance from the point to the occupied cells (box, blocks)."""
    d = _box_distance(x0, x1, x2, lo, hi)
    if d > 0.0:
        return d
    b0 = int(math.floor((x0 / res - origin[0]) / B))
    b1 = int(math.floor((x1 / res - origin[1]) / B))
    b2 = int(math.floor((x2 / res - origin[2]) / B))
    if 0 <= b0 < blb.shape[0] and 0 <= b1 < blb.shape[1] and 0 <= b2 < blb.shape[2]:
        return blb[b0, b1, b2]
    return 0.0


@kernel(inline="always")
def _block_range(x0, x1, x2, s, res, origin, bocc, B):
    """The blocks (I0, I1, J0, J1, K0, K1), inclusive, that can hold a point within s [m] of
    the point (x0, x1, x2)."""
    n0, n1, n2 = bocc.shape[0], bocc.shape[1], bocc.shape[2]
    I0 = max(int(math.floor(((x0 - s) / res - origin[0]) / B)), 0)
    I1 = min(int(math.floor(((x0 + s) / res - origin[0]) / B)), n0 - 1)
    J0 = max(int(math.floor(((x1 - s) / res - origin[1]) / B)), 0)
    J1 = min(int(math.floor(((x1 + s) / res - origin[1]) / B)), n1 - 1)
    K0 = max(int(math.floor(((x2 - s) / res - origin[2]) / B)), 0)
    K1 = min(int(math.floor(((x2 + s) / res - origin[2]) / B)), n2 - 1)
    return I0, I1, J0, J1, K0, K1


@kernel(inline="always")
def _cell_span(lo, hi, first, end, res, o):
    """The cells [i0, i1) of the block's cells [first, end) that can hold part of the box
    [lo, hi] along one axis (a cell to spare on each side)."""
    i0 = max(first, int(math.floor(lo / res)) - o - 1)
    i1 = min(end, int(math.floor(hi / res)) - o + 2)
    return i0, i1


@kernel(inline="always")
def _nearest_within(x0, x1, x2, s, stop, idx, cb, res, origin, bocc, B):
    """(the distance [m] from the point to the nearest occupied cell's box if below s, else
    s; that box's nearest point (3 floats), the point itself when none is within s), visiting
    the occupied blocks whose content box (`bocc`) lies within s; returns as soon as a box
    closer than `stop` [m] is found (stop < 0: the nearest)."""
    best = s
    y0, y1, y2 = x0, x1, x2
    I0, I1, J0, J1, K0, K1 = _block_range(x0, x1, x2, s, res, origin, bocc, B)
    for I in range(I0, I1 + 1):
        for J in range(J0, J1 + 1):
            for K in range(K0, K1 + 1):
                if bocc[I, J, K, 0] > bocc[I, J, K, 3]:   # empty
                    continue
                a = max(bocc[I, J, K, 0] - x0, 0.0, x0 - bocc[I, J, K, 3])
                b = max(bocc[I, J, K, 1] - x1, 0.0, x1 - bocc[I, J, K, 4])
                c = max(bocc[I, J, K, 2] - x2, 0.0, x2 - bocc[I, J, K, 5])
                if a * a + b * b + c * c >= best * best:
                    continue
                i0, i1 = _cell_span(bocc[I, J, K, 0], bocc[I, J, K, 3], I * B, min((I + 1) * B, idx.shape[0]), res,
                                    origin[0])
                j0, j1 = _cell_span(bocc[I, J, K, 1], bocc[I, J, K, 4], J * B, min((J + 1) * B, idx.shape[1]), res,
                                    origin[1])
                k0, k1 = _cell_span(bocc[I, J, K, 2], bocc[I, J, K, 5], K * B, min((K + 1) * B, idx.shape[2]), res,
                                    origin[2])
                for i in range(i0, i1):
                    e0 = max((origin[0] + i) * res - x0, 0.0, x0 - (origin[0] + i + 1) * res)
                    for j in range(j0, j1):
                        e1 = max((origin[1] + j) * res - x1, 0.0, x1 - (origin[1] + j + 1) * res)
                        if e0 * e0 + e1 * e1 >= best * best:   # the cell holds its box
                            continue
                        for k in range(k0, k1):
                            m = idx[i, j, k]
                            if m >= 0:
                                f0 = max(cb[m, 0] - x0, 0.0, x0 - cb[m, 3])
                                f1 = max(cb[m, 1] - x1, 0.0, x1 - cb[m, 4])
                                f2 = max(cb[m, 2] - x2, 0.0, x2 - cb[m, 5])
                                e = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
                                if e < best:
                                    best = e
                                    y0 = min(max(x0, cb[m, 0]), cb[m, 3])
                                    y1 = min(max(x1, cb[m, 1]), cb[m, 4])
                                    y2 = min(max(x2, cb[m, 2]), cb[m, 5])
                                    if best < stop:
                                        return best, y0, y1, y2
    return best, y0, y1, y2


@kernel(inline="always")
def ball_clearance(x0, x1, x2, r, need, idx, cb, res, origin, blb, bocc, B, lo, hi):
    """A lower bound [m] of the distance from the ball (centre, radius r) to the occupied
    cells; exact up to `need` (a value >= need means "clear by need")."""
    d = _coarse(x0, x1, x2, res, origin, blb, B, lo, hi) - r
    if d >= need:
        return d
    s = need + r  # cells farther than s from the centre cannot bring the ball within need
    if 2.0 * s > MAX_REACH_BLOCKS * B * res:
        return d
    return max(_nearest_within(x0, x1, x2, s, -1.0, idx, cb, res, origin, bocc, B)[0] - r, d)


@kernel(inline="always")
def ball_near(x0, x1, x2, r, need, idx, cb, res, origin, blb, bocc, B, lo, hi):
    """True when the ball (centre, radius r) may come within `need` [m] of an occupied cell
    (a cell within reach is found, or the reach spans too many blocks to look)."""
    if _coarse(x0, x1, x2, res, origin, blb, B, lo, hi) - r >= need:
        return False
    s = need + r
    if 2.0 * s > MAX_REACH_BLOCKS * B * res:
        return True
    return _nearest_within(x0, x1, x2, s, s, idx, cb, res, origin, bocc, B)[0] < s


@kernel
def map_candidates(R, p, margins, exact_depth,
                   l0_joint, l0_c, l0_r, mem_start, mem_count, mem_parts,
                   part_joint, c_start, c_count, c_centres, c_radii,
                   f_start, f_count, f_centres, f_radii,
                   idx, cb, res, origin, blb, bocc, B, lo, hi):
    """(configuration, moving part) pairs that may come within margins[n] [m] of the map.

    Args:
        R, p: joint frames of N configurations (`Kinematics.joint_transforms`).
        margins: (N,) the margin of each configuration [m].
        exact_depth: True: `depth` is a lower bound of the part's distance, exact for the cells
            within reach (certificates); False: a part stops at its first ball found near and
            `depth` is that ball's coarse bound (an order of likelihood only: boolean checks).
        l0_joint ... f_radii: the robot side of `broadphase.world_candidates` (one ball per
            moving joint, then each part's coarse and fine covers).
        idx, cb, res, origin, blb, bocc, B, lo, hi: the map (module docstring).

    Returns:
        n, part (T,) int64 and depth (T,) [m] (see `exact_depth`).
    """
    N = R.shape[0]
    n_out = np.empty(64, dtype=np.int64)
    g_out = np.empty(64, dtype=np.int64)
    d_out = np.empty(64)
    T = 0
    x = np.empty(3)
    for n in range(N):
        margin = margins[n]
        for k in range(l0_joint.shape[0]):
            j = l0_joint[k]
            for r in range(3):
                x[r] = R[n, j, r, 0] * l0_c[k, 0] + R[n, j, r, 1] * l0_c[k, 1] + R[n, j, r, 2] * l0_c[k, 2] + p[n, j, r]
            if _coarse(x[0], x[1], x[2], res, origin, blb, B, lo, hi) - l0_r[k] >= margin:
                continue
            for mi in range(mem_start[k], mem_start[k] + mem_count[k]):
                g = mem_parts[mi]
                near = False
                for b in range(c_start[g], c_start[g] + c_count[g]):
                    for r in range(3):
                        x[r] = (R[n, j, r, 0] * c_centres[b, 0] + R[n, j, r, 1] * c_centres[b, 1]
                                + R[n, j, r, 2] * c_centres[b, 2] + p[n, j, r])
                    if ball_near(x[0], x[1], x[2], c_radii[b], margin, idx, cb, res, origin, blb, bocc, B, lo, hi):
                        near = True
                        break
                if not near:
                    continue
                m = np.inf
                for b in range(f_start[g], f_start[g] + f_count[g]):
                    for r in range(3):
                        x[r] = (R[n, j, r, 0] * f_centres[b, 0] + R[n, j, r, 1] * f_centres[b, 1]
                                + R[n, j, r, 2] * f_centres[b, 2] + p[n, j, r])
                    if exact_depth:
                        s = ball_clearance(x[0], x[1], x[2], f_radii[b], margin, idx, cb, res, origin, blb, bocc, B, lo, hi)
                    else:
                        if ball_near(x[0], x[1], x[2], f_radii[b], margin, idx, cb, res, origin, blb, bocc, B, lo, hi):
                            m = _coarse(x[0], x[1], x[2], res, origin, blb, B, lo, hi) - f_radii[b]
                            break
                        continue
                    if s < m:
                        m = s
                if m < margin:
                    if T == n_out.shape[0]:
                        n_out = np.concatenate((n_out, np.empty(T, dtype=np.int64)))
                        g_out = np.concatenate((g_out, np.empty(T, dtype=np.int64)))
                        d_out = np.concatenate((d_out, np.empty(T)))
                    n_out[T] = n
                    g_out[T] = g
                    d_out[T] = m
                    T += 1
    return n_out[:T].copy(), g_out[:T].copy(), d_out[:T].copy()


@kernel
def point_lower_bounds(X, idx, cb, res, origin, blb, bocc, B, lo, hi, exact_within):
    """(M,) lower bounds [m] of the distance of points X (M, 3) to the occupied cells, exact
    where they are below `exact_within` [m] (then within the enumerated cells)."""
    out = np.empty(X.shape[0])
    for m in range(X.shape[0]):
        out[m] = ball_clearance(X[m, 0], X[m, 1], X[m, 2], 0.0, exact_within, idx, cb, res, origin, blb, bocc, B, lo, hi)
    return out


@kernel
def cells_contain(X, idx, cb, res, origin):
    """True when a point of X (K, 3) [m] lies in an occupied cell's box (faces included, to 1e-9 m)."""
    for m in range(X.shape[0]):
        for e in (0.0, -1e-9, 1e-9):
            i = int(math.floor((X[m, 0] + e) / res)) - origin[0]
            j = int(math.floor((X[m, 1] + e) / res)) - origin[1]
            k = int(math.floor((X[m, 2] + e) / res)) - origin[2]
            if 0 <= i < idx.shape[0] and 0 <= j < idx.shape[1] and 0 <= k < idx.shape[2] and idx[i, j, k] >= 0:
                c = idx[i, j, k]
                if (cb[c, 0] - 1e-9 <= X[m, 0] <= cb[c, 3] + 1e-9 and cb[c, 1] - 1e-9 <= X[m, 1] <= cb[c, 4] + 1e-9
                        and cb[c, 2] - 1e-9 <= X[m, 2] <= cb[c, 5] + 1e-9):
                    return True
    return False


@kernel
def map_nearest_terms(R, p, centres, radii, joint, bodies, start, count, body_centre, body_radius, activation,
                      idx, cb, res, origin, blb, bocc, B, lo, hi):
    """The clearance terms of `manip.collision.clearance` against a map: for each
    (configuration, body) the ball nearest the occupied cells, kept when closer than
    `activation` [m], with the unit gradient of its centre's distance (from the nearest point
    of the nearest cell). Each ball looks only as far as the nearest found so far (ties: the
    first ball); one whose coarse bound is beyond that is not looked at.

    Returns:
        (n, s (T,) int64, distance (T,) [m], centre x (T, 3), unit normal (T, 3)).
    """
    N = R.shape[0]
    Bn = bodies.shape[0]
    cap = N * Bn
    n_out = np.empty(cap, dtype=np.int64)
    s_out = np.empty(cap, dtype=np.int64)
    d_out = np.empty(cap)
    x_out = np.empty((cap, 3))
    nrm = np.empty((cap, 3))
    x = np.empty(3)
    T = 0
    for n in range(N):
        for b in range(Bn):
            j = bodies[b]
            for r in range(3):
                x[r] = (R[n, j, r, 0] * body_centre[b, 0] + R[n, j, r, 1] * body_centre[b, 1]
                        + R[n, j, r, 2] * body_centre[b, 2] + p[n, j, r])
            if _coarse(x[0], x[1], x[2], res, origin, blb, B, lo, hi) - body_radius[b] >= activation:
                continue
            best = activation   # only a ball nearer than this gives a term
            best_s = -1
            y0 = y1 = y2 = 0.0
            for s in range(start[b], start[b] + count[b]):
                for r in range(3):
                    x[r] = (R[n, j, r, 0] * centres[s, 0] + R[n, j, r, 1] * centres[s, 1]
                            + R[n, j, r, 2] * centres[s, 2] + p[n, j, r])
                if _coarse(x[0], x[1], x[2], res, origin, blb, B, lo, hi) - radii[s] >= best:
                    continue   # cannot be nearer than the best ball so far, nor active
                e, c0, c1, c2 = _nearest_within(x[0], x[1], x[2], best + radii[s], -1.0, idx, cb, res, origin,
                                                bocc, B)
                if e < best + radii[s] and e - radii[s] < best:
                    best = e - radii[s]
                    best_s = s
                    y0, y1, y2 = c0, c1, c2
            if best_s < 0:
                continue
            s = best_s
            for r in range(3):
                x_out[T, r] = (R[n, j, r, 0] * centres[s, 0] + R[n, j, r, 1] * centres[s, 1]
                               + R[n, j, r, 2] * centres[s, 2] + p[n, j, r])
            # the unit direction from the nearest point of the nearest cell to the centre
            g0, g1, g2 = x_out[T, 0] - y0, x_out[T, 1] - y1, x_out[T, 2] - y2
            norm = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
            if norm < 1e-12:   # the centre in a cell: away from that cell's centre
                g0 = x_out[T, 0] - (math.floor(x_out[T, 0] / res) + 0.5) * res
                g1 = x_out[T, 1] - (math.floor(x_out[T, 1] / res) + 0.5) * res
                g2 = x_out[T, 2] - (math.floor(x_out[T, 2] / res) + 0.5) * res
                norm = max(math.sqrt(g0 * g0 + g1 * g1 + g2 * g2), 1e-12)
            nrm[T, 0], nrm[T, 1], nrm[T, 2] = g0 / norm, g1 / norm, g2 / norm
            n_out[T] = n
            s_out[T] = s
            d_out[T] = best
            T += 1
    return n_out[:T].copy(), s_out[:T].copy(), d_out[:T].copy(), x_out[:T].copy(), nrm[:T].copy()
