"""The solid of an occupancy map's cell that holds measured points: their convex hull.

A cell of `manip.collision.occupancy.OccupancyMap` that keeps the points measured in it is
the convex hull of those points (clamped to the cell) and of their copies on each face its
box is extended to (a face shared with an occupied cell) of the points within `BAND` cells
of that face, so that a surface going on into the next cell meets that cell's hull there,
as the boxes meet. The hull lies in the cell's box and holds every point it is given
(`manip.perception` gives a run of pixels' points less those within 0.5 um of the segment
between the run's ends): a slanted face or an edge seen in a cell is as thin as it was
measured, where the box would stick out by up to a cell. Hulls are built on first use
(`MapGeometry`), about 0.2 ms each.
"""

from __future__ import annotations

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


def cell_hull(points: np.ndarray, box: np.ndarray, res: float) -> tuple[coal.ConvexBase, np.ndarray]:
    """(the coal convex, its planes (F, 4) (n, d): n . x + d <= 0 inside) of the hull of
    `hull_points(points, box, res)` and of three points `GROW` [m] from the first along the
    axes, into the box (so that it always spans a volume: coal's hull of flat input crashes)."""
    X = hull_points(points, box, res)
    inward = np.where(X[0] + GROW <= box[3:], 1.0, -1.0)   # a hull cell's box is thicker than GROW
    X = np.vstack([X, X[0] + GROW * np.diag(inward)])
    hull = ConvexHull(X)   # qhull through scipy: a QhullError, never a crash
    pts = coal.StdVec_Vec3s()
    for x in X[hull.vertices]:
        pts.append(x)
    return coal.ConvexBase.convexHull(pts, False, "Qt"), np.ascontiguousarray(hull.equations)


__all__ = ["cell_hull", "hull_points", "BAND", "GROW", "SWEEP"]
