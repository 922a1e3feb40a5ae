"""A collision mesh from a point cloud: the surface of the occupied voxels.

Used by the tutorial wrapper's `update_world_by_pointcloud` (cuRobo builds a mesh from the
cloud too, `Mesh.from_pointcloud`). Every point marks the cube of side `pitch` that holds
it; the mesh is the outer faces of those cubes (faces shared by two occupied cubes are left
out), two triangles per face, outward normals. Non-convex clouds stay non-convex; a flat or
single-point cloud still gives a closed box surface `pitch` thick.
"""

from __future__ import annotations

import numpy as np

from manip.collision import Mesh
from manip.errors import InvalidInputError
from manip.pose import Pose

#: The 6 faces of a unit cube: (axis, side, the 4 corners (counter-clockwise seen from outside)).
_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
_FACES = (
    # neighbour offset, corner indices of the face (outward, counter-clockwise)
    ((-1, 0, 0), (0, 1, 3, 2)),
    ((1, 0, 0), (4, 6, 7, 5)),
    ((0, -1, 0), (0, 4, 5, 1)),
    ((0, 1, 0), (2, 3, 7, 6)),
    ((0, 0, -1), (0, 2, 6, 4)),
    ((0, 0, 1), (1, 5, 7, 3)),
)


def voxel_mesh(points: np.ndarray, pitch: float = 0.02, name: str = "world_pointcloud") -> Mesh:
    """The surface mesh of the voxels of side `pitch` [m] occupied by `points` (N, 3) [m].

    Args:
        points: (N, 3) finite points, N >= 1, in the robot base frame [m].
        pitch: voxel side [m].
        name: the mesh obstacle's name.

    Raises:
        InvalidInputError: a wrong shape, no points, a non-finite value or pitch <= 0.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] == 0:
        raise InvalidInputError(f"points must have shape (N, 3) with N >= 1; got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InvalidInputError("points must be finite")
    if not (np.isfinite(pitch) and pitch > 0):
        raise InvalidInputError(f"pitch must be > 0 [m]; got {pitch}")
    cells = np.unique(np.floor(p / pitch).astype(np.int64), axis=0)
    occupied = {tuple(c) for c in cells.tolist()}
    origin = cells.min(axis=0)
    vert_index: dict[tuple[int, int, int], int] = {}
    vertices: list[tuple[int, int, int]] = []
    faces: list[tuple[int, int, int]] = []

    def vid(corner: tuple[int, int, int]) -> int:
        k = vert_index.get(corner)
        if k is None:
            k = vert_index[corner] = len(vertices)
            vertices.append(corner)
        return k

    for c in cells.tolist():
        for offset, quad in _FACES:
            if (c[0] + offset[0], c[1] + offset[1], c[2] + offset[2]) in occupied:
                continue
            ids = [vid((c[0] + int(_CORNERS[i, 0]), c[1] + int(_CORNERS[i, 1]), c[2] + int(_CORNERS[i, 2])))
                   for i in quad]
            faces.append((ids[0], ids[1], ids[2]))
            faces.append((ids[0], ids[2], ids[3]))
    V = (np.asarray(vertices, dtype=float) - origin) * pitch
    offset = origin * pitch
    return Mesh(name, pose=Pose(offset), vertices=V,
                faces=np.asarray(faces, dtype=int))
