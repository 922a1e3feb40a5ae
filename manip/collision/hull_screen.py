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
from manip.jit import kernel

#: [m] a pair is dropped only when GJK proves it more than the padding plus this apart (coal's
#: contacts near the padding are decided to ~1e-9 m; 10 um of screening power is negligible).
SLACK = 1e-5

#: The screen runs. Off: on MotionBenchMaker's Franka plans it costs as much as the coal queries it
#: saves (BENCHMARKS.md, "Round twelve"); the answers are the same either way. Its tables
#: (`convex_parts`) are built by the checker at the first check that runs it, not at each edit.
ENABLED = False


@kernel
def apart(kind, a, b, RA, pA, RB, pB, pk, ph, prho, pst, pcn, V, okind, oR, oc, oh, orho, wmargin, smargin):
    """(T,) bool: the candidates (T,) kind (0 = world: part a, obstacle b; 1 = self: parts a, b),
    placed at RA (T, 3, 3), pA (T, 3) (part a) and RB, pB (part b of self pairs) in the base
    frame, that GJK proves more than wmargin (world) or smargin (self) [m] apart. pk..V:
    `convex_parts.part_tables`; okind: `convex_parts.obstacle_kinds`; oR..orho: the broadphase's obstacle tables.

    Each pair's GJK starts from its last direction in this call (the same pair at a nearby
    configuration of the batch: a separating direction decides in one step)."""
    T = kind.shape[0]
    G, O = pk.shape[0], okind.shape[0]
    out = np.zeros(T, dtype=np.bool_)
    last = np.zeros((G, O + G, 3))
    v = np.empty(3)
    for t in range(T):
        g, o = a[t], b[t]
        if pk[g] == gjk.NO:
            continue
        col = o if kind[t] == 0 else O + o
        if kind[t] == 0:
            if okind[o] == gjk.NO:
                continue
            cb = oc[o]
        else:
            if pk[o] == gjk.NO:
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
