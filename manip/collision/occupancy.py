"""`OccupancyMap`: an obstacle made of the occupied cells of a voxel grid (what cameras saw).

The cells of edge `resolution` [m] lie on a lattice fixed to the robot base frame: cell
(i, j, k) is [i r, (i + 1) r] x [j r, (j + 1) r] x [k r, (k + 1) r]. Each occupied cell holds
a box within it: `bounds` (what was measured in it, e.g. the bounding box of the points
that fell in it: a surface becomes a thin slab) or, without bounds, the whole cell; the box is
extended to each face the cell shares with an occupied cell, so the boxes of a surface seen
as face-adjacent cells meet. A cell given its measured `points` is their convex hull (with
the points near a face its box is extended to copied onto it, so that hulls meet there as
the boxes do; `manip.collision.occupancy_hulls`), which its box bounds; any other cell is
its box. The map is the union of these solids, in every check of
the planner and in its continuous certificate (the broadphase and the optimiser's clearance
terms use the boxes: bounds of the hulls):

- broadphase: the robot's sphere covers against a distance bound of the boxes (the box
  holding them, blocks of `BLOCK` cells with an exact distance transform between blocks,
  then the exact distance to the boxes of the cells within reach of each ball;
  `manip.collision.occupancy_kernels`), so a configuration far from every cell costs a few
  lookups whatever the number of cells;
- exact: a part against the boxes (the cells' boxes merged into fewer disjoint ones that
  tile the same union; a map with points: each cell's own box, `MapGeometry`) in the cells
  its vertices' box spans, decided by cheap conclusive tests where they can
  (`manip.collision.occupancy_exact`) and by coal on the rest, each a `coal.Box` or a cell's
  hull made on first use, so installing a new map builds no coal geometry; a part inside a
  solid (not touching its faces) is found by the grid (`contains_points`), as for solid
  meshes (`manip.collision.solids`); the certificate keeps every part off every face, so the
  path's first configuration decides the inside question for the whole path.

A map is immutable (like every shape): `manip.perception` builds a new one for each update.
It lies in the base frame (its pose is the identity) and is never checked against the
links fixed to the base (`ObstacleTables.below_base`): the ground or table the robot stands
on, seen by a camera, does not put every configuration in collision.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import coal
import numpy as np
from scipy import ndimage

from manip.collision.occupancy_boxes import boxes_near_balls, cell_range, grid_tables, merge_boxes, near_boxes
from manip.collision.occupancy_exact import part_boxes, part_hull
from manip.collision.occupancy_hulls import BAND as HULL_BAND
from manip.collision.occupancy_hulls import GROW as HULL_GROW
from manip.collision.occupancy_hulls import SWEEP as HULL_SWEEP
from manip.collision.occupancy_hulls import box_triangles, cell_hull, solids_mesh
from manip.collision.occupancy_kernels import cells_contain, map_candidates, point_lower_bounds
from manip.collision.shapes import Mesh, _check_name, as_pose
from manip.errors import InvalidInputError
from manip.jit import kernel_array
from manip.pose import Pose
from manip.validation import positive

#: Cells per block edge of the broadphase's block distance bounds.
BLOCK = 4
#: Largest dense grid an occupancy map holds (cells).
MAX_CELLS = 64_000_000
#: A cell whose points lie within this of a plane normal to an axis is its box, not their
#: hull [m] (an axis-aligned face: its box is as thin; boxes merge, hulls do not).
FLAT = 1e-3

@dataclass(frozen=True, eq=False)
class OccupancyMap(Mesh):
    """The occupied cells of a voxel grid as one obstacle (see the module docstring).

    Build it with `OccupancyMap.from_cells` (or `manip.perception`, which integrates depth
    images into one). As a `Mesh` it shows its cells' boxes (`vertices`, `faces`) to code
    that draws or exports meshes.

    Attributes:
        resolution: the cells' edge [m].
        cells: (C, 3) int64 lattice indices of the occupied cells, sorted, read-only.
        bounds: (C, 6) [m] (lo, hi) what each cell holds (before the extension to occupied
            neighbours), read-only; None: whole cells.
        points: (N, 3) [m] the measured points of the cells, cell c's being
            points[point_start[c]:point_start[c + 1]] (as measured: the hull clamps them to the
            cell; an empty range: the cell is its box), read-only; None: every cell is its box.
        point_start: (C + 1,) int64 (with `points`), read-only.
    """

    kind: ClassVar[str] = "occupancy"

    resolution: float = 0.02
    cells: np.ndarray = dataclasses.field(default=None, repr=False)  # type: ignore[assignment]
    bounds: np.ndarray | None = dataclasses.field(default=None, repr=False)
    points: np.ndarray | None = dataclasses.field(default=None, repr=False)
    point_start: np.ndarray | None = dataclasses.field(default=None, repr=False)

    def __init__(self, *args, **kwargs):
        raise InvalidInputError("build an OccupancyMap with OccupancyMap.from_cells(name, resolution, cells) "
                                "or MotionGenerator.update_world_from_depth / update_world_from_pointcloud")

    @classmethod
    def from_cells(cls, name: str, resolution: float, cells, bounds=None, points=None,
                   _sorted: bool = False) -> OccupancyMap:
        """A map of the given occupied cells.

        Args:
            name: the obstacle's name.
            resolution: cell edge [m] > 0.
            cells: (C, 3) integer lattice indices (C may be 0: an empty map).
            bounds: (C, 6) [m] (x0, y0, z0, x1, y1, z1) per cell: the box the cell holds
                (clamped to the cell; e.g. the bounds of the points measured in it); None:
                whole cells (or, with `points`, the bounds of each cell's points). Repeated
                cells take the union of their bounds.
            points: None, or (start (C + 1,) int, points (N, 3) [m]): cell c's measured points
                are points[start[c]:start[c + 1]], in the order of `cells` (distinct cells;
                a cell's bounds grow to hold its points, and its hull is clamped to the
                cell); the cell is then their convex hull (with the points near a face its
                box is extended to copied onto it), unless they lie within `FLAT` of a plane
                normal to an axis or the range is empty: then the cell is its box.

        Raises:
            InvalidInputError: a bad name, resolution, cells, bounds or points array.
        """
        _check_name(name, "occupancy map")
        res = positive(resolution, f"occupancy map '{name}': resolution", "m")
        c = np.asarray(cells)
        if c.size == 0:
            c = np.zeros((0, 3), dtype=np.int64)
        if c.ndim != 2 or c.shape[1] != 3 or c.dtype.kind not in "iu":
            raise InvalidInputError(f"occupancy map '{name}': cells must be an integer (C, 3) array; "
                                    f"got {c.dtype.name} {c.shape}")
        b = None
        if bounds is not None:
            b = np.asarray(bounds, dtype=np.float64)
            if b.size == 0:
                b = b.reshape(0, 6)
            if b.shape != (c.shape[0], 6) or not np.all(np.isfinite(b)) or np.any(b[:, 3:] < b[:, :3]):
                raise InvalidInputError(f"occupancy map '{name}': bounds must be a finite ({c.shape[0]}, 6) array "
                                        f"[x0, y0, z0, x1, y1, z1] [m] with x0 <= x1, y0 <= y1, z0 <= z1 per cell; "
                                        f"got shape {b.shape}")
        c = c.astype(np.int64)
        start, P = (None, None) if points is None else _point_lists(name, points, c, _sorted)
        if P is not None and not _sorted:   # the bounds hold each cell's points (whole cells without bounds or points)
            some = np.diff(start) > 0
            lo, hi = np.full((c.shape[0], 3), np.inf), np.full((c.shape[0], 3), -np.inf)
            if some.any():
                lo[some] = np.minimum.reduceat(P, start[:-1][some], axis=0)
                hi[some] = np.maximum.reduceat(P, start[:-1][some], axis=0)
            if b is None:
                b = np.hstack([np.where(some[:, None], lo, c * res), np.where(some[:, None], hi, (c + 1) * res)])
            else:
                b = np.hstack([np.minimum(b[:, :3], lo), np.maximum(b[:, 3:], hi)])
            # in the order of the sorted cells
            order = np.lexsort(c.T[::-1])
            if c.shape[0] > 1 and np.any(np.all(np.diff(c[order], axis=0) == 0, axis=1)):
                raise InvalidInputError(f"occupancy map '{name}': cells must be distinct when points are given")
            counts = np.diff(start)[order]
            rows = np.repeat(start[:-1][order], counts) + (np.arange(int(counts.sum())) -
                                                            np.repeat(np.cumsum(counts) - counts, counts))
            c, b, P = c[order], b[order], P[rows]
            start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
            _sorted = True
        if not _sorted:   # _sorted: distinct, sorted
            c, inv = np.unique(c, axis=0, return_inverse=True)
            inv = inv.reshape(-1)
            if b is not None:
                u = np.full((c.shape[0], 6), np.inf)
                u[:, 3:] = -np.inf
                np.minimum.at(u[:, :3], inv, b[:, :3])
                np.maximum.at(u[:, 3:], inv, b[:, 3:])
                b = u
        c.setflags(write=False)
        if b is not None:
            b = np.ascontiguousarray(b)
            b.setflags(write=False)
        if P is not None:
            for arr in (start, P):
                arr.setflags(write=False)
        out = object.__new__(cls)
        for key, value in (("name", name), ("pose", Pose(np.zeros(3))), ("file_path", None), ("solid", True),
                           ("resolution", float(res)), ("cells", c), ("bounds", b), ("points", P),
                           ("point_start", start)):
            object.__setattr__(out, key, value)
        out._tables_of(c)
        return out

    def _tables_of(self, c: np.ndarray) -> None:
        """The grid, the cells' boxes, the broadphase bounds and the merged boxes of cells c (C, 3)."""
        res = self.resolution
        shared: dict = {}
        hulls = None
        if c.shape[0] == 0:   # an empty map: one tiny box far away stands for the geometry
            boxes = np.concatenate([np.full(3, 1e6), np.full(3, 1e6 + 1e-3)])[None]
            of_cell = np.zeros(0, dtype=np.int64)
            idx = np.full((1, 1, 1), -1, dtype=np.int32)
            cb = np.zeros((0, 6))
            origin = np.zeros(3, dtype=np.int64)
            blb = np.full((1, 1, 1), np.inf)
            blocks = np.concatenate([np.full(3, np.inf), np.full(3, -np.inf)]).reshape(1, 1, 1, 6)   # empty
            lo = hi = boxes[0, :3]
        else:
            origin, shape = cell_range(c)
            if int(np.prod(shape.astype(float))) > MAX_CELLS:
                raise InvalidInputError(f"occupancy map '{self.name}': its cells span {shape.tolist()} cells "
                                        f"(more than {MAX_CELLS:,}); use a coarser resolution")
            whole = self.bounds is None
            bounds = np.zeros((0, 6)) if whole else np.array(self.bounds, dtype=np.float64)   # writable: one signature
            # blocks of BLOCK cells: the exact box-to-box distance between a block and the nearest
            # occupied block is the distance transform of the dilated block grid (module doc)
            # blocks: the box holding each block's cells' boxes
            idx, cb, lo, hi, blocks, grown = grid_tables(c, bounds, whole, origin, shape, float(res), BLOCK)
            blb = ndimage.distance_transform_edt(~grown) * (BLOCK * res) if not grown.all() else np.zeros(grown.shape)
            hull_cells = self._hull_cells()
            if hull_cells.size == 0:
                boxes, of_cell = merge_boxes(idx, cb, origin, float(res))
            else:   # the boxes merged, each hull on its own (its cell's box bounds it)
                masked = idx.copy()
                masked[tuple((c[hull_cells] - origin).T)] = -1
                boxes, of_cell = merge_boxes(masked, cb, origin, float(res))
                of_cell[hull_cells] = boxes.shape[0] + np.arange(hull_cells.size)
                box_cell = np.concatenate([np.full(boxes.shape[0], -1), hull_cells])
                boxes = np.vstack([boxes, cb[hull_cells]])
                hulls = (self.point_start, self.points, box_cell)
        shared["geometry"] = MapGeometry(boxes, idx, of_cell, np.ascontiguousarray(origin, dtype=np.int64), float(res),
                                         hulls)
        shared["tables"] = (idx, np.ascontiguousarray(cb), float(res), np.ascontiguousarray(origin, dtype=np.int64),
                            np.ascontiguousarray(blb, dtype=np.float64), np.ascontiguousarray(blocks), BLOCK,
                            np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))
        object.__setattr__(self, "_grid", shared)
        object.__setattr__(self, "scale", np.ones(3))

    def _hull_cells(self) -> np.ndarray:
        """(H,) int64 the cells that are the hulls of their points: those with points whose
        bounds are thicker than `FLAT` along every axis (a flatter cell is its box, within FLAT
        of its hull)."""
        if self.points is None:
            return np.zeros(0, dtype=np.int64)
        thick = np.all(self.bounds[:, 3:] - self.bounds[:, :3] > FLAT, axis=1)
        return np.flatnonzero(thick & (np.diff(self.point_start) > 0))

    @property
    def vertices(self) -> np.ndarray:   # type: ignore[override]
        """(8 M, 3) corners [m] of the merged boxes (drawn, exported; built on first use)."""
        return self._mesh()[0]

    @property
    def faces(self) -> np.ndarray:   # type: ignore[override]
        """(12 M, 3) triangles of the merged boxes' faces."""
        return self._mesh()[1]

    def _mesh(self) -> tuple[np.ndarray, np.ndarray]:
        mesh = self._grid.get("mesh")
        if mesh is None:
            V, F = box_triangles(self._grid["geometry"].boxes)
            V.setflags(write=False)
            F.setflags(write=False)
            mesh = self._grid["mesh"] = (V, F)
        return mesh

    def solids_mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """(V (K, 3) [m], F (T, 3)): triangles of the solids the checks see, in the frame of
        `vertices` (the merged boxes and each hull cell's convex hull: ~0.2-0.4 ms a hull not
        built yet), for drawing; `vertices` / `faces` are the boxes alone (the hulls' bounds)."""
        g = self._grid["geometry"]
        return solids_mesh(g.boxes, g.solid, g.hulls, self.resolution)

    # ------------------------------------------------------------------ shape interface
    def _sharing_copy(self) -> OccupancyMap:
        out = object.__new__(type(self))
        out.__dict__.update(self.__dict__)
        return out

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._tables_of(self.cells)   # the dense tables are rebuilt (pickles carry the cells)

    def __getstate__(self) -> dict:
        state = {k: v for k, v in self.__dict__.items() if k != "_grid"}
        return state

    def with_pose(self, pose) -> OccupancyMap:
        """A map lies in the base frame: only the identity pose is accepted."""
        p = as_pose(pose, f"occupancy map '{self.name}'")
        if not (np.allclose(p.position, 0.0) and abs(abs(p.quaternion[0]) - 1.0) < 1e-12):
            raise InvalidInputError(f"occupancy map '{self.name}' lies in the robot base frame and cannot be moved; "
                                    "integrate the camera data again instead")
        return self

    def with_name(self, name: str) -> OccupancyMap:
        out = self._sharing_copy()
        object.__setattr__(out, "name", _check_name(name, "occupancy map"))
        return out

    @property
    def solid_data(self):
        """None: a map's inside test is its grid (`contains_points`), not a mesh's normals."""
        return None

    def decimated(self, cell: float) -> Mesh:
        raise InvalidInputError(f"occupancy map '{self.name}' is already a grid; integrate at another resolution")

    def local_aabb(self) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self._grid["tables"][7], self._grid["tables"][8]
        return (lo + hi) / 2.0, (hi - lo) / 2.0

    def to_dict(self) -> dict:
        out = {"resolution": self.resolution, "cells": self.cells.tolist()}
        if self.bounds is not None:
            out["bounds"] = self.bounds.tolist()
        if self.points is not None:
            out["point_start"] = self.point_start.tolist()
            out["points"] = self.points.tolist()
        return out

    # ------------------------------------------------------------------ queries
    @property
    def num_cells(self) -> int:
        """Number of occupied cells."""
        return int(self.cells.shape[0])

    @property
    def num_boxes(self) -> int:
        """Number of disjoint boxes the cells' boxes are merged into, and of hulls (the exact
        geometry)."""
        return 0 if self.num_cells == 0 else int(self._grid["geometry"].boxes.shape[0])

    @property
    def num_hulls(self) -> int:
        """Number of cells that are the convex hull of their points (the others are boxes)."""
        return int(self._hull_cells().size)

    @property
    def broadphase_tables(self) -> tuple:
        """(idx, cb, res, origin, blb, bocc, BLOCK, lo, hi): the tables of `occupancy_kernels`
        (bocc (nb0, nb1, nb2, 6) [m]: the box holding each block's cells' boxes)."""
        return self._grid["tables"]

    def cell_boxes(self) -> np.ndarray:
        """(C, 6) [m] (lo, hi) the box each cell of `cells` holds (base frame)."""
        return self._grid["tables"][1].copy()

    def cell_centres(self) -> np.ndarray:
        """(C, 3) centres [m] of the occupied cells (base frame)."""
        return (self.cells + 0.5) * self.resolution

    def contains_points(self, X: np.ndarray) -> bool:
        """True when any point of X (3,) or (K, 3) [m] (base frame) lies in the solid an
        occupied cell holds (its box, `cell_boxes`, or its hull; faces included).

        Raises:
            InvalidInputError: X is not finite points (3,) or (K, 3).
        """
        try:
            P = np.asarray(X, dtype=np.float64)
        except (TypeError, ValueError):
            P = None
        if P is None or P.ndim not in (1, 2) or P.shape[-1] != 3 or not np.all(np.isfinite(P)):
            raise InvalidInputError(f"occupancy map '{self.name}': contains_points takes finite points (3,) or (K, 3) "
                                    f"[m]; got {X!r:.80}")
        idx, cb, res, origin = self._grid["tables"][:4]
        P = kernel_array(P.reshape(-1, 3))
        if self.points is None or self.num_cells == 0:
            return bool(cells_contain(P, idx, cb, res, origin))
        return self._grid["geometry"].contains(P)

    def lower_bounds(self, X: np.ndarray, exact_within: float = 0.0) -> np.ndarray:
        """(M,) lower bounds [m] of the distances of points X (M, 3) to the occupied cells
        (exact below `exact_within` [m]; +inf for an empty map)."""
        X = np.ascontiguousarray(X, dtype=np.float64).reshape(-1, 3)
        if self.num_cells == 0:
            return np.full(X.shape[0], np.inf)
        return point_lower_bounds(X, *self._grid["tables"], float(exact_within))

    def coal_geometry(self) -> MapGeometry:
        """The exact geometry: the merged boxes, tested by `MapGeometry` (not one coal object)."""
        return self._grid["geometry"]


def _point_lists(name: str, points, c: np.ndarray, trusted: bool) -> tuple[np.ndarray, np.ndarray]:
    """(start (C + 1,) int64, points (N, 3) [m]) of `from_cells`' points argument for cells c
    (C, 3), validated unless `trusted` (the map's own, `manip.perception`'s)."""
    if trusted:
        return points
    try:
        start, P = points
        start = np.asarray(start)
        P = np.asarray(P, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(f"occupancy map '{name}': points must be (start (C + 1,) int, points (N, 3) [m]) "
                                f"or None; got {type(points).__name__}") from None
    if P.size == 0:
        P = P.reshape(0, 3)
    C = c.shape[0]
    if (start.shape != (C + 1,) or start.dtype.kind not in "iu" or start[0] != 0
            or np.any(np.diff(start) < 0) or start[-1] != P.shape[0]):
        raise InvalidInputError(f"occupancy map '{name}': points' start must be a non-decreasing integer ({C + 1},) "
                                f"array from 0 to the number of points; got {start.dtype.name} {start.shape}")
    if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)):
        raise InvalidInputError(f"occupancy map '{name}': points must be finite (N, 3) [m]; got shape {P.shape}")
    return start.astype(np.int64), np.array(P, dtype=np.float64, order="C")   # copies: the map's are read-only


class MapGeometry:
    """The exact geometry of a map: boxes (M, 6) [m] (lo, hi), base frame: disjoint merged
    boxes, each a solid, or (a map with points, `hulls`) one per cell, a solid or the bound of
    the cell's convex hull (`solid` (M,) bool says which). Each `coal.Box` or hull is made on
    first use. Its `collide` / `distance` stand for coal's calls against one geometry: a part
    is tested against the solids its (placed) bounding box comes near (`collide`: those
    `occupancy_exact.part_boxes` leaves undecided)."""

    def __init__(self, boxes: np.ndarray, idx: np.ndarray, of_cell: np.ndarray, origin: np.ndarray, res: float,
                 hulls: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None):
        """hulls: (start (C + 1,), points (N, 3) [m], box_cell (M,)): box m bounds the hull of
        cell box_cell[m]'s points (points[start[c]:start[c + 1]]; -1: the box is a solid)."""
        self.boxes = np.ascontiguousarray(boxes, dtype=np.float64)
        self.boxes.setflags(write=False)
        self._grid = (self.boxes, idx, np.ascontiguousarray(of_cell, dtype=np.int64), origin, float(res))
        self.hulls = hulls
        self.solid = np.ones(self.boxes.shape[0], dtype=bool) if hulls is None else hulls[2] < 0
        empty = (np.zeros(1, dtype=np.int64), np.zeros((0, 3)), np.full(self.boxes.shape[0], -1, dtype=np.int64))
        # `part_boxes`' hull arguments: start, points, box_cell, band, sweep, grow
        self._points = (*(empty if hulls is None else hulls), HULL_BAND * float(res), HULL_SWEEP, HULL_GROW)
        self.solid.setflags(write=False)
        self._coal: list = [None] * self.boxes.shape[0]
        self._hull: list = [None] * self.boxes.shape[0]
        self._local: dict = {}

    def _box(self, m: int) -> tuple:
        """(coal.Box, its transform, its planes (6, 4) (n, d): n . x + d <= 0 inside) of box m."""
        got = self._coal[m]
        if got is None:   # a flat box (a surface measured in one plane) gets a nanometre of thickness for coal
            lo, hi = self.boxes[m, :3], self.boxes[m, 3:]
            planes = np.hstack([np.vstack([-np.eye(3), np.eye(3)]), np.concatenate([lo, -hi])[:, None]])
            got = self._coal[m] = (coal.Box(*np.maximum(hi - lo, 1e-9)), coal.Transform3s(np.eye(3), (lo + hi) / 2.0),
                                   planes)
        return got

    def _solid(self, m: int) -> tuple:
        """(coal geometry, its transform, its planes (F, 4) (n, d): n . x + d <= 0 inside, base
        frame) of solid m: its box, or the hull it bounds."""
        if self.solid[m]:
            return self._box(m)
        got = self._hull[m]
        if got is None:
            start, P, box_cell = self.hulls
            c = box_cell[m]
            convex, planes = cell_hull(P[start[c]:start[c + 1]], self.boxes[m], self._grid[4])
            got = self._hull[m] = (convex, coal.Transform3s(), planes)
        return got

    def contains(self, X: np.ndarray) -> bool:
        """True when a point of X (K, 3) [m] lies in a solid (faces included, to 1e-9 m; a
        hull's to `occupancy_hulls.GROW`)."""
        boxes, idx, of_cell, origin, res = self._grid
        for x in X:
            lo = np.floor((x - 1e-9) / res).astype(np.int64) - origin
            hi = np.floor((x + 1e-9) / res).astype(np.int64) - origin
            for i in range(max(lo[0], 0), min(hi[0], idx.shape[0] - 1) + 1):
                for j in range(max(lo[1], 0), min(hi[1], idx.shape[1] - 1) + 1):
                    for k in range(max(lo[2], 0), min(hi[2], idx.shape[2] - 1) + 1):
                        cell = idx[i, j, k]
                        if cell < 0:
                            continue
                        m = of_cell[cell]
                        if not (np.all(boxes[m, :3] <= x + 1e-9) and np.all(x <= boxes[m, 3:] + 1e-9)):
                            continue
                        if self.solid[m] or np.all(self._solid(m)[2] @ np.append(x, 1.0) <= HULL_GROW):
                            return True
        return False

    def _obb(self, geometry, tf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The oriented box (axes R (3, 3), centre (3,), half extents (3,)) [m] holding
        `geometry` placed at `tf` (its local bounding box)."""
        got = self._local.get(id(geometry))
        if got is None or got[0] is not geometry:
            local = geometry.aabb_local
            if not local.min_[0] <= local.max_[0]:   # not computed yet (coal's convex hulls)
                geometry.computeLocalAABB()
                local = geometry.aabb_local
            got = (geometry, (local.min_ + local.max_) / 2.0, (local.max_ - local.min_) / 2.0)
            self._local[id(geometry)] = got
        R = tf.getRotation()
        return R, R @ got[1] + tf.getTranslation(), got[2]

    def _aabb(self, geometry, tf) -> tuple[np.ndarray, np.ndarray]:
        """The world box (lo, hi) holding `geometry` placed at `tf`."""
        R, cw, h = self._obb(geometry, tf)
        hw = np.abs(R) @ h
        return cw - hw, cw + hw

    def _hit(self, m: int, geometry, tf, request, result) -> bool:
        """coal.collide of `geometry` at `tf` with solid m (a hull only when its box is hit:
        the box is cheaper, and often clear)."""
        if not self.solid[m]:
            box, btf, _ = self._box(m)
            result.clear()
            if not coal.collide(geometry, tf, box, btf, request, result):
                return False
        solid, stf, _ = self._solid(m)
        result.clear()
        return bool(coal.collide(geometry, tf, solid, stf, request, result))

    def collide(self, geometry, tf, request, result, balls=None) -> bool:
        """coal.collide of `geometry` at `tf` against the solids (within the request's security
        margin): a mesh, convex or box by `occupancy_exact.part_boxes` and coal on the solids
        it leaves; another shape by coal on the solids whose boxes the balls `balls` ((K, 3)
        centres, (K,) radii [m], base frame, holding the geometry, or a callable giving them),
        if known, come near (else its bounding box)."""
        margin = float(request.security_margin) + 1e-9
        hull = part_hull(geometry)
        if hull is not None:   # the boxes a cheap test decides are not given to coal
            hit, ids = part_boxes(*self._grid, self.solid, *self._points, tf.getRotation(), tf.getTranslation(),
                                  *hull, float(request.security_margin))
            if hit:
                return True
            for m in ids.tolist():
                if self._hit(m, geometry, tf, request, result):
                    return True
            return False
        if callable(balls):
            balls = balls()
        if balls is not None:
            ids, d = boxes_near_balls(*self._grid, balls[0], balls[1], margin)
        else:
            ids, d = near_boxes(self.boxes, *self._aabb(geometry, tf), margin)
        if ids.size == 0:
            return False
        for m in (ids.tolist() if ids.size == 1 else ids[np.argsort(d)].tolist()):
            if self._hit(m, geometry, tf, request, result):
                return True
        return False

    def distance(self, geometry, tf, request, result) -> tuple[float, np.ndarray | None]:
        """(coal's distance [m] of `geometry` at `tf` to the nearest solid, the unit direction
        from the geometry to that solid between their closest points (None when touching))."""
        lo, hi = self._aabb(geometry, tf)
        ids, d = near_boxes(self.boxes, lo, hi, np.inf)
        order = np.argsort(d)
        best, normal = np.inf, None
        for m, bound in zip(ids[order].tolist(), d[order].tolist()):
            if bound >= best:
                break
            box, btf, _ = self._solid(m)
            result.clear()
            dist = float(coal.distance(geometry, tf, box, btf, request, result))
            if dist < best:
                best = dist
                normal = result.normal.copy() if dist > 0.0 else None
        return best, normal


def geometry_collide(geometry, tf, obstacle_geometry, obstacle_tf, request, result, balls=None) -> bool:
    """coal.collide, or `MapGeometry.collide` for an occupancy map's geometry (`balls`: its
    argument, a callable giving it, or None)."""
    if type(obstacle_geometry) is MapGeometry:
        return obstacle_geometry.collide(geometry, tf, request, result, balls)
    return bool(coal.collide(geometry, tf, obstacle_geometry, obstacle_tf, request, result))


def geometry_distance(geometry, tf, obstacle_geometry, obstacle_tf, request, result) -> tuple[float, np.ndarray | None]:
    """(coal.distance, the normal of its result (None when touching)), or `MapGeometry.distance`."""
    if type(obstacle_geometry) is MapGeometry:
        return obstacle_geometry.distance(geometry, tf, request, result)
    d = float(coal.distance(geometry, tf, obstacle_geometry, obstacle_tf, request, result))
    return d, (result.normal.copy() if d > 0.0 else None)


def occupancy_candidates(R: np.ndarray, p: np.ndarray, margins: np.ndarray, world_tables: tuple,
                         maps: tuple, exact_depth: bool = True) -> tuple[np.ndarray, ...]:
    """(configuration, part, obstacle, depth) rows (T,) of the moving parts that may come
    within margins (N,) [m] of the occupancy maps `maps` ((obstacle index, broadphase
    tables) pairs, `ObstacleTables.occupancy_maps`); depth: a lower bound of the distance [m].

    Args:
        R, p: joint frames of N configurations; world_tables: the robot side of
            `broadphase.world_candidates` (`CollisionState.world_tables`).
        exact_depth: False for boolean checks (depth then only orders the candidates;
            `occupancy_kernels.map_candidates`).
    """
    margins = np.ascontiguousarray(margins, dtype=np.float64)
    out = []
    for o, tables in maps:
        n, g, d = map_candidates(R, p, margins, exact_depth, *world_tables, *tables)
        if n.size:
            out.append((n, g, np.full(n.size, o, dtype=np.int64), d))
    if not out:
        e = np.zeros(0, dtype=np.int64)
        return e, e, e, np.zeros(0)
    return tuple(np.concatenate(c) for c in zip(*out))


__all__ = ["OccupancyMap", "MapGeometry", "BLOCK", "occupancy_candidates", "geometry_collide", "geometry_distance"]
