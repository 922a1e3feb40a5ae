"""The convex shapes of parts and obstacles that `collision.gjk` tests, and the planes of a
mesh's convex hull.

One place for what two users of `gjk` had each written (`collision.hull_screen`, the exact
checker's screen of its narrowphase candidates, and `planning.path.compiled_narrowphase`, the
coarse search's own narrowphase), and for the hull planes of a mesh that `collision.inside`,
`collision.occupancy_exact` and `compiled_narrowphase` compute:

- `part_row` / `part_tables`: a part (`collision.tables.Part`) as a `gjk` shape: a box, sphere,
  capsule or cylinder as itself, a triangle mesh as the vertices of its convex hull (which
  holds it), anything else `gjk.NO` (its pairs are left to coal);
- `obstacle_kinds`: the `gjk` kind of each obstacle (boxes, spheres, capsules, cylinders);
- `vertices` / `hull_planes`: a mesh's (or a convex's) vertices, and the facet planes and area
  of their convex hull, cached per geometry.
"""

from __future__ import annotations

import numpy as np

from manip.collision import gjk
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Sphere

__all__ = ["hull_planes", "obstacle_kinds", "part_row", "part_tables", "vertices"]

_PLANES: dict[int, tuple[object, tuple[np.ndarray, float] | None]] = {}   # id(geometry) -> (geometry, planes)


def part_row(part) -> tuple[int, np.ndarray, float, np.ndarray]:
    """(kind, h (3,), rho [m], vertices (K, 3) [m]) of one part (`collision.tables.Part`) for
    `gjk`, in its geometry frame.

    A triangle mesh is the `VERTICES` of its convex hull (`part.hull`, a coal.Convex of the
    mesh's vertices: it holds the mesh). `gjk.NO` (coal decides the part's pairs) for a mesh
    without a hull of its own or with a flat one (fewer than 4 points), and for any other
    geometry (a coal.Convex, an ellipsoid, ...): a hull given beside a geometry that is not a
    mesh is not known to hold it, nor to be it."""
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
        return gjk.NO, np.zeros(3), 0.0, z
    P = np.asarray(hull.points(), dtype=float).reshape(-1, 3)
    if P.shape[0] < 4:
        return gjk.NO, np.zeros(3), 0.0, z
    return gjk.VERTICES, np.zeros(3), 0.0, np.ascontiguousarray(P)


def part_tables(parts) -> tuple:
    """The parts' rows (`part_row`) as arrays: kind (G,), h (G, 3), rho (G,), vertex rows start
    (G,), count (G,) of V (N, 3) (each part in its own geometry frame)."""
    rows = [part_row(p) for p in parts]
    G = len(rows)
    count = np.array([len(r[3]) for r in rows], dtype=np.int64)
    return (np.array([r[0] for r in rows], dtype=np.int64),
            np.ascontiguousarray(np.array([r[1] for r in rows], dtype=float).reshape(G, 3)),
            np.array([r[2] for r in rows], dtype=float),
            np.cumsum(count) - count, count,
            np.ascontiguousarray(np.concatenate([r[3] for r in rows] + [np.zeros((0, 3))]).reshape(-1, 3)))


def obstacle_kinds(obstacles) -> np.ndarray:
    """(O,) the `gjk` kind of each obstacle (`gjk.NO` for meshes, occupancy maps, other shapes);
    its placement and size are the broadphase's obstacle tables (`tables.ObstacleTables.broadphase`)."""
    out = np.full(len(obstacles), gjk.NO, dtype=np.int64)
    for o, ob in enumerate(obstacles):
        if type(ob) in (Cuboid, Sphere, Capsule):
            out[o] = gjk.ROUNDED_BOX
        elif type(ob) is Cylinder:
            out[o] = gjk.CYLINDER
    return out


def vertices(geometry) -> np.ndarray | None:
    """(P, 3) the vertices [m] of a coal mesh or the points of a coal.Convex (its frame), else None."""
    if hasattr(geometry, "num_tris") and hasattr(geometry, "vertices"):   # a BVH mesh
        return np.asarray(geometry.vertices(), dtype=float).reshape(-1, 3)
    if hasattr(geometry, "points") and hasattr(geometry, "num_points"):   # coal.Convex
        return np.asarray(geometry.points(), dtype=float).reshape(-1, 3)
    return None


def hull_planes(geometry) -> tuple[np.ndarray, float] | None:
    """The convex hull of a coal mesh's vertices (or a coal.Convex's points), its frame:
    (equations (F, 4): (n, d) with n . x + d <= 0 inside, |n| = 1; area [m^2]); None for
    another geometry or fewer than 4 vertices; ((0, 4), nan) for flat vertices (qhull fails).
    Cached per geometry (qhull runs once per mesh)."""
    got = _PLANES.get(id(geometry))
    if got is not None and got[0] is geometry:
        return got[1]
    V = vertices(geometry)
    planes = None
    if V is not None and V.shape[0] >= 4:
        from scipy.spatial import ConvexHull, QhullError
        try:
            hull = ConvexHull(V)
            planes = (hull.equations, float(hull.area))
        except (QhullError, ValueError):
            planes = (np.zeros((0, 4)), float("nan"))
    if len(_PLANES) > 4096:
        _PLANES.clear()
    _PLANES[id(geometry)] = (geometry, planes)
    return planes
