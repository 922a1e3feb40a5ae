"""Exact part-against-map tests decided without coal where a cheap test is conclusive.

A moving part (a triangle mesh, a convex or a box) against the boxes of an occupancy map
(`manip.collision.occupancy.MapGeometry`; a box is a solid, or bounds one: a cell's convex
hull, which these tests only clear): of the boxes in the cells its vertices' box spans,

- a box that a vertex of the part lies in (within coal's security margin) collides: the vertex
  is a point of the part, the box a solid;
- a box with a corner inside a closed part (deeper than its surface may lie under its convex
  hull's boundary) and a corner outside the hull collides: the box crosses the surface;
- a box beyond the margin from the part's vertices' box, or beyond a plane of its 26-DOP or
  of its convex hull, is free: each holds the part;
- a cell's hull (bounded by its box) is free when a plane of the part's 26-DOP or hull, or a
  direction found by Frank-Wolfe iterations, keeps all its points (and their copies) beyond
  the margin from the part's vertices; a point of it inside the closed part collides;
- the others (neither decided) go to coal, the nearest (by the 26-DOP) first.

Each answer is coal's, up to `TOLERANCE` [m] at the boundary (a vertex or corner must be
inside by that much, a separation must exceed the margin by that much; anything closer goes
to coal).
"""

from __future__ import annotations

import math

import numpy as np

from manip.collision.convex_parts import hull_planes, vertices
from manip.collision.occupancy_boxes import index_span
from manip.collision.solids import mesh_arrays, solid_data, weld
from manip.errors import InvalidInputError
from manip.jit import kernel

#: A vertex closer than this to a box's faces, or a separation closer than this to the
#: margin, is left to coal [m].
TOLERANCE = 1e-9
#: Directions tried between a part and a cell's hull before coal decides (`_hull_apart`).
HULL_ITERATIONS = 32

_LOCAL: dict[int, tuple] = {}


def _kdop(V: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 26 planes (unit normals (26, 3), offsets (26,)) of the k-DOP holding points V (P, 3)."""
    D = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if (x, y, z) != (0, 0, 0)],
                 dtype=float)
    D /= np.linalg.norm(D, axis=1)[:, None]
    return np.ascontiguousarray(D), np.ascontiguousarray((V @ D.T).max(axis=0))


def _surface_depth(geometry, V: np.ndarray, eq: np.ndarray, area: float) -> float:
    """How far [m] a closed mesh's surface may lie inside its convex hull's boundary (each
    triangle bounded by the facet plane nearest its three corners); 0 for a convex solid,
    inf for a surface that is not closed."""
    if not hasattr(geometry, "tri_indices"):   # coal.Convex: a solid
        return 0.0
    W, F = weld(V, mesh_arrays(geometry)[1])
    try:
        volume = solid_data(W, F, "part").volume
    except InvalidInputError:   # open or inconsistent: the inside of the hull says nothing
        return np.inf
    below = -(W @ eq[:, :3].T + eq[:, 3])   # (P, facets) >= 0: each vertex's depth under each facet's plane
    depth = float(below[F].max(axis=1).min(axis=1).max())
    # the hull's points deeper than `depth` are all inside the surface, or all outside: then it
    # would enclose no more than the shell between them and the boundary
    return depth if abs(volume) > area * depth else np.inf


def part_hull(geometry) -> tuple[np.ndarray, ...] | None:
    """The data of a part's coal geometry (its frame) for `part_boxes`, or None for a shape
    these tests do not handle (spheres, cylinders, ...: coal alone decides). Cached.

    Returns:
        (vertices (P, 3), 26-DOP normals (26, 3), offsets (26,), convex hull normals (F, 3),
        offsets (F,): n . x <= offset for every point of the part, how far its surface may
        lie inside the hull's boundary (inf: not a closed mesh)) [m].
    """
    got = _LOCAL.get(id(geometry))
    if got is not None and got[0] is geometry:
        return got[1]
    data = None
    if hasattr(geometry, "halfSide"):   # coal.Box
        h = np.asarray(geometry.halfSide, dtype=float)
        V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * h
        data = (V, *_kdop(V), np.vstack([np.eye(3), -np.eye(3)]), np.concatenate([h, h]), 0.0)
    else:
        V = vertices(geometry)   # a BVH mesh's, a coal.Convex's, else None
        if V is not None and V.shape[0] >= 4:
            eq, area = hull_planes(geometry)   # n . x + d <= 0 inside; none when flat: the box and 26-DOP alone
            data = (np.ascontiguousarray(V), *_kdop(V), np.ascontiguousarray(eq[:, :3]), np.ascontiguousarray(-eq[:, 3]),
                    np.inf if not len(eq) else _surface_depth(geometry, V, eq, area))
    if len(_LOCAL) > 4096:
        _LOCAL.clear()
    _LOCAL[id(geometry)] = (geometry, data)
    return data


@kernel(inline="always")
def _placed_planes(N, h, R, t):
    """The planes n . x <= h (N (F, 3), h (F,), part frame) placed at (R, t): (F, 4) (n, h)."""
    out = np.empty((N.shape[0], 4))
    for f in range(N.shape[0]):
        for a in range(3):
            out[f, a] = R[a, 0] * N[f, 0] + R[a, 1] * N[f, 1] + R[a, 2] * N[f, 2]
        out[f, 3] = h[f] + out[f, 0] * t[0] + out[f, 1] * t[1] + out[f, 2] * t[2]
    return out


@kernel(inline="always")
def _separation(Pl, boxes, b):
    """The largest gap [m] between box b and a placed plane of Pl (F, 4) (n, h: n . x <= h
    holds the part) along its normal: a lower bound of their distance (< 0: they overlap)."""
    out = -np.inf
    for f in range(Pl.shape[0]):
        n0, n1, n2 = Pl[f, 0], Pl[f, 1], Pl[f, 2]
        low = (n0 * (boxes[b, 0] if n0 > 0.0 else boxes[b, 3]) + n1 * (boxes[b, 1] if n1 > 0.0 else boxes[b, 4])
               + n2 * (boxes[b, 2] if n2 > 0.0 else boxes[b, 5]))
        out = max(out, low - Pl[f, 3])
    return out


@kernel(inline="always")
def _crosses(Pl, boxes, b, depth):
    """True when a corner of box b lies deeper than `depth` [m] inside the placed planes Pl
    (F, 4) (n, h) and another outside them (each beyond TOLERANCE): the box crosses a closed
    surface lying within `depth` inside their boundary."""
    inside = outside = False
    for c in range(8):
        x0 = boxes[b, 3] if c & 1 else boxes[b, 0]
        x1 = boxes[b, 4] if c & 2 else boxes[b, 1]
        x2 = boxes[b, 5] if c & 4 else boxes[b, 2]
        worst = -np.inf
        for f in range(Pl.shape[0]):
            worst = max(worst, Pl[f, 0] * x0 + Pl[f, 1] * x1 + Pl[f, 2] * x2 - Pl[f, 3])
            if worst > TOLERANCE:
                break
        if worst > TOLERANCE:
            outside = True
        elif worst < -depth - TOLERANCE:
            inside = True
        if inside and outside:
            return True
    return False


@kernel(inline="always")
def _planes_separate(Pl, boxes, b, sep):
    """True when a placed plane of Pl (F, 4) (n, h: n . x <= h holds the part) keeps the part
    more than sep [m] from box b (the box's lowest point along n is beyond it)."""
    for f in range(Pl.shape[0]):
        n0, n1, n2 = Pl[f, 0], Pl[f, 1], Pl[f, 2]
        low = (n0 * (boxes[b, 0] if n0 > 0.0 else boxes[b, 3]) + n1 * (boxes[b, 1] if n1 > 0.0 else boxes[b, 4])
               + n2 * (boxes[b, 2] if n2 > 0.0 else boxes[b, 5]))
        if low - Pl[f, 3] > sep:
            return True
    return False


@kernel(inline="always")
def _points_beyond(Pl, f, X, s0, s1, lo, hi, ext, band, grow, sep):
    """True when every hull point of a cell (its points X[s0:s1] clamped to its box lo-hi, and
    their copies on the box's faces ext (6,) (lo, hi: extended) within `band` of them, grown
    by `grow` [m] along each axis) lies beyond placed plane f of Pl (F, 4) (n, h) by more
    than sep [m]: the plane keeps the cell's hull more than sep from the part."""
    n0, n1, n2, hh = Pl[f, 0], Pl[f, 1], Pl[f, 2], Pl[f, 3]
    g = grow * (abs(n0) + abs(n1) + abs(n2)) + sep
    for i in range(s0, s1):
        val = -hh
        for a in range(3):
            x = min(max(X[i, a], lo[a]), hi[a])
            n = n0 if a == 0 else (n1 if a == 1 else n2)
            val += n * x
            d = 0.0   # the lowest a copy on this axis's faces takes n . x
            if ext[a] and x - lo[a] <= band:
                d = min(d, n * (lo[a] - x))
            if ext[3 + a] and hi[a] - x <= band:
                d = min(d, n * (hi[a] - x))
            val += d
        if not (val > g):
            return False
    return True


@kernel(inline="always")
def _hull_top(u0, u1, u2, X, s0, s1, lo, hi, ext, band, grow):
    """(the largest u . x over a cell's hull (its points X[s0:s1] clamped to the box lo-hi, their
    copies on the box's faces ext (6,) within `band`, grown by `grow` along each axis: a
    bound), the point of X (clamped) reaching it first) for the direction u (unnormalised)."""
    top = -np.inf
    b0 = b1 = b2 = 0.0
    for i in range(s0, s1):
        x0 = min(max(X[i, 0], lo[0]), hi[0])
        x1 = min(max(X[i, 1], lo[1]), hi[1])
        x2 = min(max(X[i, 2], lo[2]), hi[2])
        v = u0 * x0 + u1 * x1 + u2 * x2
        if v > top:
            top, b0, b1, b2 = v, x0, x1, x2
        for a in range(3):   # the copies: a coordinate moved onto a face within the band
            x = x0 if a == 0 else (x1 if a == 1 else x2)
            n = u0 if a == 0 else (u1 if a == 1 else u2)
            d = 0.0
            if ext[a] and x - lo[a] <= band:
                d = max(d, n * (lo[a] - x))
            if ext[3 + a] and hi[a] - x <= band:
                d = max(d, n * (hi[a] - x))
            v += d
        top = max(top, v)
    return top + grow * (abs(u0) + abs(u1) + abs(u2)), b0, b1, b2


@kernel(inline="always")
def _hull_apart(W, X, s0, s1, lo, hi, ext, band, grow, sep):
    """True when a direction is found along which the part's vertices W (P, 3) [m] lie more
    than sep [m] beyond a cell's hull (`_hull_top`): they are apart. The directions are the
    iterates of Frank-Wolfe towards the nearest point of their difference; each is checked on
    its own, so an iteration that goes astray only leaves the pair to coal."""
    x0 = W[0, 0] - min(max(X[s0, 0], lo[0]), hi[0])
    x1 = W[0, 1] - min(max(X[s0, 1], lo[1]), hi[1])
    x2 = W[0, 2] - min(max(X[s0, 2], lo[2]), hi[2])
    for it in range(HULL_ITERATIONS):
        nx = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
        if nx < 1e-12:
            return False
        low = np.inf   # the part's lowest point along x
        a0 = a1 = a2 = 0.0
        for v in range(W.shape[0]):
            val = x0 * W[v, 0] + x1 * W[v, 1] + x2 * W[v, 2]
            if val < low:
                low, a0, a1, a2 = val, W[v, 0], W[v, 1], W[v, 2]
        top, b0, b1, b2 = _hull_top(x0, x1, x2, X, s0, s1, lo, hi, ext, band, grow)
        if (low - top) / nx > sep:
            return True
        # s = a - b: the support of the difference towards -x; the nearest point of [x, s] to 0
        d0, d1, d2 = a0 - b0 - x0, a1 - b1 - x1, a2 - b2 - x2
        dd = d0 * d0 + d1 * d1 + d2 * d2
        gain = -(x0 * d0 + x1 * d1 + x2 * d2)
        if dd < 1e-24 or gain <= 1e-9 * nx * nx:   # x is (nearly) the nearest: not apart by more than sep
            return False
        g = min(gain / dd, 1.0)
        x0, x1, x2 = x0 + g * d0, x1 + g * d1, x2 + g * d2
    return False


@kernel(inline="always")
def _point_inside(Pl, X, s0, s1, lo, hi, depth):
    """True when a point X[s0:s1] (clamped to the box lo-hi: a point of the cell's hull) lies
    deeper than `depth` + TOLERANCE [m] inside the placed planes Pl (F, 4) (n, h): inside a
    closed part whose surface lies within `depth` of them."""
    for i in range(s0, s1):
        x0 = min(max(X[i, 0], lo[0]), hi[0])
        x1 = min(max(X[i, 1], lo[1]), hi[1])
        x2 = min(max(X[i, 2], lo[2]), hi[2])
        worst = -np.inf
        for f in range(Pl.shape[0]):
            worst = max(worst, Pl[f, 0] * x0 + Pl[f, 1] * x1 + Pl[f, 2] * x2 - Pl[f, 3])
            if worst >= -depth - TOLERANCE:
                break
        if worst < -depth - TOLERANCE:
            return True
    return False


@kernel
def part_boxes(boxes, idx, of_cell, origin, res, solid, start, X, box_cell, band, sweep, grow, R, t, V, Nk, hk,
               N, h, depth, margin):
    """The boxes (M, 6) [m] of a map a part may touch, and whether one surely does.

    Args:
        boxes, idx, of_cell, origin, res: the map's (merged or cell) boxes, grid, box of each
            cell, grid origin, cell edge (`MapGeometry`).
        solid: (M,) bool: the box is the solid itself; False: it bounds the convex hull of
            cell box_cell[b]'s points X[start[c]:start[c + 1]] (N, 3) [m] (clamped to the box,
            with their copies within `band` [m] on its faces more than `sweep` [m] beyond
            them, grown by `grow` [m]: `occupancy_hulls`), which a plane of the part's 26-DOP or hull clears, or a point
            inside the part decides; a vertex or a surface in the box decides nothing.
        R, t: (3, 3), (3,) the part's placement; V (P, 3): its vertices, (Nk (D, 3), hk (D,))
            and (N (F, 3), h (F,)): planes n . x <= h holding it (its 26-DOP, its convex hull),
            in its frame (`part_hull`); depth: how far the part's closed surface may lie inside
            its hull's boundary [m] (a box corner deeper than that inside the hull and one
            outside it: the box crosses the part's surface).
        margin: coal's security margin [m].

    Returns:
        (hit: a vertex of the part lies in a solid box (within the margin), a solid box
        crosses its closed surface or a hull's point lies inside it, ids (T,) int64 of the
        boxes left to coal (or to the hulls they bound), nearest by the 26-DOP first).
    """
    P = V.shape[0]
    W = np.empty((P, 3))
    wlo = np.full(3, np.inf)
    whi = np.full(3, -np.inf)
    for v in range(P):
        for a in range(3):
            W[v, a] = R[a, 0] * V[v, 0] + R[a, 1] * V[v, 1] + R[a, 2] * V[v, 2] + t[a]
            wlo[a] = min(wlo[a], W[v, a])
            whi[a] = max(whi[a], W[v, a])
    Pk = _placed_planes(Nk, hk, R, t)
    Ph = np.empty((0, 4))   # the hull's planes placed, when first needed
    sep = margin + TOLERANCE
    inner = margin - TOLERANCE   # a vertex nearer than this to a box (or inside it) collides
    seen = np.zeros(boxes.shape[0], dtype=np.bool_)
    cand = np.empty(64, dtype=np.int64)
    dist = np.empty(64)
    nc = 0
    lo0, hi0 = index_span(wlo[0] - sep, whi[0] + sep, res, origin[0], idx.shape[0])
    lo1, hi1 = index_span(wlo[1] - sep, whi[1] + sep, res, origin[1], idx.shape[1])
    lo2, hi2 = index_span(wlo[2] - sep, whi[2] + sep, res, origin[2], idx.shape[2])
    for i in range(lo0, hi0 + 1):
        for j in range(lo1, hi1 + 1):
            for k in range(lo2, hi2 + 1):
                cell = idx[i, j, k]
                if cell < 0:
                    continue
                b = of_cell[cell]
                if seen[b]:
                    continue
                seen[b] = True
                free = False
                for a in range(3):   # the vertices' box
                    if boxes[b, a] - whi[a] > sep or wlo[a] - boxes[b, 3 + a] > sep:
                        free = True
                        break
                if free:
                    continue
                d = _separation(Pk, boxes, b)   # along the k-DOP's planes: a lower bound
                if d > sep:
                    continue
                if nc == cand.shape[0]:
                    cand = np.concatenate((cand, np.empty(nc, dtype=np.int64)))
                    dist = np.concatenate((dist, np.empty(nc)))
                cand[nc] = b
                dist[nc] = d
                nc += 1
    order = np.argsort(dist[:nc])
    keep = np.empty(nc, dtype=np.int64)
    blo = np.empty(3)
    bhi = np.empty(3)
    pmin = np.empty(3)
    pmax = np.empty(3)
    ext = np.zeros(6, dtype=np.bool_)
    T = 0
    for n in range(nc):   # nearest first: a vertex inside decides; the hull's planes clear
        b = cand[order[n]]
        for v in range(P if solid[b] else 0):
            e0 = max(boxes[b, 0] - W[v, 0], W[v, 0] - boxes[b, 3])
            e1 = max(boxes[b, 1] - W[v, 1], W[v, 1] - boxes[b, 4])
            e2 = max(boxes[b, 2] - W[v, 2], W[v, 2] - boxes[b, 5])
            if max(e0, e1, e2) < -TOLERANCE:   # inside by more than the tolerance
                return True, np.zeros(0, dtype=np.int64)
            if inner > 0.0:
                g0, g1, g2 = max(e0, 0.0), max(e1, 0.0), max(e2, 0.0)
                if g0 * g0 + g1 * g1 + g2 * g2 < inner * inner:
                    return True, np.zeros(0, dtype=np.int64)
        if Ph.shape[0] == 0 and N.shape[0] > 0:
            Ph = _placed_planes(N, h, R, t)
        if _planes_separate(Ph, boxes, b, sep):
            continue
        if solid[b]:
            if depth < np.inf and _crosses(Ph, boxes, b, depth):
                return True, np.zeros(0, dtype=np.int64)
        else:   # the hull's points: a plane of the part that clears them all, or one inside it
            c = box_cell[b]
            s0, s1 = start[c], start[c + 1]
            for a in range(3):
                blo[a] = boxes[b, a]
                bhi[a] = boxes[b, 3 + a]
                pmin[a] = np.inf
                pmax[a] = -np.inf
            for i in range(s0, s1):   # the faces the hull's copies lie on (`occupancy_hulls.hull_points`)
                for a in range(3):
                    x = min(max(X[i, a], blo[a]), bhi[a])
                    pmin[a] = min(pmin[a], x)
                    pmax[a] = max(pmax[a], x)
            for a in range(3):
                ext[a] = pmin[a] - blo[a] > sweep
                ext[3 + a] = bhi[a] - pmax[a] > sweep
            clear = False
            for f in range(Pk.shape[0]):
                if _points_beyond(Pk, f, X, s0, s1, blo, bhi, ext, band, grow, sep):
                    clear = True
                    break
            if not clear:
                for f in range(Ph.shape[0]):
                    if _points_beyond(Ph, f, X, s0, s1, blo, bhi, ext, band, grow, sep):
                        clear = True
                        break
            if clear:
                continue
            if depth < np.inf and Ph.shape[0] > 0 and _point_inside(Ph, X, s0, s1, blo, bhi, depth):
                return True, np.zeros(0, dtype=np.int64)
            if _hull_apart(W, X, s0, s1, blo, bhi, ext, band, grow, sep):
                continue
        keep[T] = b
        T += 1
    return False, keep[:T].copy()
