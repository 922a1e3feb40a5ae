"""Compiled (numba) kernels of depth integration (`manip.perception.integrate`).

Cells are those of `manip.collision.occupancy`: cell (i, j, k) is the box [i r, (i + 1) r]^3
(r the resolution) in the robot base frame; a cell is named by one int64 key
(`pack`: 21 bits per axis, |index| < 2^20).

- `sphere_index`, `on_robot`: the robot's balls at q: a grid of the cells near a ball and
  each part's balls with their bounding box, through which the self-filter finds the parts
  (each a 26-DOP) a point may lie on;
- `depth_cells`: back-projects a depth image (pinhole, distance to the image plane) into the
  base frame, drops the points within a ball of the robot and beyond the range, and returns
  the key of each point's cell with the bounds of the points in it (a point within `SNAP`
  [m] before a cell face along its ray counts in the cell behind it, so that a surface on a
  face is held by the cell behind it): the box is the surface as the camera saw it, and what
  a point hides behind it is unknown (not in the box; with `behind` > 0, for
  `unknown="occupied"`, the ray that far behind the point too); at a silhouette (the next pixel sees
  far beyond, or nothing) the bounds reach that pixel's ray at the point's depth, so a
  surface's edge between two rays is held (`manip.perception.observations.reduce_points`
  merges the rows of a repeated key and groups the points: a points map's cell is their hull);
- `cells_seen_free`: which cells every pixel ray through them passes without a hit: the
  ray through a pixel's centre hits its surface at depth d (inf: nothing within range);
  within a cell it is free when d + SNAP exceeds the depth where it leaves the cell's box.
  A cell is seen free when at least one ray passes it and every ray through it is free
  there; a pixel without a measurement (NaN) through it keeps it. Cells partly outside the
  image, or not wholly in front of the camera, are kept.
"""

from __future__ import annotations

import math

import numpy as np

from manip.jit import kernel

#: A point this close before a cell face along its ray (in depth units: metres along the
#: optical axis, at most that many metres along the ray) counts in the cell behind it.
SNAP = 1e-5
#: A neighbouring pixel whose depth is farther by more than max(SILHOUETTE [m], SILHOUETTE_PX
#: pixel footprints) (or unmeasured: NaN / inf) makes a pixel a silhouette (`depth_cells`).
SILHOUETTE = 0.02
SILHOUETTE_PX = 10.0
#: Slots of `depth_cells`' table of the cells written lately (a power of two).
RECENT = 1 << 12
#: Of a run of pixels in one cell, a point within this of the segment between the run's first
#: and last points is not kept [m] (it lies within this of the cell's hull; a plane's interior
#: points, up to a depth image's float32 round-off): `depth_cells`.
RUN_TOLERANCE = 5e-7
#: Points buffered per run before they are written (`depth_cells`).
RUN = 64
_BIAS = 1 << 20
_MASK = (1 << 21) - 1


@kernel(inline="always")
def ifloor(x):
    """int(math.floor(x)) for finite |x| < 2^62, without a libm call (the portable x86-64
    build, SSE2 only, has no rounding instruction)."""
    i = int(x)   # towards zero
    return i - 1 if x < i else i


@kernel(inline="always")
def pack(i, j, k):
    """The int64 key of cell (i, j, k)."""
    return ((i + _BIAS) << 42) | ((j + _BIAS) << 21) | (k + _BIAS)


@kernel
def unpack(keys):
    """(C, 3) int64 cell indices of keys (C,)."""
    out = np.empty((keys.shape[0], 3), dtype=np.int64)
    for n in range(keys.shape[0]):
        key = keys[n]
        out[n, 0] = ((key >> 42) & _MASK) - _BIAS
        out[n, 1] = ((key >> 21) & _MASK) - _BIAS
        out[n, 2] = (key & _MASK) - _BIAS
    return out


@kernel
def pack_all(cells):
    """(C,) keys of cells (C, 3) int64."""
    out = np.empty(cells.shape[0], dtype=np.int64)
    for n in range(cells.shape[0]):
        out[n] = pack(cells[n, 0], cells[n, 1], cells[n, 2])
    return out


@kernel
def sphere_index(centres, radii, ball_part, parts, res):
    """The robot's balls (S, 3), (S,) [m] (of parts ball_part (S,), `parts` of them) for the
    self-filter: (origin (3,) int64, shape (3,) int64, near (cells,) uint8, box (parts, 6) [m],
    start (parts + 1,) int64, balls (S,) int64): `near` marks the cells (of edge `res`, over
    the grid holding every ball) that a ball's box of cells overlaps; `box` is the bounding
    box (lo, hi) of each part's balls and balls[start[g]:start[g + 1]] are part g's balls."""
    S = centres.shape[0]
    lo = np.empty(3, dtype=np.int64)
    hi = np.empty(3, dtype=np.int64)
    for a in range(3):
        lo[a] = 1 << 40
        hi[a] = -(1 << 40)
    for s in range(S):
        for a in range(3):
            lo[a] = min(lo[a], int(math.floor((centres[s, a] - radii[s]) / res)))
            hi[a] = max(hi[a], int(math.floor((centres[s, a] + radii[s]) / res)))
    if S == 0:
        for a in range(3):
            lo[a] = 0
            hi[a] = -1
    shape = np.empty(3, dtype=np.int64)
    for a in range(3):
        shape[a] = hi[a] - lo[a] + 1
    near = np.zeros(shape[0] * shape[1] * shape[2], dtype=np.uint8)
    box = np.empty((parts, 6))
    for g in range(parts):
        for a in range(3):
            box[g, a] = np.inf
            box[g, 3 + a] = -np.inf
    start = np.zeros(parts + 1, dtype=np.int64)
    for s in range(S):
        i0 = int(math.floor((centres[s, 0] - radii[s]) / res)) - lo[0]
        i1 = int(math.floor((centres[s, 0] + radii[s]) / res)) - lo[0]
        j0 = int(math.floor((centres[s, 1] - radii[s]) / res)) - lo[1]
        j1 = int(math.floor((centres[s, 1] + radii[s]) / res)) - lo[1]
        k0 = int(math.floor((centres[s, 2] - radii[s]) / res)) - lo[2]
        k1 = int(math.floor((centres[s, 2] + radii[s]) / res)) - lo[2]
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                base = (i * shape[1] + j) * shape[2]
                for k in range(k0, k1 + 1):
                    near[base + k] = 1
        g = ball_part[s]
        start[g + 1] += 1
        for a in range(3):   # padded: a point in a ball is in its part's box despite rounding
            box[g, a] = min(box[g, a], centres[s, a] - radii[s] - 1e-9)
            box[g, 3 + a] = max(box[g, 3 + a], centres[s, a] + radii[s] + 1e-9)
    for g in range(parts):
        start[g + 1] += start[g]
    balls = np.empty(S, dtype=np.int64)
    fill = start[:parts].copy()
    for s in range(S):
        balls[fill[ball_part[s]]] = s
        fill[ball_part[s]] += 1
    return lo, shape, near, box, start, balls


@kernel(inline="always")
def _in_dop(y0, y1, y2, g, dop, margin):
    """True when the point lies within `margin` [m] of part g's 26-DOP: n.y - d <= margin for
    every face (dop (G, 4, 26): the faces' n (3 rows) and d; a branch-free count)."""
    out = 0
    for f in range(dop.shape[2]):
        out += dop[g, 0, f] * y0 + dop[g, 1, f] * y1 + dop[g, 2, f] * y2 - dop[g, 3, f] > margin
    return out == 0


@kernel(inline="always")
def _on_part(y0, y1, y2, ball, centres, radii, ball_part, dop, margin):
    """True when the point lies in (grown) ball `ball` and within `margin` of its part's 26-DOP."""
    g0 = y0 - centres[ball, 0]
    g1 = y1 - centres[ball, 1]
    g2 = y2 - centres[ball, 2]
    if g0 * g0 + g1 * g1 + g2 * g2 > radii[ball] * radii[ball]:
        return False
    return _in_dop(y0, y1, y2, ball_part[ball], dop, margin)


@kernel(inline="always")
def _robot_ball(y0, y1, y2, centres, radii, dop, margin, box, start, balls):
    """A ball that holds the point, the point within `margin` of its part's 26-DOP (the point
    lies on the robot), or -1 (parts by the boxes of their balls, `sphere_index`)."""
    for g in range(box.shape[0]):
        if not (box[g, 0] <= y0 <= box[g, 3] and box[g, 1] <= y1 <= box[g, 4] and box[g, 2] <= y2 <= box[g, 5]):
            continue
        if not _in_dop(y0, y1, y2, g, dop, margin):
            continue
        for m in range(start[g], start[g + 1]):
            ball = balls[m]
            g0 = y0 - centres[ball, 0]
            g1 = y1 - centres[ball, 1]
            g2 = y2 - centres[ball, 2]
            if g0 * g0 + g1 * g1 + g2 * g2 <= radii[ball] * radii[ball]:
                return ball
    return -1


@kernel(inline="always")
def _robot_point(y0, y1, y2, centres, radii, dop, margin, cell, lo, shape, near, box, start, balls):
    """True when the point lies in a (grown) ball of a part and within `margin` of that part's
    26-DOP (`sphere_index`: the point's cell is near a ball)."""
    i = ifloor(y0 / cell) - lo[0]
    j = ifloor(y1 / cell) - lo[1]
    k = ifloor(y2 / cell) - lo[2]
    if i < 0 or j < 0 or k < 0 or i >= shape[0] or j >= shape[1] or k >= shape[2]:
        return False
    if near[(i * shape[1] + j) * shape[2] + k] == 0:
        return False
    return _robot_ball(y0, y1, y2, centres, radii, dop, margin, box, start, balls) >= 0


@kernel
def on_robot(X, centres, radii, ball_part, dop, margin, cell, lo, shape, near, box, start, balls):
    """(N,) bool: which points X (N, 3) [m] lie on the robot (`_robot_point`; ball_part unused)."""
    out = np.zeros(X.shape[0], dtype=np.bool_)
    for n in range(X.shape[0]):
        out[n] = _robot_point(X[n, 0], X[n, 1], X[n, 2], centres, radii, dop, margin, cell, lo, shape, near, box,
                              start, balls)
    return out


@kernel(inline="always")
def _row_spans(depth):
    """(H,) the first and (H,) the last pixel of each row of depth (H, W) that holds a finite
    non-zero value (a depth, or a negative one), and how many pixels these spans hold (a
    branch-free pass: most of an image is often empty)."""
    H, W = depth.shape
    first = np.empty(H, dtype=np.int64)
    last = np.empty(H, dtype=np.int64)
    n = 0
    for v in range(H):
        some = 0
        for u in range(W):   # a count without branches
            z = depth[v, u]
            some += (z < np.inf) & (z != 0.0)
        f = 0
        g = W - 1
        if some == 0:
            f = W
            g = -1
        else:
            while not (depth[v, f] < np.inf and depth[v, f] != 0.0):
                f += 1
            while not (depth[v, g] < np.inf and depth[v, g] != 0.0):
                g -= 1
        first[v] = f
        last[v] = g
        n += max(g - f + 1, 0)
    return first, last, n


@kernel(inline="always")
def _widen(bounds, row, m0, m1, m2, m3, m4, m5):
    """Widen row `row` of bounds (P, 6) (lo, hi) [m] to hold the box (m0, m1, m2)-(m3, m4, m5)."""
    bounds[row, 0] = min(bounds[row, 0], m0)
    bounds[row, 1] = min(bounds[row, 1], m1)
    bounds[row, 2] = min(bounds[row, 2], m2)
    bounds[row, 3] = max(bounds[row, 3], m3)
    bounds[row, 4] = max(bounds[row, 4], m4)
    bounds[row, 5] = max(bounds[row, 5], m5)


@kernel(inline="always")
def _flush(rb, rn, pts, prow, n, row):
    """Write the run rb[:rn] (rn >= 1, points (RUN, 3) [m]) of row `row` into pts / prow from n:
    its first and last points and those farther than RUN_TOLERANCE from the segment between
    them. Returns the new n."""
    a0, a1, a2 = rb[0, 0], rb[0, 1], rb[0, 2]
    e0, e1, e2 = rb[rn - 1, 0] - a0, rb[rn - 1, 1] - a1, rb[rn - 1, 2] - a2
    ee = e0 * e0 + e1 * e1 + e2 * e2
    for i in range(rn):
        if 0 < i < rn - 1:
            g0, g1, g2 = rb[i, 0] - a0, rb[i, 1] - a1, rb[i, 2] - a2
            s = 0.0 if ee == 0.0 else min(max((g0 * e0 + g1 * e1 + g2 * e2) / ee, 0.0), 1.0)
            h0, h1, h2 = g0 - s * e0, g1 - s * e1, g2 - s * e2
            if h0 * h0 + h1 * h1 + h2 * h2 <= RUN_TOLERANCE * RUN_TOLERANCE:
                continue
        elif i == rn - 1 and rn > 1 and ee == 0.0:
            continue   # the same point again
        _emit(pts, prow, n, row, rb[i, 0], rb[i, 1], rb[i, 2])
        n += 1
    return n


@kernel(inline="always")
def _emit(pts, prow, n, row, x0, x1, x2):
    """Point n (x0, x1, x2) [m] of row `row` into pts (cap, 3) / prow (cap,)."""
    pts[n, 0] = x0
    pts[n, 1] = x1
    pts[n, 2] = x2
    prow[n] = row


@kernel
def depth_cells(depth, fx, fy, cx, cy, R, t, max_range, res, exact, behind, reach_c, reach_r,
                centres, radii, ball_part, dop, margin, cell, lo, shape, near, box, start, balls):
    """Keys (P,) of the cells of the depth image's points (repeats mostly removed), the bounds
    (P, 6) [m] (lo, hi) of the points of each row, the points (N, 3) [m] and the row (N,) of
    each (with `exact`: the measured points but those within RUN_TOLERANCE of the segment
    between the first and last points of their run of pixels in one cell, the silhouettes'
    reach and the rays `behind`; else none), the number of points dropped on the robot and the
    number of negative depths (invalid input: the caller raises).

    Args:
        depth: (H, W) distances to the image plane [m] (inf / NaN: no point).
        fx, fy, cx, cy: pinhole intrinsics [px] (pixel (u, v) = (column, row) at its centre).
        R, t: (3, 3), (3,) the optical frame (x right, y down, z forward) in the base frame.
        max_range: points farther than this from the camera [m] are dropped.
        res: cell edge [m].
        exact: True: each row's bounds are those of its points and rays (module docstring);
            False: the whole cell (`fill="cells"`: no bounds computed per point).
        behind: with `exact`, the bounds also hold each point's ray this far behind it [depth
            units] (clamped to the cell by `OccupancyMap`; `unknown="occupied"`: what a seen
            surface hides in its own cell is unknown, so in the map); 0: the points alone.
        reach_c, reach_r: (3,) and [m]: points outside this ball are dropped (beyond reach).
        centres, radii, ball_part, dop, margin, cell, lo, shape, near, box, start, balls: the
            robot (`_robot_point`): balls grown by the margin, their parts, the parts' 26-DOPs
            (G, 4, 26: `_in_dop`), and the balls' index (`sphere_index` with cells of edge
            `cell` [m]): a point whose cell is near a ball is checked, and kept alone if not
            on the robot.
    """
    H, W = depth.shape
    first, last, cap = _row_spans(depth)
    out = np.empty(cap, dtype=np.int64)   # a row per pixel at most
    bounds = np.empty((cap, 6))
    npts = cap * (6 if behind > 0.0 else 5) if exact else 0   # a point, its ray behind, 4 silhouette reaches
    pts = np.empty((npts, 3))
    prow = np.empty(npts, dtype=np.int64)
    N = 0
    rb = np.empty((RUN, 3))   # the measured points of the current run (`_flush`)
    rn = 0
    recent = np.full(RECENT, -1, dtype=np.int64)   # keys written lately (neighbouring pixels share cells)
    row = np.empty(RECENT, dtype=np.int64)          # their rows
    P = 0
    on_robot = 0
    negative = 0
    hint = -1   # the ball of the last point found on the robot
    rr = reach_r * reach_r
    mr = max_range * max_range
    inv = 1.0 / res
    icell = 1.0 / cell
    box_lo = np.empty(3)
    box_hi = np.empty(3)
    for a in range(3):
        box_lo[a] = lo[a] * cell
        box_hi[a] = (lo[a] + shape[a]) * cell
    check_robot = centres.shape[0] > 0
    A = np.empty(W)
    for u in range(W):
        A[u] = (u - cx) / fx
    # the run of pixels in one cell (row `cr`, key `cur`): its bounds, written back when it ends
    cur = -1
    cr = -1
    m0 = m1 = m2 = m3 = m4 = m5 = 0.0
    for v in range(H):
        b = (v - cy) / fy
        # the direction (a, b, 1) in the base frame is Ra a + Rb (per row: Rb = R[:, 1] b + R[:, 2])
        e0 = R[0, 1] * b + R[0, 2]
        e1 = R[1, 1] * b + R[1, 2]
        e2 = R[2, 1] * b + R[2, 2]
        for u in range(first[v], last[v] + 1):
            z = depth[v, u]
            if not (z > 0.0 and z < np.inf):
                if z < 0.0:
                    negative += 1
                continue
            a = A[u]
            if z * z * (1.0 + a * a + b * b) > mr:
                continue
            d0 = R[0, 0] * a + e0
            d1 = R[1, 0] * a + e1
            d2 = R[2, 0] * a + e2
            x0 = t[0] + z * d0
            x1 = t[1] + z * d1
            x2 = t[2] + z * d2
            f0 = x0 - reach_c[0]
            f1 = x1 - reach_c[1]
            f2 = x2 - reach_c[2]
            if f0 * f0 + f1 * f1 + f2 * f2 > rr:
                continue
            if (check_robot and box_lo[0] <= x0 < box_hi[0] and box_lo[1] <= x1 < box_hi[1]
                    and box_lo[2] <= x2 < box_hi[2]):
                i = min(int((x0 - box_lo[0]) * icell), shape[0] - 1)
                j = min(int((x1 - box_lo[1]) * icell), shape[1] - 1)
                k = min(int((x2 - box_lo[2]) * icell), shape[2] - 1)
                c = (i * shape[1] + j) * shape[2] + k
                if near[c]:   # near the robot: on it (dropped), or a point of its own
                    y0, y1, y2 = x0 + SNAP * d0, x1 + SNAP * d1, x2 + SNAP * d2
                    if hint >= 0 and _on_part(y0, y1, y2, hint, centres, radii, ball_part, dop, margin):
                        on_robot += 1   # the ball of the last point on the robot (neighbouring pixels share it)
                        continue
                    ball = _robot_ball(y0, y1, y2, centres, radii, dop, margin, box, start, balls)
                    if ball >= 0:
                        hint = ball
                        on_robot += 1
                        continue
                    ci, cj, ck = ifloor(y0 * inv), ifloor(y1 * inv), ifloor(y2 * inv)
                    out[P] = pack(ci, cj, ck)
                    if exact:
                        bounds[P, 0] = bounds[P, 3] = x0
                        bounds[P, 1] = bounds[P, 4] = x1
                        bounds[P, 2] = bounds[P, 5] = x2
                        _emit(pts, prow, N, P, x0, x1, x2)
                        N += 1
                    else:
                        bounds[P, 0], bounds[P, 3] = ci * res, (ci + 1) * res
                        bounds[P, 1], bounds[P, 4] = cj * res, (cj + 1) * res
                        bounds[P, 2], bounds[P, 5] = ck * res, (ck + 1) * res
                    P += 1
                    continue
            zs = z + SNAP   # SNAP further along the ray (depth units, as `cells_seen_free`)
            ci = ifloor((t[0] + zs * d0) * inv)
            cj = ifloor((t[1] + zs * d1) * inv)
            ck = ifloor((t[2] + zs * d2) * inv)
            key = pack(ci, cj, ck)
            if not exact:   # whole cells: one row per cell (as far as the recent keys tell)
                if key != cur:
                    cur = key
                    slot = (key ^ (key >> 19) ^ (key >> 37)) & (RECENT - 1)
                    if recent[slot] != key:
                        recent[slot] = key
                        out[P] = key
                        bounds[P, 0], bounds[P, 3] = ci * res, (ci + 1) * res
                        bounds[P, 1], bounds[P, 4] = cj * res, (cj + 1) * res
                        bounds[P, 2], bounds[P, 5] = ck * res, (ck + 1) * res
                        P += 1
                continue
            # the bounds hold the point and its ray `behind` further (0: the point alone)
            zb = z + behind
            y0 = t[0] + zb * d0
            y1 = t[1] + zb * d1
            y2 = t[2] + zb * d2
            if key != cur:   # a new run: the last one's bounds and points into its row; this cell's row
                if cr >= 0:
                    _widen(bounds, cr, m0, m1, m2, m3, m4, m5)
                if rn > 0:
                    N = _flush(rb, rn, pts, prow, N, cr)
                    rn = 0
                cur = key
                slot = (key ^ (key >> 19) ^ (key >> 37)) & (RECENT - 1)
                if recent[slot] != key:
                    recent[slot] = key
                    row[slot] = P
                    out[P] = key
                    bounds[P, 0] = bounds[P, 1] = bounds[P, 2] = np.inf
                    bounds[P, 3] = bounds[P, 4] = bounds[P, 5] = -np.inf
                    P += 1
                cr = row[slot]
                m0, m1, m2 = min(x0, y0), min(x1, y1), min(x2, y2)
                m3, m4, m5 = max(x0, y0), max(x1, y1), max(x2, y2)
            else:
                m0, m1, m2 = min(m0, x0, y0), min(m1, x1, y1), min(m2, x2, y2)
                m3, m4, m5 = max(m3, x0, y0), max(m4, x1, y1), max(m5, x2, y2)
            if rn == RUN:   # a long run: written, and the next one starts where it ended
                N = _flush(rb, rn, pts, prow, N, cr)
                rb[0, 0], rb[0, 1], rb[0, 2] = rb[RUN - 1, 0], rb[RUN - 1, 1], rb[RUN - 1, 2]
                rn = 1
            rb[rn, 0], rb[rn, 1], rb[rn, 2] = x0, x1, x2
            rn += 1
            if behind > 0.0:
                _emit(pts, prow, N, cr, y0, y1, y2)
                N += 1
            # a silhouette: the surface goes on up to the next pixel's ray (whose depth is far
            # beyond, or unmeasured): the bounds take that ray's point at this depth
            far = z + max(SILHOUETTE, SILHOUETTE_PX * z / fx)
            for nb in range(4):
                if nb == 0:
                    uu, vv = u + 1, v
                    if uu >= W:
                        continue
                elif nb == 1:
                    uu, vv = u - 1, v
                    if uu < 0:
                        continue
                elif nb == 2:
                    uu, vv = u, v + 1
                    if vv >= H:
                        continue
                else:
                    uu, vv = u, v - 1
                    if vv < 0:
                        continue
                if depth[vv, uu] < far:
                    continue
                bb = (vv - cy) / fy
                g0 = t[0] + z * (R[0, 0] * A[uu] + R[0, 1] * bb + R[0, 2])
                g1 = t[1] + z * (R[1, 0] * A[uu] + R[1, 1] * bb + R[1, 2])
                g2 = t[2] + z * (R[2, 0] * A[uu] + R[2, 1] * bb + R[2, 2])
                m0, m1, m2 = min(m0, g0), min(m1, g1), min(m2, g2)
                m3, m4, m5 = max(m3, g0), max(m4, g1), max(m5, g2)
                _emit(pts, prow, N, cr, g0, g1, g2)
                N += 1
    if cr >= 0:
        _widen(bounds, cr, m0, m1, m2, m3, m4, m5)
    if rn > 0:
        N = _flush(rb, rn, pts, prow, N, cr)
    return out[:P].copy(), bounds[:P].copy(), pts[:N], prow[:N], on_robot, negative


@kernel
def cells_seen_free(cells, depth, fx, fy, cx, cy, R, t, res, near):
    """(C,) bool: which cells (C, 3) int64 the depth image sees free (module docstring).

    Args:
        depth: (H, W) [m]: inf = nothing hit, NaN = no measurement.
        R, t: the optical frame in the base frame (as `depth_cells`).
        near: cells with a corner closer than this to the camera plane [m] are kept.
    """
    H, W = depth.shape
    C = cells.shape[0]
    out = np.zeros(C, dtype=np.bool_)
    lo = np.empty(3)
    hi = np.empty(3)
    for n in range(C):
        for a in range(3):
            lo[a] = cells[n, a] * res
            hi[a] = (cells[n, a] + 1) * res
        umin, umax, vmin, vmax = np.inf, -np.inf, np.inf, -np.inf
        ok = True
        for corner in range(8):
            q0 = hi[0] if corner & 4 else lo[0]
            q1 = hi[1] if corner & 2 else lo[1]
            q2 = hi[2] if corner & 1 else lo[2]
            # camera coordinates R^T (q - t)
            y0 = R[0, 0] * (q0 - t[0]) + R[1, 0] * (q1 - t[1]) + R[2, 0] * (q2 - t[2])
            y1 = R[0, 1] * (q0 - t[0]) + R[1, 1] * (q1 - t[1]) + R[2, 1] * (q2 - t[2])
            y2 = R[0, 2] * (q0 - t[0]) + R[1, 2] * (q1 - t[1]) + R[2, 2] * (q2 - t[2])
            if y2 <= near:
                ok = False
                break
            uu = fx * y0 / y2 + cx
            vv = fy * y1 / y2 + cy
            umin, umax = min(umin, uu), max(umax, uu)
            vmin, vmax = min(vmin, vv), max(vmax, vv)
        if not ok or umin < -0.5 or vmin < -0.5 or umax > W - 0.5 or vmax > H - 0.5:
            continue
        seen = False
        free = True
        for v in range(int(math.ceil(vmin)), int(math.floor(vmax)) + 1):
            b = (v - cy) / fy
            for u in range(int(math.ceil(umin)), int(math.floor(umax)) + 1):
                a = (u - cx) / fx
                d0 = R[0, 0] * a + R[0, 1] * b + R[0, 2]
                d1 = R[1, 0] * a + R[1, 1] * b + R[1, 2]
                d2 = R[2, 0] * a + R[2, 1] * b + R[2, 2]
                # slabs: the ray t + l d (l = depth) inside the box for l in [l_in, l_out]
                l_in, l_out = -np.inf, np.inf
                for ax in range(3):
                    o = t[ax]
                    d = d0 if ax == 0 else (d1 if ax == 1 else d2)
                    if d == 0.0:
                        if o < lo[ax] or o > hi[ax]:
                            l_in, l_out = 1.0, 0.0
                        continue
                    l1 = (lo[ax] - o) / d
                    l2 = (hi[ax] - o) / d
                    if l1 > l2:
                        l1, l2 = l2, l1
                    l_in = max(l_in, l1)
                    l_out = min(l_out, l2)
                if not (l_in < l_out):
                    continue
                seen = True
                z = depth[v, u]
                if not (z + SNAP > l_out):   # NaN keeps the cell
                    free = False
                    break
            if not free:
                break
        out[n] = seen and free
    return out
