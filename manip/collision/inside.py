"""Parts and obstacles wholly inside a robot part's closed mesh, for configurations checked on their own.

coal's mesh tests see triangles: a finger wholly inside panda_link5's mesh, or a pebble wholly
inside it, touches none and passes as free, and no sphere-cover candidate need reach it (the
covers hold the surfaces). `InsideTable` lists, once per robot (parts list and checked self
pairs), what could lie inside what: ordered part pairs (a, b) where b's mesh is closed and a is
smaller (`solids.part_volume`), and the closed parts an obstacle could lie in. A kernel screens
each configuration's candidates (the probe centre of a within its probe radius of b's box, then
of b's convex hull, which holds b); `solids.part_in_part` / `solids.contains` decide the few left.

Motions need none of this: a motion that brings a part inside another crosses its surface, which
the checks along the motion see (`collision.checker`, `collision.certify`).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from manip.collision.convex_parts import hull_planes
from manip.collision.solids import closed_part_mesh, contains, part_in_part, part_volume, probe_points
from manip.jit import kernel

__all__ = ["InsideTable", "inside_table", "wholly_inside"]


@dataclass(frozen=True, eq=False)
class InsideTable:
    """What could lie wholly inside what, for one robot (parts list, checked self pairs).

    Attributes:
        parts: the robot's parts (`collision.tables.Part`).
        joint, gR, gp: (G,), (G, 3, 3), (G, 3) each part's joint and geometry frame in it.
        lower, upper: (G, 3) each part's mesh bounding box, its frame [m] (nan: not a mesh).
        centre: (G, 3) the centre of each part's probe points, its joint frame [m];
            radius: (G,) their largest distance from it [m].
        hulls: (G, F, 4) the facets (n, d) of each closed part's convex hull, its frame
            (n . x + d <= 0 inside; padded with facets nothing is outside of).
        size: (G,) half the diagonal of each part's box [m] (an obstacle whose bounding ball is
            larger cannot lie inside it; nan: not a mesh); ball_centre: (G, 3) the box's centre,
            the part's joint frame [m].
        a, b: (K,) the ordered pairs where part a could lie inside part b.
        closed: (B,) the parts with a closed mesh (an obstacle could lie inside them).
    """

    parts: list
    joint: np.ndarray
    gR: np.ndarray
    gp: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    hulls: np.ndarray
    size: np.ndarray
    ball_centre: np.ndarray
    a: np.ndarray
    b: np.ndarray
    closed: np.ndarray


def inside_table(parts, pairs: np.ndarray, part_joint: np.ndarray, gR: np.ndarray, gp: np.ndarray) -> InsideTable:
    """The `InsideTable` of `parts` with checked self pairs `pairs` (P, 2); part_joint, gR, gp as
    its attributes. Cached per parts list and pairs."""
    key = (id(parts), np.asarray(pairs).tobytes())
    hit = _TABLES.get(key)
    if hit is not None and hit[0] is parts:
        return hit[1]
    G = len(parts)
    solid = [closed_part_mesh(part.geometry, part.name) for part in parts]
    volume = [part_volume(part.geometry, s) for part, s in zip(parts, solid)]
    lower, upper = np.full((G, 3), np.nan), np.full((G, 3), np.nan)
    centre, radius, facets = np.zeros((G, 3)), np.zeros(G), []
    for g, part in enumerate(parts):
        if hasattr(part.geometry, "num_tris"):
            V = np.asarray(part.geometry.vertices(), dtype=float).reshape(-1, 3)
            lower[g], upper[g] = V.min(axis=0), V.max(axis=0)
        P = probe_points(part.geometry)
        c = P.mean(axis=0)
        centre[g], radius[g] = gR[g] @ c + gp[g], np.linalg.norm(P - c, axis=1).max()
        facets.append(hull_planes(part.geometry)[0] if solid[g] is not None else np.zeros((0, 4)))   # cached per mesh
    hulls = np.zeros((G, max(len(f) for f in facets) if G else 0, 4))
    hulls[:, :, 3] = -np.inf
    for g, f in enumerate(facets):
        hulls[g, :len(f)] = f
    ordered = []
    for a, b in np.asarray(pairs, dtype=np.int64).reshape(-1, 2).tolist():
        if solid[b] is not None and volume[a] < volume[b]:
            ordered.append((a, b))
        if solid[a] is not None and volume[b] < volume[a]:
            ordered.append((b, a))
    ab = np.array(ordered, dtype=np.int64).reshape(-1, 2)
    tab = InsideTable(parts, np.asarray(part_joint, dtype=np.int64), np.asarray(gR, float), np.asarray(gp, float),
                      lower, upper, centre, radius, hulls, np.linalg.norm(upper - lower, axis=1) / 2,
                      np.einsum("gij,gj->gi", np.asarray(gR, float), (lower + upper) / 2) + gp, ab[:, 0].copy(), ab[:, 1].copy(),
                      np.array([g for g in range(G) if solid[g] is not None], dtype=np.int64))
    if len(_TABLES) > 64:
        _TABLES.clear()
    _TABLES[key] = (parts, tab)
    return tab


_TABLES: dict[tuple, tuple[object, InsideTable]] = {}


def wholly_inside(tab: InsideTable, obstacles, R: np.ndarray, p: np.ndarray, allowed: np.ndarray | None = None,
                  hits: list | None = None) -> np.ndarray:
    """(N,) bool: the configurations, given by their joint frames R (N, J+1, 3, 3), p (N, J+1, 3)
    (base frame), where a part, or an obstacle of `obstacles` (`collision.tables.ObstacleTables`),
    lies wholly inside a part's closed mesh (a probe point of it inside). allowed: (G, O) bool,
    (part, obstacle) pairs not checked; `hits`: when given, every pair found is appended to it,
    all of them: (1, part a, part b) or (0, part b, obstacle o)."""
    out = np.zeros(R.shape[0], dtype=bool)
    kind, other, b, pj, pc, pr = _candidates(tab, obstacles)
    if not b.size or not R.shape[0]:
        return out
    rows, ks = _screen(R, p, pj, pc, pr, b, tab.joint, tab.gR, tab.gp, tab.lower, tab.upper, tab.hulls, tab.ball_centre,
                       tab.size)
    for n, k in zip(rows.tolist(), ks.tolist()):
        g, x = int(b[k]), int(other[k])
        if (out[n] and hits is None) or (not kind[k] and allowed is not None and allowed[g, x]):
            continue
        B, jb = tab.parts[g], tab.joint[g]
        Rb, pb = R[n, jb] @ tab.gR[g], R[n, jb] @ tab.gp[g] + p[n, jb]
        if kind[k]:   # part x inside part g
            A, ja = tab.parts[x], tab.joint[x]
            found = part_in_part(A.geometry, R[n, ja] @ tab.gR[x], R[n, ja] @ tab.gp[x] + p[n, ja],
                                 closed_part_mesh(B.geometry, B.name), B.geometry, Rb, pb)
        else:   # obstacle x inside part g
            tf = obstacles.transforms[x]
            X = probe_points(obstacles.geometries[x]) @ np.asarray(tf.getRotation()).T + np.asarray(tf.getTranslation())
            found = contains(closed_part_mesh(B.geometry, B.name), B.geometry, (X - pb) @ Rb)
        if found:
            out[n] = True
            if hits is not None:
                hits.append((1, x, g) if kind[k] else (0, g, x))
    return out


def _candidates(tab: InsideTable, obstacles) -> tuple[np.ndarray, ...]:
    """The screen's candidates (K,): kind (1: part `other` in part b; 0: obstacle `other` in part
    b), other, b, and the point screened: its joint pj (0: the base frame), its place pc (K, 3) in
    that frame [m], its radius pr [m]. Cached per obstacle tables (weakly) and table."""
    per_world = _CANDIDATES.setdefault(obstacles, {})
    hit = per_world.get(id(tab))
    if hit is not None and hit[0] is tab:
        return hit[1]
    O = len(obstacles.obstacles)
    b_obs, o = np.repeat(tab.closed, O), np.tile(np.arange(O), tab.closed.size)
    ball = np.linalg.norm(obstacles.h, axis=1) + obstacles.rho   # each obstacle's bounding ball, base frame
    fits = ball[o] <= tab.size[b_obs]   # only an obstacle smaller than the part can lie inside it
    b_obs, o = b_obs[fits], o[fits]
    # a primitive's centre lies inside it, so inside the part if it is: no radius; a mesh's box centre need not
    r_obs = np.where([hasattr(obstacles.geometries[k], "num_tris") for k in o.tolist()], ball[o], 0.0)
    K = tab.a.size
    table = (np.r_[np.ones(K, dtype=np.int64), np.zeros(o.size, dtype=np.int64)], np.r_[tab.a, o], np.r_[tab.b, b_obs],
             np.r_[tab.joint[tab.a], np.zeros(o.size, dtype=np.int64)],
             np.ascontiguousarray(np.vstack([tab.centre[tab.a], obstacles.c[o].reshape(-1, 3)])),
             np.r_[tab.radius[tab.a], r_obs])
    if len(per_world) > 8:
        per_world.clear()
    per_world[id(tab)] = (tab, table)
    return table


#: per obstacle tables (held weakly: an edited world's old tables are not kept alive), per robot table
_CANDIDATES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


@kernel
def _screen(R, p, pj, pc, pr, b, joint, gR, gp, lower, upper, hulls, ball_centre, ball_radius):
    """For configurations n (joint frames R (N, J+1, 3, 3), p (N, J+1, 3)) and candidates k (K,):
    where the point pc[k] (joint pj[k]'s frame) lies within pr[k] of part b[k]'s bounding ball
    (ball_centre (G, 3), its joint's frame; ball_radius (G,)), its box (lower, upper (G, 3)) and its
    convex hull (hulls (G, F, 4)), these two in its frame (gR, gp (G, ...) in joint[b[k]]'s frame).
    Returns (M,) rows n and (M,) candidates k."""
    N, K = R.shape[0], pj.shape[0]
    rows = np.empty(N * K, dtype=np.int64)
    ks = np.empty(N * K, dtype=np.int64)
    m = 0
    x = np.empty(3)
    u = np.empty(3)
    y = np.empty(3)
    for n in range(N):
        for k in range(K):
            g, jb, ja = b[k], joint[b[k]], pj[k]
            d2 = 0.0
            for i in range(3):   # the point, base frame, from part g's bounding ball's centre
                x[i] = p[n, ja, i] - p[n, jb, i]
                for j in range(3):
                    x[i] += R[n, ja, i, j] * pc[k, j] - R[n, jb, i, j] * ball_centre[g, j]
                d2 += x[i] * x[i]
            reach = ball_radius[g] + pr[k]
            if d2 > reach * reach:
                continue
            for i in range(3):   # from joint jb's origin
                for j in range(3):
                    x[i] += R[n, jb, i, j] * ball_centre[g, j]
            for j in range(3):   # in joint jb's frame, from the part's origin
                u[j] = -gp[g, j]
                for i in range(3):
                    u[j] += R[n, jb, i, j] * x[i]
            near = True
            for i in range(3):   # in the part's frame
                y[i] = gR[g, 0, i] * u[0] + gR[g, 1, i] * u[1] + gR[g, 2, i] * u[2]
                if not (lower[g, i] - pr[k] <= y[i] <= upper[g, i] + pr[k]):
                    near = False
            if not near:
                continue
            for f in range(hulls.shape[1]):
                if hulls[g, f, 0] * y[0] + hulls[g, f, 1] * y[1] + hulls[g, f, 2] * y[2] + hulls[g, f, 3] > pr[k]:
                    near = False
                    break
            if near:
                rows[m], ks[m] = n, k
                m += 1
    return rows[:m], ks[:m]
