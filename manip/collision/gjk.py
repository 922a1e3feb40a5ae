"""A compiled "within margin?" test of two convex shapes (GJK on support functions), for the
compiled coarse search only (`planning.path.compiled_search`).

Shapes, each placed by a rotation R (3, 3) and a centre c (3,) [m] in the base frame:
- `VERTICES`: the convex hull of a vertex set (rows start..start+count of a flat (N, 3) array,
  in the shape's own frame), grown by a rounding rho [m];
- `ROUNDED_BOX`: a box of half extents h (3,) [m] grown by rho [m]: a box (rho 0), a sphere
  (h 0), a capsule (h (0, 0, half length));
- `CYLINDER`: radius h[0], half height h[2] [m] along the local z axis.

`within` runs GJK's distance iteration on the cores (the shapes without their rounding) and
stops as soon as a bound decides: the lower bound of the distance above the margin (plus the
roundings) is a certain "apart", the distance between two points of the shapes at most the
margin a certain "within". When neither bound has decided once the bounds are within
`_EPS` of each other, the upper bound decides (the answer may then differ from coal's only for
a distance within ~1e-9 m of the margin); after `_MAX_ITERATIONS` it answers `UNSURE`.

Not an exact check of the robot's geometry: the coarse search uses it on the parts' convex
hulls (a mesh's hull holds the mesh, so "apart" from the hull is "apart" from the mesh; a
"within" is taken as the mesh's only when the mesh is its hull up to
`compiled_narrowphase.CONVEX_TOLERANCE`), and coal treats meshes as surfaces where this test
treats hulls as solids. The guarantees of a plan never depend on it: the coarse path goes
through the fine repairs (coal), the shortcut, the optimiser and the certificate, which all
use the exact checker. Use it nowhere else.
"""

from __future__ import annotations

import numpy as np

from manip.jit import kernel

VERTICES, ROUNDED_BOX, CYLINDER = 0, 1, 2
NO = -1   # a shape none of these kinds describes: its pairs are left to coal (`collision.convex_parts`)
APART, WITHIN, UNSURE = 0, 1, 2

_MAX_ITERATIONS = 64
_EPS = 1e-10  # [m] bounds this close: converged


@kernel
def support(kind, R, c, h, V, start, count, d, out):
    """The point of the core of shape (kind, R, c, h, V[start:start + count]) (module
    docstring; rounding excluded) furthest along direction d (3,), into out (3,)."""
    l0 = R[0, 0] * d[0] + R[1, 0] * d[1] + R[2, 0] * d[2]   # d in the shape's frame: R^T d
    l1 = R[0, 1] * d[0] + R[1, 1] * d[1] + R[2, 1] * d[2]
    l2 = R[0, 2] * d[0] + R[1, 2] * d[1] + R[2, 2] * d[2]
    if kind == VERTICES:
        best, k = -np.inf, start
        for i in range(start, start + count):
            s = V[i, 0] * l0 + V[i, 1] * l1 + V[i, 2] * l2
            if s > best:
                best, k = s, i
        x, y, z = V[k, 0], V[k, 1], V[k, 2]
    elif kind == ROUNDED_BOX:
        x = h[0] if l0 >= 0 else -h[0]
        y = h[1] if l1 >= 0 else -h[1]
        z = h[2] if l2 >= 0 else -h[2]
    else:
        r = np.sqrt(l0 * l0 + l1 * l1)
        x, y = (h[0] * l0 / r, h[0] * l1 / r) if r > 0 else (0.0, 0.0)
        z = h[2] if l2 >= 0 else -h[2]
    for j in range(3):
        out[j] = c[j] + R[j, 0] * x + R[j, 1] * y + R[j, 2] * z


@kernel
def _solve(G, b, k, lam):
    """lam[:k] = G[:k, :k]^-1 b[:k] (k <= 3, Cramer's rule); False when G is singular."""
    if k == 1:
        if abs(G[0, 0]) < 1e-30:
            return False
        lam[0] = b[0] / G[0, 0]
        return True
    if k == 2:
        det = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
        if abs(det) < 1e-30:
            return False
        lam[0] = (b[0] * G[1, 1] - G[0, 1] * b[1]) / det
        lam[1] = (G[0, 0] * b[1] - b[0] * G[1, 0]) / det
        return True
    det = (G[0, 0] * (G[1, 1] * G[2, 2] - G[1, 2] * G[2, 1]) - G[0, 1] * (G[1, 0] * G[2, 2] - G[1, 2] * G[2, 0])
           + G[0, 2] * (G[1, 0] * G[2, 1] - G[1, 1] * G[2, 0]))
    if abs(det) < 1e-36:
        return False
    for col in range(3):
        M00, M01, M02 = G[0, 0], G[0, 1], G[0, 2]
        M10, M11, M12 = G[1, 0], G[1, 1], G[1, 2]
        M20, M21, M22 = G[2, 0], G[2, 1], G[2, 2]
        if col == 0:
            M00, M10, M20 = b[0], b[1], b[2]
        elif col == 1:
            M01, M11, M21 = b[0], b[1], b[2]
        else:
            M02, M12, M22 = b[0], b[1], b[2]
        lam[col] = (M00 * (M11 * M22 - M12 * M21) - M01 * (M10 * M22 - M12 * M20) + M02 * (M10 * M21 - M11 * M20)) / det
    return True


@kernel
def _closest(Y, n, v, G, b, lam):
    """The point v (3,) of the hull of the simplex Y[:n] (n <= 4, rows of (4, 3)) nearest to the
    origin; Y keeps the vertices of the face it lies on. Returns their count (0: none found)."""
    best = np.inf
    best_mask = 0
    bx, by, bz = 0.0, 0.0, 0.0
    for mask in range(1, 1 << n):
        idx0 = -1
        m = 0
        for i in range(n):
            if mask >> i & 1:
                if idx0 < 0:
                    idx0 = i
                m += 1
        k = m - 1
        # origin projected on the face's affine hull: y0 + sum lam_i (yi - y0)
        r = 0
        ok = True
        if k > 0:
            for i in range(n):
                if i != idx0 and mask >> i & 1:
                    s = 0
                    for i2 in range(n):
                        if i2 != idx0 and mask >> i2 & 1:
                            G[r, s] = ((Y[i, 0] - Y[idx0, 0]) * (Y[i2, 0] - Y[idx0, 0])
                                       + (Y[i, 1] - Y[idx0, 1]) * (Y[i2, 1] - Y[idx0, 1])
                                       + (Y[i, 2] - Y[idx0, 2]) * (Y[i2, 2] - Y[idx0, 2]))
                            s += 1
                    b[r] = -((Y[i, 0] - Y[idx0, 0]) * Y[idx0, 0] + (Y[i, 1] - Y[idx0, 1]) * Y[idx0, 1]
                             + (Y[i, 2] - Y[idx0, 2]) * Y[idx0, 2])
                    r += 1
            ok = _solve(G, b, k, lam)
        if not ok:
            continue
        x, y, z = Y[idx0, 0], Y[idx0, 1], Y[idx0, 2]
        s0 = 1.0
        r = 0
        for i in range(n):
            if i != idx0 and mask >> i & 1:
                if lam[r] < 0:
                    ok = False
                s0 -= lam[r]
                x += lam[r] * (Y[i, 0] - Y[idx0, 0])
                y += lam[r] * (Y[i, 1] - Y[idx0, 1])
                z += lam[r] * (Y[i, 2] - Y[idx0, 2])
                r += 1
        if not ok or s0 < 0:
            continue
        d2 = x * x + y * y + z * z
        if d2 < best:
            best, best_mask, bx, by, bz = d2, mask, x, y, z
    if best_mask == 0:
        return 0
    v[0], v[1], v[2] = bx, by, bz
    m = 0
    for i in range(n):
        if best_mask >> i & 1:
            for j in range(3):
                Y[m, j] = Y[i, j]
            m += 1
    return m


@kernel
def within(ka, Ra, ca, ha, rhoa, kb, Rb, cb, hb, rhob, V, sa, na, sb, nb, margin):
    """APART when shapes a and b (module docstring: kind, R, c, h, rounding [m]; vertex rows
    V[sa:sa + na], V[sb:sb + nb] for `VERTICES`) keep more than `margin` [m] apart, WITHIN when
    they come within it (or overlap), UNSURE when GJK did not decide."""
    v = np.empty(3)
    for j in range(3):
        v[j] = ca[j] - cb[j]
    return within_from(ka, Ra, ca, ha, rhoa, kb, Rb, cb, hb, rhob, V, sa, na, sb, nb, margin, v)


@kernel
def within_from(ka, Ra, ca, ha, rhoa, kb, Rb, cb, hb, rhob, V, sa, na, sb, nb, margin, v):
    """`within`, GJK starting from direction v (3,) (any; a separating direction of a nearby
    placement decides an "apart" in one step), left holding GJK's last direction (the next
    call's start). The answer does not depend on the start, only the iterations it takes, but
    for a distance within ~1e-9 m of the margin (module docstring)."""
    thr = margin + rhoa + rhob
    Y = np.empty((4, 3))
    d = np.empty(3)
    pa = np.empty(3)
    pb = np.empty(3)
    G = np.empty((3, 3))
    bb = np.empty(3)
    lam = np.empty(3)
    if v[0] == 0 and v[1] == 0 and v[2] == 0:
        v[0] = 1.0
    n = 0
    for _ in range(_MAX_ITERATIONS):
        # w = support of (a - b) along -v
        for j in range(3):
            d[j] = -v[j]
        support(ka, Ra, ca, ha, V, sa, na, d, pa)
        for j in range(3):
            d[j] = v[j]
        support(kb, Rb, cb, hb, V, sb, nb, d, pb)
        vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
        vn = np.sqrt(vv)
        vw = 0.0
        for j in range(3):
            vw += v[j] * (pa[j] - pb[j])
        if vw > thr * vn:   # a lower bound of the distance above the margin
            return APART
        if n > 0 and vn <= thr:   # two points of the shapes within the margin
            return WITHIN
        if n > 0 and vv - vw <= _EPS * max(vn, 1e-3):   # converged: the distance is |v|
            return WITHIN if vn <= thr else APART
        for j in range(3):
            Y[n, j] = pa[j] - pb[j]
        n = _closest(Y, n + 1, v, G, bb, lam)
        if n == 0:
            return UNSURE
        if n == 4 or v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= 1e-24:   # the origin is inside: overlap
            return WITHIN
    return UNSURE
