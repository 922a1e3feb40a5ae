"""The compiled search's own narrowphase: the broadphase candidates of a configuration decided
in the kernel by `collision.gjk.within` on convex shapes, for the coarse search only.

A part is its convex hull (meshes: the hull's vertices; boxes, spheres, capsules, cylinders of
attached objects: themselves); an obstacle is a box, sphere, capsule or cylinder (meshes,
occupancy maps and other shapes: not decided here). A candidate pair is
- free when GJK keeps the two convex shapes more than the padding apart (certain for any mesh:
  its hull holds it),
- colliding when GJK brings them within the padding and both sides are convex (a closed mesh
  whose triangles all lie within `CONVEX_TOLERANCE` of its hull's boundary; an open mesh never
  counts as convex here: its hull fills what its surface leaves open),
- else left to coal (the `numba.objmode` callback of `compiled_search`), as are the pairs of a
  part with an obstacle it may touch (`CollisionChecker.allowing`) when any is.

The answers may differ from the exact checker's (coal, meshes as triangle surfaces) by up to
`CONVEX_TOLERANCE` and for a part wholly inside a convex mesh, or a mesh wholly inside a
part: the search may then take another path. The guarantees do not depend on it: the coarse
path goes through the fine repairs (coal, at the fine resolution), the shortcut, the optimiser
and the certificate, all with the exact checker. Used by the coarse search only.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import ConvexHull

from manip.collision import gjk
from manip.collision.convex_parts import hull_planes, obstacle_kinds, part_tables
from manip.collision.solids import closed_part_mesh, mesh_arrays
from manip.jit import kernel

#: [m] a mesh is convex for this test when every triangle's vertices and centroid lie within
#: this depth of its hull's boundary (the Panda's collision meshes: 0.03-0.23 mm).
CONVEX_TOLERANCE = 1e-3

_CONCAVITY: dict[int, tuple[object, float]] = {}   # id(mesh) -> (mesh, depth [m])
_LAST_PARTS: tuple = (None, None)                    # (parts, their arrays): `_part_arrays`


def concavity(mesh, hull_points: np.ndarray | None = None, limit: float = np.inf) -> float:
    """The largest depth [m] of a triangle's vertex or centroid of coal mesh `mesh` inside the
    convex hull of hull_points (K, 3) (None: of the mesh's vertices, `convex_parts.hull_planes`)
    (0 for a convex mesh); once a depth exceeds `limit` [m], that depth (the points are visited
    in blocks: a concave mesh stops early)."""
    V, T = mesh_arrays(mesh)
    X = np.concatenate([V, V[T].mean(axis=1)])
    # (F, 4): n . x + d <= 0 inside, |n| = 1
    eq = hull_planes(mesh)[0] if hull_points is None else ConvexHull(hull_points).equations
    worst = 0.0
    for s in range(0, X.shape[0], 512):
        depth = -(X[s:s + 512] @ eq[:, :3].T + eq[:, 3])    # (M, F) >= 0 inside
        worst = max(worst, float(depth.min(axis=1).max()))
        if worst > limit:
            break
    return worst


def _convex(part, kind: int) -> bool:
    """True when part (`collision.tables.Part`) of `convex_parts` kind `kind` is its convex
    shape up to CONVEX_TOLERANCE: a primitive, or a closed mesh no deeper than that under its
    hull's boundary (`concavity`)."""
    geom = part.geometry
    if kind == gjk.NO:
        return False
    if not hasattr(geom, "num_tris"):
        return True
    # an open mesh's hull fills what its surface leaves open (the Kinova's links): a hull
    # within the padding says nothing there, coal decides (and its concavity is not computed:
    # large meshes made that seconds of a first plan's budget)
    if closed_part_mesh(geom, part.name) is None:
        return False
    cached = _CONCAVITY.get(id(geom))
    if cached is None or cached[0] is not geom:
        cached = _CONCAVITY[id(geom)] = (geom, concavity(geom, limit=CONVEX_TOLERANCE))
    return cached[1] <= CONVEX_TOLERANCE


def _part_arrays(parts) -> tuple:
    """`NarrowTables`' part arrays (`convex_parts.part_tables`, the joints and placements, the
    convex flags), kept for the last parts seen (the same `Part` objects in every state of a
    checker until its attachments change)."""
    global _LAST_PARTS
    last, arrays = _LAST_PARTS
    if last is not None and len(last) == len(parts) and all(a is b for a, b in zip(last, parts)):
        return arrays
    kind, h, rho, start, count, V = part_tables(parts)
    G = len(parts)
    arrays = (
        kind,
        np.array([p.joint for p in parts], dtype=np.int64),
        np.ascontiguousarray(np.array([p.R for p in parts], dtype=float).reshape(G, 3, 3)),
        np.ascontiguousarray(np.array([p.p for p in parts], dtype=float).reshape(G, 3)),
        h, rho, start, count, V,
        np.array([_convex(p, int(k)) for p, k in zip(parts, kind)], dtype=np.bool_),
    )
    _LAST_PARTS = (tuple(parts), arrays)
    return arrays


class NarrowTables:
    """The arrays of `decide` for one collision state (`collision.state.CollisionState`).

    parts: kind (G,), joint (G,), R (G, 3, 3), c (G, 3) in the joint frame, h (G, 3), rho (G,),
    vertex rows start (G,), count (G,) of V (N, 3), convex (G,); obstacles: kind (O,) (their
    placements and sizes are the broadphase's `obstacle_tables`); allowed (G, O) bool. With
    state None: empty tables (of the same types, for a search that does not use them).
    """

    def __init__(self, state):
        parts, obstacles = (state.parts, state.obstacles) if state is not None else ((), ())
        (self.kind, self.joint, self.R, self.c, self.h, self.rho, self.start, self.count, self.V,
         self.convex) = _part_arrays(parts)
        G = len(parts)
        self.okind = obstacle_kinds(obstacles)
        allowed = None if state is None else state.allowed_world
        self.allowed = (np.zeros((G, len(obstacles)), dtype=np.bool_) if allowed is None
                        else np.ascontiguousarray(allowed, dtype=np.bool_))
        self.margins = np.zeros(2) if state is None else np.array([state.padding, state.self_padding])

    def arrays(self) -> tuple:
        """The tables in `decide`'s order."""
        return (self.kind, self.joint, self.R, self.c, self.h, self.rho, self.start, self.count, self.V, self.convex,
                self.okind, self.allowed, self.margins)


@kernel
def _place(g, R, p, nt, Rw, cw):
    """Part g's shape placed in the base frame (into Rw (3, 3), cw (3,)) at joint frames R, p."""
    jR, jc = nt[2], nt[3]
    j = nt[1][g]
    for r in range(3):
        cw[r] = p[0, j, r]
        for s in range(3):
            v = 0.0
            for k in range(3):
                v += R[0, j, r, k] * jR[g, k, s]
            Rw[r, s] = v
            cw[r] += R[0, j, r, s] * jc[g, s]


@kernel
def decide(kind, a, b, R, p, nt, ot):
    """The candidates (T,) kind (0 = world, 1 = self), a (part), b (obstacle or part) of the
    configuration with joint frames R (1, J+1, 3, 3), p (1, J+1, 3): (1 when one certainly
    collides, -1 when all are certainly free, else 0), then the mask (T,) of the pairs left to
    coal. nt: `NarrowTables.arrays()`; ot: the broadphase's obstacle tables (R, c, h, rho, cyl)."""
    pk, _, _, _, ph, prho, pst, pcn, V, convex, okind, allowed, margins = nt
    oR, oc, oh, orho = ot[0], ot[1], ot[2], ot[3]
    T = kind.shape[0]
    left = np.zeros(T, dtype=np.bool_)
    Ra, ca, Rb, cb = np.empty((3, 3)), np.empty(3), np.empty((3, 3)), np.empty(3)
    unsure = False
    for t in range(T):
        g, o = a[t], b[t]
        if pk[g] == gjk.NO:
            left[t] = unsure = True
            continue
        _place(g, R, p, nt, Ra, ca)
        if kind[t] == 0:
            if allowed[g, o]:
                continue
            if okind[o] == gjk.NO:
                left[t] = unsure = True
                continue
            r = gjk.within(pk[g], Ra, ca, ph[g], prho[g], okind[o], oR[o], oc[o], oh[o], orho[o], V, pst[g], pcn[g],
                           0, 0, margins[0])
            sure = convex[g]
        else:
            if pk[o] == gjk.NO:
                left[t] = unsure = True
                continue
            _place(o, R, p, nt, Rb, cb)
            r = gjk.within(pk[g], Ra, ca, ph[g], prho[g], pk[o], Rb, cb, ph[o], prho[o], V, pst[g], pcn[g], pst[o],
                           pcn[o], margins[1])
            sure = convex[g] and convex[o]
        if r == gjk.APART:
            continue
        if r == gjk.WITHIN and sure:
            return 1, left
        left[t] = unsure = True
    return (0 if unsure else -1), left
