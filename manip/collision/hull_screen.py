"""A compiled screen of the exact checker's narrowphase candidates: the pairs whose convex
shapes GJK keeps clearly apart, which coal would find free, decided without coal.

A candidate (configuration, part, obstacle or other part) left by the broadphase goes to coal
(`CollisionChecker._narrowphase`), one Python call each. Before that, one kernel call runs
`collision.gjk.within` on every candidate whose two sides are convex shapes GJK knows: a part's
convex hull (a mesh: its hull's vertices, which hold the mesh; a box, sphere, capsule or
cylinder: itself) against a box, sphere, capsule or cylinder obstacle, or against another
part. A pair GJK proves more than the padding plus `SLACK` apart is free for coal too (the
mesh lies inside its hull, and coal finds a contact only within the padding, up to its own
tolerance, far below `SLACK`), so it is dropped; every other pair still goes to coal, in the
same order. Only "apart" is decided here, never "within" (a surface mesh may hold an obstacle
inside it without touching it, and a mesh may lie up to a millimetre inside its hull): the
answers of every check stay coal's, bit for bit. A pair apart by hulls cannot be one part
wholly inside the other either (`_part_in_part`: the inner part would lie in the outer's hull).
"""

from __future__ import annotations

import numpy as np

from manip.collision import gjk
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Sphere
from manip.jit import kernel

#: [m] a pair is dropped only when GJK proves it more than the padding plus this apart (coal's
#: contacts near the padding are decided to ~1e-9 m; 10 um of screening power is negligible).
SLACK = 1e-5

#: The screen runs. Off: on MotionBenchMaker's Franka plans it costs as much as the coal queries it
#: saves (BENCHMARKS.md, "Round twelve"); the answers are the same either way.
ENABLED = False

NO = -1   # a shape kind this screen does not decide (the pair goes to coal)


def _part_row(part) -> tuple[int, np.ndarray, float, np.ndarray]:
    """(kind, h (3,), rho, vertices (K, 3)) of one part (`collision.tables.Part`) for `gjk`."""
    geom, hull = part.geometry, part.hull
    name = type(geom).__name__
    z = np.zeros((0, 3))
    if name == "Box":
        return gjk.ROUNDED_BOX, np.asarray(geom.halfSide, dtype=float), 0.0, z
    if name == "Sphere":
        return gjk.ROUNDED_BOX, np.zeros(3), float(geom.radius), z
    if name == "Capsule":
        return gjk.ROUNDED_BOX, np.array([0.0, 0.0, float(geom.halfLength)]), float(geom.radius), z
    if name == "Cylinder":
        r = float(geom.radius)
        return gjk.CYLINDER, np.array([r, r, float(geom.halfLength)]), 0.0, z
    if hull is None or hull is geom or not hasattr(hull, "points") or not hasattr(geom, "num_tris"):
        return NO, np.zeros(3), 0.0, z
    P = np.asarray(hull.points(), dtype=float).reshape(-1, 3)
    if P.shape[0] < 4:
        return NO, np.zeros(3), 0.0, z
    return gjk.VERTICES, np.zeros(3), 0.0, np.ascontiguousarray(P)


def part_tables(parts) -> tuple:
    """The parts' arrays of `apart`: kind (G,), h (G, 3), rho (G,), vertex rows start (G,),
    count (G,) of V (N, 3) (each part in its own geometry frame)."""
    rows = [_part_row(p) for p in parts]
    G = len(rows)
    count = np.array([len(r[3]) for r in rows], dtype=np.int64)
    return (np.array([r[0] for r in rows], dtype=np.int64),
            np.ascontiguousarray(np.array([r[1] for r in rows], dtype=float).reshape(G, 3)),
            np.array([r[2] for r in rows], dtype=float),
            np.cumsum(count) - count, count,
            np.ascontiguousarray(np.concatenate([r[3] for r in rows] + [np.zeros((0, 3))]).reshape(-1, 3)))


def obstacle_kinds(obstacles) -> np.ndarray:
    """(O,) the `gjk` kind of each obstacle (`NO` for meshes, occupancy maps, other shapes); its
    placement and size are the broadphase's obstacle tables (`tables.ObstacleTables.broadphase`)."""
    out = np.full(len(obstacles), NO, dtype=np.int64)
    for o, ob in enumerate(obstacles):
        if type(ob) in (Cuboid, Sphere, Capsule):
            out[o] = gjk.ROUNDED_BOX
        elif type(ob) is Cylinder:
            out[o] = gjk.CYLINDER
    return out


@kernel
def apart(kind, a, b, RA, pA, RB, pB, pk, ph, prho, pst, pcn, V, okind, oR, oc, oh, orho, wmargin, smargin):
    """(T,) bool: the candidates (T,) kind (0 = world: part a, obstacle b; 1 = self: parts a, b),
    placed at RA (T, 3, 3), pA (T, 3) (part a) and RB, pB (part b of self pairs) in the base
    frame, that GJK proves more than wmargin (world) or smargin (self) [m] apart. pk..V:
    `part_tables`; okind: `obstacle_kinds`; oR..orho: the broadphase's obstacle tables.

    Each pair's GJK starts from its last direction in this call (the same pair at a nearby
    configuration of the batch: a separating direction decides in one step)."""
    T = kind.shape[0]
    G, O = pk.shape[0], okind.shape[0]
    out = np.zeros(T, dtype=np.bool_)
    last = np.zeros((G, O + G, 3))
    v = np.empty(3)
    for t in range(T):
        g, o = a[t], b[t]
        if pk[g] == NO:
            continue
        col = o if kind[t] == 0 else O + o
        if kind[t] == 0:
            if okind[o] == NO:
                continue
            cb = oc[o]
        else:
            if pk[o] == NO:
                continue
            cb = pB[t]
        if last[g, col, 0] == 0.0 and last[g, col, 1] == 0.0 and last[g, col, 2] == 0.0:
            for k in range(3):
                v[k] = pA[t, k] - cb[k]
        else:
            for k in range(3):
                v[k] = last[g, col, k]
        if kind[t] == 0:
            r = gjk.within_from(pk[g], RA[t], pA[t], ph[g], prho[g], okind[o], oR[o], oc[o], oh[o], orho[o], V,
                                pst[g], pcn[g], 0, 0, wmargin, v)
        else:
            r = gjk.within_from(pk[g], RA[t], pA[t], ph[g], prho[g], pk[o], RB[t], pB[t], ph[o], prho[o], V,
                                pst[g], pcn[g], pst[o], pcn[o], smargin, v)
        for k in range(3):
            last[g, col, k] = v[k]
        out[t] = r == gjk.APART
    return out
