"""The solid of an occupancy map's cell that holds measured points: their convex hull.

A cell of `manip.collision.occupancy.OccupancyMap` that keeps the points measured in it is
the convex hull of those points (clamped to the cell) and of their copies on each face its
box is extended to (a face shared with an occupied cell) of the points within `BAND` cells
of that face, so that a surface going on into the next cell meets that cell's hull there,
as the boxes meet. The hull lies in the cell's box and holds every point it is given
(`manip.perception` gives a run of pixels' points less those within 0.5 um of the segment
between the run's ends): a slanted face or an edge seen in a cell is as thin as it was
measured, where the box would stick out by up to a cell. Hulls are built on first use
(`MapGeometry`), about 0.2-0.4 ms each, and remembered by their cell's points and box (a map
updated where little changed builds the hulls of its new cells only).
"""

from __future__ import annotations

import threading

import coal
import numpy as np
from scipy.spatial import ConvexHull

#: A box reaching farther than this beyond its cell's points along an axis was extended to
#: that face [m] (twice the boxes' rounding, `occupancy_boxes.QUANTUM`).
SWEEP = 2e-4
#: Points within this fraction of a cell of a face the box is extended to are copied onto it.
BAND = 0.5
#: The hull reaches this far [m] beyond one of its points along each axis (so it spans a
#: volume; about ten times a depth image's float32 round-off).
GROW = 1e-6


def hull_points(points: np.ndarray, box: np.ndarray, res: float) -> np.ndarray:
    """The points (K, 3) [m] whose convex hull is the cell's solid: `points` (N >= 1, 3)
    clamped to `box` (6,) (lo, hi) (the cell's box, within the cell) and, for each face of the
    box more than `SWEEP` beyond them, copies on it of those within `BAND` cells (of edge
    `res` [m]) of it."""
    X = np.clip(np.asarray(points, dtype=np.float64), box[:3], box[3:])
    lo, hi = X.min(axis=0), X.max(axis=0)
    band = BAND * res
    for a in range(3):
        for face, gap in ((box[a], lo[a] - box[a]), (box[3 + a], box[3 + a] - hi[a])):
            if gap > SWEEP:
                Y = X[np.abs(X[:, a] - face) <= band]
                Y[:, a] = face
                X = np.vstack([X, Y])
    return X


def _hull(points: np.ndarray, box: np.ndarray, res: float) -> list:
    """[V (K, 3) [m] the hull's vertices, F (T, 3) its outward triangles (indices into V),
    planes (P, 4) (n, d): n . x + d <= 0 inside, the coal convex or None until asked for] of
    `hull_points(points, box, res)` and three points `GROW` [m] from the first along the axes,
    into the box (so that they always span a volume: coal's hull of flat input crashes; qhull
    through scipy raises a QhullError instead). Remembered for the last `HULL_CACHE` cells by
    their points and box: an updated map builds the hulls of its new cells only."""
    key = (np.ascontiguousarray(points, dtype=np.float64).tobytes(), np.asarray(box, dtype=np.float64).tobytes(), res)
    got = _HULLS.get(key)
    if got is None:
        X = hull_points(points, box, res)
        inward = np.where(X[0] + GROW <= box[3:], 1.0, -1.0)   # a hull cell's box is thicker than GROW
        X = np.vstack([X, X[0] + GROW * np.diag(inward)])
        hull = ConvexHull(X)
        index = np.full(X.shape[0], -1, dtype=np.int64)
        index[hull.vertices] = np.arange(hull.vertices.size)
        V, F = X[hull.vertices], index[hull.simplices]
        normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        inward = np.einsum("ij,ij->i", normal, hull.equations[:, :3]) < 0
        F[inward] = F[inward][:, ::-1]
        planes = np.ascontiguousarray(hull.equations)
        for a in (V, F, planes):   # shared by every map with this cell
            a.setflags(write=False)
        got = [V, F, planes, None]
        with _HULLS_LOCK:   # maps of several threads
            _HULLS[key] = got
            while len(_HULLS) > HULL_CACHE:
                del _HULLS[next(iter(_HULLS))]   # the oldest (dicts keep insertion order)
    return got


def cell_hull(points: np.ndarray, box: np.ndarray, res: float) -> tuple[coal.ConvexBase, np.ndarray]:
    """(the coal convex, its planes (F, 4) (n, d): n . x + d <= 0 inside) of the hull of
    `hull_points(points, box, res)` (and of `_hull`'s three points that keep it a volume).
    The convex is made from qhull's triangles (one hull computation; coal's own hull of the
    same vertices gives the same collisions, and distances within GJK's 1e-6 m tolerance, as
    the tests check)."""
    got = _hull(points, box, res)
    if got[3] is None:
        V, F = got[0], got[1]
        pts, tris = coal.StdVec_Vec3s(), coal.StdVec_Triangle()
        for x in V:
            pts.append(x)
        for a, b, c in F.tolist():
            tris.append(coal.Triangle(a, b, c))
        got[3] = coal.Convex(pts, tris)
    return got[3], got[2]


def hull_triangles(points: np.ndarray, box: np.ndarray, res: float) -> tuple[np.ndarray, np.ndarray]:
    """(V (K, 3) [m], F (T, 3)): the vertices and outward triangles of `cell_hull`'s hull."""
    got = _hull(points, box, res)
    return got[0], got[1]


def box_triangles(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(V (8 M, 3), F (12 M, 3)): the corners [m] and outward (counter-clockwise) triangles of
    the boxes (M, 6) (lo, hi)."""
    b = np.asarray(boxes, dtype=np.float64).reshape(-1, 6)
    V = (b[:, None, :3] + _CORNERS[None] * (b[:, None, 3:] - b[:, None, :3])).reshape(-1, 3)
    F = (_BOX_FACES[None] + 8 * np.arange(b.shape[0])[:, None, None]).reshape(-1, 3)
    return V, F


def solids_mesh(boxes: np.ndarray, solid: np.ndarray, hulls, res: float) -> tuple[np.ndarray, np.ndarray]:
    """(V (K, 3) [m], F (T, 3)): triangles of a map's solids as the checks see them (see
    `occupancy.MapGeometry`): box m where `solid[m]`, else the hull of cell `box_cell[m]`'s
    points (`hull_triangles`), hulls = (start, points, box_cell), each face outward."""
    V, F = box_triangles(boxes[solid])
    Vs, Fs, n = [V], [F], V.shape[0]
    for m in np.flatnonzero(~solid):
        start, P, box_cell = hulls
        c = box_cell[m]
        X, T = hull_triangles(P[start[c]:start[c + 1]], boxes[m], res)
        Vs.append(X)
        Fs.append(T + n)
        n += X.shape[0]
    return np.vstack(Vs), np.vstack(Fs)


#: Cells whose hulls `_hull` remembers (a few kB each).
HULL_CACHE = 8192
_HULLS: dict = {}
_HULLS_LOCK = threading.Lock()


# the 12 triangles of a unit box (corners numbered x * 4 + y * 2 + z), counter-clockwise outside
_BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.int64)
_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.int64)


__all__ = ["box_triangles", "cell_hull", "hull_points", "hull_triangles", "solids_mesh", "HULL_CACHE", "BAND", "GROW", "SWEEP"]
