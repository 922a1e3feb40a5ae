"""`OccupancyMap`: an obstacle made of the occupied cells of a voxel grid (what cameras saw).

The cells of edge `resolution` [m] lie on a lattice fixed to the robot base frame: cell
(i, j, k) is the box [i r, (i + 1) r] x [j r, (j + 1) r] x [k r, (k + 1) r]. The map is the
union of its occupied cells, as solid boxes, in every check of the planner and in its
continuous certificate:

- broadphase: the robot's sphere covers against a distance bound of the cells (the box
  holding them, blocks of `BLOCK` cells with an exact distance transform between blocks,
  then the exact box distance of the cells within reach of each ball;
  `manip.collision.occupancy_kernels`), so a configuration far from every cell costs a few
  lookups whatever the number of cells;
- exact: coal on the boundary of the union of the boxes (the occupied cells merged into
  disjoint boxes, their faces as triangles); a part inside a box touches no triangle, so a
  point of each of its pieces is looked up in the grid (`contains_points`), as for solid
  meshes (`manip.collision.solids`); the certificate keeps every part off every face, so
  the path's first configuration decides the inside question for the whole path.

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

from manip.collision.occupancy_kernels import cells_contain, map_candidates, merge_boxes, point_lower_bounds
from manip.collision.shapes import Mesh, _check_name, as_pose
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.validation import positive

#: Cells per block edge of the broadphase's block distance bounds.
BLOCK = 4
#: Largest dense grid an occupancy map holds (cells).
MAX_CELLS = 64_000_000

# the 12 triangles of a unit box (corners numbered x * 4 + y * 2 + z), counter-clockwise outside
_BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.int64)
_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.int64)


@dataclass(frozen=True, eq=False)
class OccupancyMap(Mesh):
    """The occupied cells of a voxel grid as one obstacle (see the module docstring).

    Build it with `OccupancyMap.from_cells` (or `manip.perception`, which integrates depth
    images into one). As a `Mesh` it shows its cells' boxes (`vertices`, `faces`) to code
    that draws or exports meshes.

    Attributes:
        resolution: the cells' edge [m].
        cells: (C, 3) int64 lattice indices of the occupied cells, sorted, read-only.
    """

    kind: ClassVar[str] = "occupancy"

    resolution: float = 0.02
    cells: np.ndarray = dataclasses.field(default=None, repr=False)  # type: ignore[assignment]

    def __init__(self, *args, **kwargs):
        raise InvalidInputError("build an OccupancyMap with OccupancyMap.from_cells(name, resolution, cells) "
                                "or MotionGenerator.update_world_from_depth / update_world_from_pointcloud")

    @classmethod
    def from_cells(cls, name: str, resolution: float, cells, _sorted: bool = False) -> OccupancyMap:
        """A map of the given occupied cells.

        Args:
            name: the obstacle's name.
            resolution: cell edge [m] > 0.
            cells: (C, 3) integer lattice indices (C may be 0: an empty map).

        Raises:
            InvalidInputError: a bad name, resolution or cells array.
        """
        _check_name(name, "occupancy map")
        res = positive(resolution, f"occupancy map '{name}': resolution", "m")
        c = np.asarray(cells)
        if c.size == 0:
            c = np.zeros((0, 3), dtype=np.int64)
        if c.ndim != 2 or c.shape[1] != 3 or c.dtype.kind not in "iu":
            raise InvalidInputError(f"occupancy map '{name}': cells must be an integer (C, 3) array; "
                                    f"got {c.dtype.name} {c.shape}")
        c = c.astype(np.int64) if _sorted else np.unique(c.astype(np.int64), axis=0)   # _sorted: distinct, sorted
        c.setflags(write=False)
        out = object.__new__(cls)
        for key, value in (("name", name), ("pose", Pose(np.zeros(3))), ("file_path", None), ("solid", True),
                           ("resolution", float(res)), ("cells", c)):
            object.__setattr__(out, key, value)
        out._tables_of(c)
        return out

    def _tables_of(self, c: np.ndarray) -> None:
        """The dense grid, the broadphase bounds and the boxes' triangles of cells c (C, 3)."""
        res = self.resolution
        shared: dict = {}
        if c.shape[0] == 0:   # an empty map: one tiny box far away stands for the geometry
            lo = np.full(3, 1e6)
            V = lo + _CORNERS * 1e-3
            F = _BOX_FACES.copy()
            occ = np.zeros((1, 1, 1), dtype=np.uint8)
            origin = np.zeros(3, dtype=np.int64)
            blb = np.full((1, 1, 1), np.inf)
            blocks = np.zeros((1, 1, 1), dtype=bool)
            hi = lo
        else:
            origin = c.min(axis=0)
            shape = c.max(axis=0) - origin + 1
            if int(np.prod(shape.astype(float))) > MAX_CELLS:
                raise InvalidInputError(f"occupancy map '{self.name}': its cells span {shape.tolist()} cells "
                                        f"(more than {MAX_CELLS:,}); use a coarser resolution")
            occ = np.zeros(tuple(int(s) for s in shape), dtype=np.uint8)
            rel = c - origin
            occ[rel[:, 0], rel[:, 1], rel[:, 2]] = 1
            lo, hi = origin * res, (origin + shape) * res
            # blocks of BLOCK cells: the exact box-to-box distance between a block and the nearest
            # occupied block is the distance transform of the dilated block grid (module doc)
            nb = -(-shape // BLOCK)
            blocks = np.zeros(tuple(int(s) for s in nb), dtype=bool)
            bi = rel // BLOCK
            blocks[bi[:, 0], bi[:, 1], bi[:, 2]] = True
            grown = ndimage.binary_dilation(np.pad(blocks, 1), structure=np.ones((3, 3, 3), dtype=bool))[1:-1, 1:-1, 1:-1]
            blb = ndimage.distance_transform_edt(~grown) * (BLOCK * res) if not grown.all() else np.zeros(grown.shape)
            boxes = merge_boxes(occ)
            corners = (boxes[:, None, :3] + _CORNERS[None] * (boxes[:, None, 3:] - boxes[:, None, :3]) + origin) * res
            V = corners.reshape(-1, 3)
            F = (_BOX_FACES[None] + 8 * np.arange(boxes.shape[0])[:, None, None]).reshape(-1, 3)
            shared["boxes"] = boxes
        V.setflags(write=False)
        F.setflags(write=False)
        object.__setattr__(self, "vertices", V)
        object.__setattr__(self, "faces", F)
        object.__setattr__(self, "scale", np.ones(3))
        shared["tables"] = (np.ascontiguousarray(occ), float(res), np.ascontiguousarray(origin, dtype=np.int64),
                            np.ascontiguousarray(blb, dtype=np.float64), np.ascontiguousarray(blocks), BLOCK,
                            np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))
        object.__setattr__(self, "_grid", shared)

    # ------------------------------------------------------------------ shape interface
    def _sharing_copy(self) -> OccupancyMap:
        out = object.__new__(type(self))
        out.__dict__.update(self.__dict__)
        return out

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._tables_of(self.cells)   # the dense tables are rebuilt (pickles carry the cells)

    def __getstate__(self) -> dict:
        state = {k: v for k, v in self.__dict__.items() if k not in ("_grid", "vertices", "faces")}
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
        lo, hi = self._grid["tables"][6], self._grid["tables"][7]
        return (lo + hi) / 2.0, (hi - lo) / 2.0

    def to_dict(self) -> dict:
        return {"resolution": self.resolution, "cells": self.cells.tolist()}

    # ------------------------------------------------------------------ queries
    @property
    def num_cells(self) -> int:
        """Number of occupied cells."""
        return int(self.cells.shape[0])

    @property
    def num_boxes(self) -> int:
        """Number of disjoint boxes the cells are merged into (the exact geometry)."""
        b = self._grid.get("boxes")
        return 0 if b is None else int(b.shape[0])

    @property
    def broadphase_tables(self) -> tuple:
        """(occ, res, origin, blb, bocc, BLOCK, lo, hi): the tables of `occupancy_kernels`."""
        return self._grid["tables"]

    def cell_centres(self) -> np.ndarray:
        """(C, 3) centres [m] of the occupied cells (base frame)."""
        return (self.cells + 0.5) * self.resolution

    def contains_points(self, X: np.ndarray) -> bool:
        """True when any point of X (K, 3) (base frame) lies in an occupied cell (faces included)."""
        occ, res, origin = self._grid["tables"][:3]
        return bool(cells_contain(np.ascontiguousarray(X, dtype=np.float64).reshape(-1, 3), occ, res, origin))

    def lower_bounds(self, X: np.ndarray, exact_within: float = 0.0) -> np.ndarray:
        """(M,) lower bounds [m] of the distances of points X (M, 3) to the occupied cells
        (exact below `exact_within` [m]; +inf for an empty map)."""
        X = np.ascontiguousarray(X, dtype=np.float64).reshape(-1, 3)
        if self.num_cells == 0:
            return np.full(X.shape[0], np.inf)
        return point_lower_bounds(X, *self._grid["tables"], float(exact_within))

    def coal_geometry(self):
        """coal's triangles of the boxes' faces (a BVH, cached)."""
        bvh = self._grid.get("bvh")
        if bvh is None:
            bvh = coal.BVHModelOBBRSS()
            bvh.beginModel(self.faces.shape[0], self.vertices.shape[0])
            bvh.addVertices(np.ascontiguousarray(self.vertices, dtype=float))
            bvh.addTriangles(np.ascontiguousarray(self.faces, dtype=np.int64))
            bvh.endModel()
            self._grid["bvh"] = bvh
        return bvh





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
__all__ = ["OccupancyMap", "BLOCK", "occupancy_candidates"]
