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
