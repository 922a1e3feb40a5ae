"""The verifier's test for a part wholly inside another part's closed mesh.

coal's mesh tests see triangles only: a link (or an obstacle) wholly inside a closed mesh
(another link's, or a mesh obstacle's) touches no triangle and passes as free. This test,
written for the independent verifier (`verify.py`; it shares no code with manip's
checker), takes one point of each part (a mesh's first vertex, a primitive's centre) and
counts the crossings of rays from it with the other part's triangles: odd on all three
rays = inside. A part that touches no triangle of a closed mesh is wholly inside it or
wholly outside it, so one point decides. Open meshes (an edge not shared by exactly two
triangles, e.g. the Kinova's) and meshes given as `surfaces` (the world's meshes not declared
solid) hold nothing: only contacts with their triangles count, which coal sees
(`surface_meshes`; `inline_mesh` builds a world mesh given by vertices and faces).
"""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin

from manip.errors import InvalidInputError

#: Ray directions of the parity test (irrational-ish, so rays rarely graze edges).
_RAYS = np.array([[0.5773, 0.5774, 0.5775], [-0.3141, 0.8660, 0.3891], [0.2718, -0.2236, 0.9360]])
_RAYS /= np.linalg.norm(_RAYS, axis=1, keepdims=True)


def _mesh(shape) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3), triangles (T, 3)) of a coal BVH mesh, or None for other shapes."""
    if not isinstance(shape, coal.BVHModelBase) or shape.num_tris == 0:
        return None
    V = np.asarray(shape.vertices(), dtype=float).reshape(-1, 3)
    F = np.array([[t[0], t[1], t[2]] for t in (shape.tri_indices(i) for i in range(shape.num_tris))],
                 dtype=np.int64).reshape(-1, 3)
    return V, F


def _closed(V: np.ndarray, F: np.ndarray) -> bool:
    """Every edge (vertices merged by position) shared by exactly two triangles."""
    _, ids = np.unique(np.round(V, 9), axis=0, return_inverse=True)
    G = ids.reshape(-1)[F]
    e = np.sort(np.concatenate([G[:, [0, 1]], G[:, [1, 2]], G[:, [2, 0]]]), axis=1)
    e = e[e[:, 0] != e[:, 1]]
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(len(counts)) and bool(np.all(counts == 2))


def _inside(p: np.ndarray, A: np.ndarray, E1: np.ndarray, E2: np.ndarray) -> bool:
    """Point p (3,) inside the closed triangle soup (A, A + E1, A + E2) (T, 3): odd crossings on every ray."""
    for d in _RAYS:
        h = np.cross(d, E2)
        det = np.einsum("ij,ij->i", E1, h)
        ok = np.abs(det) > 1e-15
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = p - A
        u = np.einsum("ij,ij->i", s, h) * inv
        qv = np.cross(s, E1)
        v = (qv @ d) * inv
        t = np.einsum("ij,ij->i", E2, qv) * inv
        hits = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        if int(hits.sum()) % 2 == 0:
            return False
    return True


class InsideTest:
    """Parts wholly inside a closed mesh, for the pairs of one pinocchio GeometryModel.

    Args:
        gm: the geometry model (robot parts and obstacles).
        pairs: (i, j) geometry index pairs to test (both ways: i inside j and j inside i).
        surfaces: geometry indices of meshes that are surfaces even when closed (the world's
            meshes not declared solid): nothing is inside them; they may still lie inside a part.
    """

    def __init__(self, gm: pin.GeometryModel, pairs, surfaces=()):
        self.names = [g.name for g in gm.geometryObjects]
        self._tri: dict[int, tuple] = {}
        rep = []
        for k, g in enumerate(gm.geometryObjects):
            m = _mesh(g.geometry)
            rep.append(m[0][0] if m is not None else np.zeros(3))  # a mesh's vertex, a primitive's centre
            if m is not None and k not in surfaces and _closed(*m):
                V, F = m
                A = V[F[:, 0]]
                self._tri[k] = (A, V[F[:, 1]] - A, V[F[:, 2]] - A, V.min(axis=0), V.max(axis=0))
        self._rep = np.array(rep).reshape(-1, 3)
        directed = [(a, b) for i, j in pairs for a, b in ((i, j), (j, i)) if b in self._tri]
        self.pairs = np.array(directed, dtype=np.int64).reshape(-1, 2)
        self._lo = np.array([self._tri[int(b)][3] for b in self.pairs[:, 1]]).reshape(-1, 3)
        self._hi = np.array([self._tri[int(b)][4] for b in self.pairs[:, 1]]).reshape(-1, 3)
        self._n = gm.ngeoms

    def first(self, gd: pin.GeometryData) -> tuple[str, str] | None:
        """(part, the part whose closed mesh wholly contains it) at gd's placements, or None."""
        if not len(self.pairs):
            return None
        M = gd.oMg
        R = np.array([M[k].rotation for k in range(self._n)])
        t = np.array([M[k].translation for k in range(self._n)])
        a, b = self.pairs[:, 0], self.pairs[:, 1]
        p = np.einsum("nij,nj->ni", R[a], self._rep[a]) + t[a]
        local = np.einsum("nji,nj->ni", R[b], p - t[b])  # in b's frame
        boxed = np.flatnonzero(np.all((local > self._lo) & (local < self._hi), axis=1))
        for n in boxed.tolist():
            A, E1, E2, _, _ = self._tri[int(b[n])]
            if _inside(local[n], A, E1, E2):
                return self.names[int(a[n])], self.names[int(b[n])]
        return None


def inline_mesh(vertices, faces, scale: np.ndarray, what: str) -> coal.BVHModelOBBRSS:
    """A coal mesh of (V, 3) vertices [m] (times `scale` (3,)) and (F, 3) vertex indices."""
    V = np.asarray(vertices, dtype=float).reshape(-1, 3) * scale
    F = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(F) == 0 or F.min() < 0 or F.max() >= len(V):
        raise InvalidInputError(f"{what}: faces must index its {len(V)} vertices; got {len(F)} faces")
    bvh = coal.BVHModelOBBRSS()
    bvh.beginModel(len(F), len(V))
    bvh.addVertices(V)
    bvh.addTriangles(F)
    bvh.endModel()
    return bvh


def surface_meshes(world: dict) -> set[str]:
    """Names of the world's meshes that are surfaces (not `"solid": true`): only contacts with
    their triangles count; nothing is inside them (manip's convention, README "Worlds")."""
    if hasattr(world, "to_dict") and not isinstance(world, dict):
        world = world.to_dict()
    return {name for name, o in ((world or {}).get("mesh") or {}).items() if not (o or {}).get("solid", False)}
