"""Closed triangle meshes as solids: the watertightness check and the inside test.

coal checks a mesh obstacle's triangles: a surface. A `Mesh(..., solid=True)` obstacle is
the volume its closed surface bounds: a robot part inside it collides although it touches
no triangle. A part that does not touch the surface lies, piece by connected piece, wholly
inside or wholly outside the volume, so one point of each piece decides (`probe_points`).
A point is inside when it lies behind the surface at its closest point, judged by the
angle-weighted pseudonormal of the closest feature (face, edge or vertex), which is exact
for a closed, consistently oriented 2-manifold (J. A. Baerentzen and H. Aanaes, "Signed
distance computation using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005). The
closest triangle comes from coal's exact distance on the obstacle's BVH.

For a continuous motion the same holds: a motion certified never to come within the
padding of the surface keeps every piece on its side, so the side at the start decides
(`manip.collision.certify`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import coal
import numpy as np

from manip.errors import InvalidInputError
from manip.jit import kernel

#: A probe point closer than this to the surface [m] counts as inside (touching).
ON_SURFACE = 1e-9


def weld(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices at exactly the same position (STL files repeat them per triangle).

    Args:
        V: (V, 3) vertices; F: (F, 3) indices into V.

    Returns:
        (vertices (V', 3), faces (F, 3) indices into them), vertices in first-use order of a sort.
    """
    V = np.ascontiguousarray(V, dtype=float) + 0.0   # -0.0 == 0.0
    order = np.lexsort(V.T[::-1])
    S = V[order]
    new = np.r_[True, np.any(S[1:] != S[:-1], axis=1)]
    ids = np.empty(len(V), dtype=np.int64)
    ids[order] = np.cumsum(new) - 1
    return S[new], ids[F]


@dataclass(frozen=True, eq=False)
class SolidData:
    """The normals of a closed mesh for the inside test (mesh frame, scaled).

    Attributes:
        face_normals: (F, 3) outward unit normals.
        face_edges: (F, 3) edge index of each triangle's edges (v0 v1, v1 v2, v2 v0).
        edge_normals: (E, 3) edge pseudonormals (the sum of the two faces' normals).
        vertex_normals: (V, 3) angle-weighted vertex pseudonormals.
        lower, upper: (3,) the bounding box [m].
        volume: the enclosed volume [m^3].
    """

    vertices: np.ndarray
    faces: np.ndarray
    face_normals: np.ndarray
    face_edges: np.ndarray
    edge_normals: np.ndarray
    vertex_normals: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    volume: float


def solid_data(V: np.ndarray, F: np.ndarray, name: str) -> SolidData:
    """Check that (V, F) (welded, scaled) bound a volume and compute its normals.

    Raises:
        InvalidInputError: naming the mesh, when an edge does not belong to exactly two
            triangles (an open or non-manifold surface), two triangles sharing an edge are
            oriented oppositely, or the surface encloses no volume.
    """
    what = f"mesh '{name}' (solid=True)"
    F = np.asarray(F, dtype=np.int64)
    if np.any((F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 0] == F[:, 2])):
        raise InvalidInputError(f"{what}: has triangles with a repeated vertex; a solid needs proper triangles")
    directed = np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)   # (3F, 2): v_k -> v_k+1
    key_lo, key_hi = directed.min(axis=1), directed.max(axis=1)
    keys, edge_of, count = np.unique(key_lo * len(V) + key_hi, return_inverse=True, return_counts=True)
    edges = np.stack([keys // len(V), keys % len(V)], axis=1)
    edge_of = edge_of.reshape(-1)
    bad = np.flatnonzero(count != 2)
    if bad.size:
        open_ = int(np.sum(count[bad] == 1))
        raise InvalidInputError(
            f"{what}: not a closed surface: {bad.size} edge(s) belong to {'1' if open_ == bad.size else '1 or 3+'} "
            f"triangle(s) instead of 2 (e.g. the edge between vertices {edges[bad[0]].tolist()} at "
            f"{V[edges[bad[0]]].round(6).tolist()}); give a watertight mesh, or leave solid=False (a surface)")
    forward = (directed[:, 0] < directed[:, 1]).astype(np.int64)
    per_edge = np.bincount(edge_of, weights=forward, minlength=len(edges))
    flipped = np.flatnonzero(per_edge != 1)   # both triangles run the edge the same way
    if flipped.size:
        raise InvalidInputError(
            f"{what}: triangles are not consistently oriented: {flipped.size} edge(s) are run the same way by "
            f"both their triangles (e.g. between vertices {edges[flipped[0]].tolist()}); orient every triangle "
            "counter-clockwise seen from outside (or all clockwise)")
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    cross = np.cross(b - a, c - a)
    volume = float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)
    extent = float(np.max(V.max(axis=0) - V.min(axis=0)))
    if not abs(volume) > 1e-12 * extent ** 3:
        raise InvalidInputError(f"{what}: the surface encloses no volume ({volume:g} m^3)")
    sign = 1.0 if volume > 0 else -1.0   # inside-out meshes are turned outward
    area2 = np.linalg.norm(cross, axis=1)
    n = sign * cross / np.where(area2 > 0, area2, 1.0)[:, None]
    face_edges = edge_of.reshape(-1, 3)
    edge_normals = np.zeros((len(edges), 3))
    np.add.at(edge_normals, face_edges.ravel(), np.repeat(n, 3, axis=0))
    # angle of each triangle at each of its corners
    vertex_normals = np.zeros((len(V), 3))
    corners = (a, b, c)
    for k in range(3):
        p, q, r = corners[k], corners[(k + 1) % 3], corners[(k + 2) % 3]
        u, w = q - p, r - p
        ang = np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), np.einsum("ij,ij->i", u, w))
        np.add.at(vertex_normals, F[:, k], ang[:, None] * n)
    return SolidData(V, F, n, face_edges, edge_normals, vertex_normals, V.min(axis=0), V.max(axis=0), abs(volume))


def _closest_feature(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, int]:
    """The closest point of triangle abc to p and its feature: 0, 1, 2 the vertices a, b, c;
    3, 4, 5 the edges ab, bc, ca; 6 the face (C. Ericson, Real-Time Collision Detection, 5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = ab @ ap, ac @ ap
    if d1 <= 0.0 and d2 <= 0.0:
        return a, 0
    bp = p - b
    d3, d4 = ab @ bp, ac @ bp
    if d3 >= 0.0 and d4 <= d3:
        return b, 1
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        return a + (d1 / (d1 - d3)) * ab, 3
    cp = p - c
    d5, d6 = ab @ cp, ac @ cp
    if d6 >= 0.0 and d5 <= d6:
        return c, 2
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        return a + (d2 / (d2 - d6)) * ac, 5
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), 4
    denom = 1.0 / (va + vb + vc)
    return a + ab * (vb * denom) + ac * (vc * denom), 6


_POINT = coal.Sphere(0.0)
_IDENTITY = coal.Transform3s()


def contains(solid: SolidData, bvh, points: np.ndarray) -> bool:
    """True when any of `points` (K, 3) (mesh frame, scaled) lies inside the solid or within
    ON_SURFACE of its surface; `bvh` is the coal geometry of the same mesh."""
    inside = np.all((points >= solid.lower) & (points <= solid.upper), axis=1)
    if not inside.any():
        return False
    req, res = coal.DistanceRequest(), coal.DistanceResult()
    V, F = solid.vertices, solid.faces
    for x in points[inside]:
        res.clear()
        d = coal.distance(bvh, _IDENTITY, _POINT, coal.Transform3s(np.eye(3), x), req, res)
        if d <= ON_SURFACE:
            return True
        t = int(res.b1)
        i, j, k = F[t]
        closest, feature = _closest_feature(x, V[i], V[j], V[k])
        if feature < 3:
            normal = solid.vertex_normals[F[t, feature]]
        elif feature < 6:
            normal = solid.edge_normals[solid.face_edges[t, feature - 3]]
        else:
            normal = solid.face_normals[t]
        if (x - closest) @ normal < 0.0:
            return True
    return False


_PROBES: dict[int, tuple[object, np.ndarray]] = {}


def mesh_arrays(geometry) -> tuple[np.ndarray, np.ndarray]:
    """The vertices (P, 3) [m] and triangles (T, 3) (vertex indices) of a coal mesh (a BVH model)."""
    V = np.asarray(geometry.vertices(), dtype=float).reshape(-1, 3)
    F = np.array([[t[0], t[1], t[2]] for t in (geometry.tri_indices(i) for i in range(geometry.num_tris))],
                 dtype=np.int64).reshape(-1, 3)
    return V, F


def probe_points(geometry) -> np.ndarray:
    """(K, 3) points of a part's coal geometry (its frame), one in each connected piece: a
    vertex of each connected set of triangles of a mesh, the centre of a primitive, a point
    of a convex. Cached per geometry."""
    hit = _PROBES.get(id(geometry))
    if hit is not None and hit[0] is geometry:
        return hit[1]
    if hasattr(geometry, "num_tris") and hasattr(geometry, "tri_indices"):
        V, F = mesh_arrays(geometry)
        parent = np.arange(len(V))

        def root(v: int) -> int:
            while parent[v] != v:
                parent[v] = parent[parent[v]]
                v = parent[v]
            return v

        for tri in F:
            r0 = root(tri[0])
            for v in tri[1:]:
                r = root(v)
                if r != r0:
                    parent[r] = r0
        used = np.unique(F)
        roots = {}
        for v in used.tolist():
            roots.setdefault(root(v), v)
        pts = V[sorted(roots.values())]
    elif hasattr(geometry, "points") and hasattr(geometry, "num_points"):
        pts = np.asarray(geometry.points(), dtype=float).reshape(-1, 3)[:1]
    else:
        pts = np.zeros((1, 3))   # primitives are centred on their frame
    if len(_PROBES) > 4096:
        _PROBES.clear()
    _PROBES[id(geometry)] = (geometry, pts)
    return pts


def part_inside(geometry, R: np.ndarray, p: np.ndarray, mesh, bvh) -> bool:
    """True when the part `geometry` placed at (R (3, 3), p (3,)) in the base frame has a probe
    point inside the solid `mesh` (a `Mesh` with solid=True) whose coal geometry is `bvh`."""
    X = probe_points(geometry) @ R.T + p
    if hasattr(mesh, "contains_points"):   # a solid with its own inside test (`OccupancyMap`)
        return mesh.contains_points(X)
    local = (X - mesh.pose.position) @ mesh.pose.rotation
    return contains(mesh.solid_data, bvh, local)


def closed_part_mesh(geometry, name: str) -> SolidData | None:
    """The `SolidData` of a robot part's coal mesh when it bounds a volume, else None (a
    primitive, which coal already treats as a solid, or an open mesh). Cached per geometry."""
    hit = _CLOSED.get(id(geometry))
    if hit is not None and hit[0] is geometry:
        return hit[1]
    if len(_CLOSED) > 4096:
        _CLOSED.clear()
    _CLOSED[id(geometry)] = (geometry, _closed_part_mesh(geometry, name))
    return _CLOSED[id(geometry)][1]


_CLOSED: dict[int, tuple[object, SolidData | None]] = {}


def _closed_part_mesh(geometry, name: str) -> SolidData | None:
    if not (hasattr(geometry, "num_tris") and hasattr(geometry, "tri_indices")):
        return None
    try:
        return solid_data(*weld(*mesh_arrays(geometry)), name)
    except InvalidInputError:
        return None


def part_volume(geometry, solid: SolidData | None) -> float:
    """The volume [m^3] of a robot part: its closed mesh's, a primitive's, or inf (an open mesh:
    nothing is tested inside it, and it is never tested inside another)."""
    if solid is not None:
        return solid.volume
    if hasattr(geometry, "num_tris") or not hasattr(geometry, "computeVolume"):
        return math.inf
    return float(geometry.computeVolume())


@dataclass(frozen=True, eq=False)
class InsideTable:
    """The robot's parts for the vectorised screen of `part_in_part` (`parts_inside_parts`).

    Attributes:
        lower, upper: (G, 3) the bounding box of each part's mesh, its frame [m] (nan: a
            primitive, which coal treats as a solid already).
        centre: (G, 3) the centre of its probe points, its frame [m]; radius: (G,) their
            largest distance from it [m].
    """

    lower: np.ndarray
    upper: np.ndarray
    centre: np.ndarray
    radius: np.ndarray


_TABLES: dict[int, tuple[object, InsideTable]] = {}


def inside_table(parts) -> InsideTable:
    """The `InsideTable` of a list of robot parts (`.geometry`), cached per list."""
    hit = _TABLES.get(id(parts))
    if hit is not None and hit[0] is parts:
        return hit[1]
    lower, upper = np.full((len(parts), 3), np.nan), np.full((len(parts), 3), np.nan)
    for k, part in enumerate(parts):
        if hasattr(part.geometry, "num_tris"):
            V = np.asarray(part.geometry.vertices(), dtype=float).reshape(-1, 3)
            lower[k], upper[k] = V.min(axis=0), V.max(axis=0)
    probes = [probe_points(g.geometry) for g in parts]
    centre = np.array([P.mean(axis=0) for P in probes])
    tab = InsideTable(lower, upper, centre, np.array([np.linalg.norm(P - c, axis=1).max() for P, c in zip(probes, centre)]))
    if len(_TABLES) > 64:
        _TABLES.clear()
    _TABLES[id(parts)] = (parts, tab)
    return tab


def part_in_part(geometry_a, Ra: np.ndarray, pa: np.ndarray, solid_b: SolidData | None, geometry_b,
                 Rb: np.ndarray, pb: np.ndarray) -> bool:
    """True when part a (coal geometry placed at (Ra, pa), base frame) has a probe point inside
    the closed mesh `solid_b` of part b placed at (Rb, pb). For two parts whose surfaces do not
    touch: coal's mesh tests see surfaces only, so a part wholly inside a link's mesh (a finger
    inside panda_link5) would pass as free."""
    if solid_b is None:
        return False
    X = probe_points(geometry_a) @ Ra.T + pa
    return contains(solid_b, geometry_b, (X - pb) @ Rb)


def part_inside_a_solid(parts, obstacles, geometries, R: np.ndarray, p: np.ndarray) -> tuple[str, str] | None:
    """The (part, obstacle) names of a moving part inside a solid mesh at one configuration, or None.

    Args:
        parts: the robot's parts (`collision.tables.Part`: geometry, joint, placement R/p in its joint frame).
        obstacles, geometries: the world's obstacles and their coal geometries.
        R, p: (J+1, 3, 3), (J+1, 3) the joint frames of the configuration (base frame).

    The continuous certificate proves that no part comes within the padding of any obstacle's
    surface along a path, so each part stays on the side of each solid it starts on: the
    path's first configuration decides for the whole path. Parts fixed to the base are left to
    the checker's static pairs.
    """
    solids = [o for o, ob in enumerate(obstacles) if getattr(ob, "solid", False)]
    if not solids:
        return None
    for part in parts:
        if part.joint == 0:
            continue
        Rj = R[part.joint]
        Rg, pg = Rj @ part.R, p[part.joint] + Rj @ part.p
        for o in solids:
            if part_inside(part.geometry, Rg, pg, obstacles[o], geometries[o]):
                return part.name, obstacles[o].name
    return None


def containable_pairs(parts, pairs: np.ndarray) -> np.ndarray:
    """(K, 2) ordered pairs (a, b) of the robot's checked self pairs `pairs` (P, 2) where part a
    could lie wholly inside part b: b's mesh is closed and a's volume is smaller (as
    `part_in_part` tests them). Cached per parts list and pairs."""
    key = (id(parts), np.asarray(pairs).tobytes())
    hit = _CONTAINABLE.get(key)
    if hit is not None and hit[0] is parts:
        return hit[1]
    solid = [closed_part_mesh(part.geometry, part.name) for part in parts]
    volume = [part_volume(part.geometry, s) for part, s in zip(parts, solid)]
    out = []
    for a, b in np.asarray(pairs, dtype=np.int64).reshape(-1, 2).tolist():
        if solid[b] is not None and volume[a] < volume[b]:
            out.append((a, b))
        if solid[a] is not None and volume[b] < volume[a]:
            out.append((b, a))
    table = np.array(out, dtype=np.int64).reshape(-1, 2)
    if len(_CONTAINABLE) > 64:
        _CONTAINABLE.clear()
    _CONTAINABLE[key] = (parts, table)
    return table


_CONTAINABLE: dict[tuple, tuple[object, np.ndarray]] = {}


def parts_inside_parts(parts, pairs: np.ndarray, R: np.ndarray, p: np.ndarray, part_joint: np.ndarray,
                       gR: np.ndarray, gp: np.ndarray, hits: list | None = None) -> np.ndarray:
    """(N,) bool: the configurations, given by their joint frames R (N, J+1, 3, 3), p (N, J+1, 3)
    (base frame), where a part a has a probe point inside part b's closed mesh, for the ordered
    pairs (a, b) (K, 2) of `containable_pairs`. part_joint (G,), gR (G, 3, 3), gp (G, 3): each
    part's joint and geometry frame in it. Screened by b's convex hull first (which holds b).
    `hits`: when given, every pair found is appended to it as (1, a, b) (all pairs, not the first)."""
    tab = inside_table(parts)
    out = np.zeros(R.shape[0], dtype=bool)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if not pairs.size or not R.shape[0]:
        return out
    a, b = pairs[:, 0], pairs[:, 1]
    ja, jb = part_joint[a], part_joint[b]
    centre = np.einsum("kij,kj->ki", gR[a], tab.centre[a]) + gp[a]   # (K, 3) a's probe centre, its joint frame
    hulls = _hull_table(parts, b)
    n_near, k_near = _centres_in_hulls(R, p, ja, jb, centre, gR[b], gp[b], tab.lower[b], tab.upper[b], hulls,
                                       tab.radius[a])
    for n, k in zip(n_near.tolist(), k_near.tolist()):
        if out[n] and hits is None:
            continue
        A, B = parts[a[k]], parts[b[k]]
        Ra, Rb = R[n, ja[k]] @ gR[a[k]], R[n, jb[k]] @ gR[b[k]]
        if part_in_part(A.geometry, Ra, R[n, ja[k]] @ gp[a[k]] + p[n, ja[k]], closed_part_mesh(B.geometry, B.name),
                        B.geometry, Rb, R[n, jb[k]] @ gp[b[k]] + p[n, jb[k]]):
            out[n] = True
            if hits is not None:
                hits.append((1, int(a[k]), int(b[k])))
    return out


def obstacles_inside_parts(parts, part_joint: np.ndarray, gR: np.ndarray, gp: np.ndarray, tables, R: np.ndarray,
                           p: np.ndarray, allowed: np.ndarray | None = None, hits: list | None = None) -> np.ndarray:
    """(N,) bool: the configurations (joint frames R (N, J+1, 3, 3), p (N, J+1, 3)) where an
    obstacle of `tables` (`collision.tables.ObstacleTables`) has a probe point inside a part's
    closed mesh (a pebble wholly inside panda_link5: coal sees the link's triangles only).
    part_joint, gR, gp: as `parts_inside_parts`; allowed: (G, O) bool, pairs not checked; `hits`:
    when given, every (part g, obstacle o) found is appended to it as (0, g, o)."""
    out = np.zeros(R.shape[0], dtype=bool)
    closed = [g for g, part in enumerate(parts) if closed_part_mesh(part.geometry, part.name) is not None]
    O = len(tables.obstacles)
    if not closed or not O or not R.shape[0]:
        return out
    tab = inside_table(parts)
    b = np.repeat(np.array(closed, dtype=np.int64), O)
    o = np.tile(np.arange(O), len(closed))
    radius = np.linalg.norm(tables.h, axis=1)[o] + tables.rho[o]   # the obstacles' bounding balls, base frame
    n_near, k_near = _centres_in_hulls(R, p, np.zeros(b.size, dtype=np.int64), part_joint[b], tables.c[o], gR[b],
                                       gp[b], tab.lower[b], tab.upper[b], _hull_table(parts, b), radius)
    for n, k in zip(n_near.tolist(), k_near.tolist()):
        g, ob = int(b[k]), int(o[k])
        if (out[n] and hits is None) or (allowed is not None and allowed[g, ob]):
            continue
        tf = tables.transforms[ob]
        X = probe_points(tables.geometries[ob]) @ np.asarray(tf.getRotation()).T + np.asarray(tf.getTranslation())
        Rb = R[n, part_joint[g]] @ gR[g]
        pb = R[n, part_joint[g]] @ gp[g] + p[n, part_joint[g]]
        if contains(closed_part_mesh(parts[g].geometry, parts[g].name), parts[g].geometry, (X - pb) @ Rb):
            out[n] = True
            if hits is not None:
                hits.append((0, g, ob))
    return out


def _hull_table(parts, b: np.ndarray) -> np.ndarray:
    """(K, F, 4) the facets (n, d) of the convex hulls of parts b (K,) (n . x + d <= 0 inside,
    each part's frame), padded with facets no point is outside of. Cached per part."""
    E = []
    for g in b.tolist():
        geometry = parts[g].geometry
        hit = _HULLS.get(id(geometry))
        if hit is None or hit[0] is not geometry:
            from scipy.spatial import ConvexHull

            V = np.asarray(geometry.vertices(), dtype=float).reshape(-1, 3)
            if len(_HULLS) > 4096:
                _HULLS.clear()
            hit = _HULLS[id(geometry)] = (geometry, ConvexHull(V).equations)
        E.append(hit[1])
    table = np.zeros((len(E), max((e.shape[0] for e in E), default=0), 4))
    table[:, :, 3] = -np.inf
    for k, e in enumerate(E):
        table[k, :e.shape[0]] = e
    return table


_HULLS: dict[int, tuple[object, np.ndarray]] = {}


@kernel
def _centres_in_hulls(R, p, ja, jb, centre, gRb, gpb, lower, upper, hulls, radius):
    """For configurations n (joint frames R (N, J+1, 3, 3), p (N, J+1, 3)) and pairs k (K,):
    where the point `centre[k]` (joint ja[k]'s frame) lies within radius[k] of the box
    [lower[k], upper[k]] and of the convex hull `hulls[k]` (F, 4) given in the frame (gRb[k],
    gpb[k]) of joint jb[k]. Returns (M,) rows n and (M,) pairs k."""
    N, K = R.shape[0], ja.shape[0]
    rows = np.empty(N * K, dtype=np.int64)
    ks = np.empty(N * K, dtype=np.int64)
    m = 0
    x = np.empty(3)
    u = np.empty(3)
    y = np.empty(3)
    for n in range(N):
        for k in range(K):
            for i in range(3):   # the point, base frame, from joint jb's origin
                x[i] = p[n, ja[k], i] - p[n, jb[k], i]
                for j in range(3):
                    x[i] += R[n, ja[k], i, j] * centre[k, j]
            for j in range(3):   # in joint jb's frame, from the part's origin
                u[j] = -gpb[k, j]
                for i in range(3):
                    u[j] += R[n, jb[k], i, j] * x[i]
            near = True
            for i in range(3):   # in the part's frame
                y[i] = gRb[k, 0, i] * u[0] + gRb[k, 1, i] * u[1] + gRb[k, 2, i] * u[2]
                if not (lower[k, i] - radius[k] <= y[i] <= upper[k, i] + radius[k]):
                    near = False
            if not near:
                continue
            for f in range(hulls.shape[1]):
                if hulls[k, f, 0] * y[0] + hulls[k, f, 1] * y[1] + hulls[k, f, 2] * y[2] + hulls[k, f, 3] > radius[k]:
                    near = False
                    break
            if near:
                rows[m], ks[m] = n, k
                m += 1
    return rows[:m], ks[:m]
