"""The planner's obstacle shapes as MuJoCo geoms of the controller's model.

Each obstacle of a `WorldConfig` becomes one geom on its own mocap body, so that moving an
obstacle is a pose update (no recompilation). Conventions (both centre the shape on its
frame, axis along local z):

========  ===========================  =========================================
shape     manip.collision              MuJoCo geom size
========  ===========================  =========================================
cuboid    dims = full edge lengths     half edge lengths
sphere    radius                       radius
cylinder  radius, height (full)        radius, half height
capsule   radius, height (segment)     radius, half segment length
mesh      vertices, faces, scale       the convex hull of the scaled vertices
========  ===========================  =========================================

MuJoCo collides meshes through their convex hull: a non-convex mesh obstacle (a shelf, a
bowl) is avoided as its hull, which is larger than the mesh (safe, but the arm cannot
reach inside it). Split such meshes into convex parts to reach in.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Obstacle, Sphere
from manip.errors import InvalidInputError

#: Prefix of the mocap bodies and geoms holding the obstacles in the controller's model.
OBSTACLE_PREFIX = "obstacle/"


@dataclass(frozen=True)
class GeomShape:
    """What a geom of the controller's model needs: MuJoCo type, size and mesh vertices."""

    type: int
    size: tuple[float, float, float]
    vertices: np.ndarray | None = None  # (V, 3) for meshes [m], in the obstacle's frame

    def same_as(self, other: GeomShape) -> bool:
        """Same geometry (so a pose update is enough)."""
        if self.type != other.type or not np.allclose(self.size, other.size, rtol=0.0, atol=1e-12):
            return False
        if self.vertices is None or other.vertices is None:
            return self.vertices is None and other.vertices is None
        return self.vertices.shape == other.vertices.shape and np.array_equal(self.vertices, other.vertices)


def geom_shape(obstacle: Obstacle) -> GeomShape:
    """The MuJoCo geometry of one planner obstacle.

    Raises:
        InvalidInputError: an unsupported shape type.
    """
    if isinstance(obstacle, Cuboid):
        h = np.asarray(obstacle.dims, dtype=float) / 2.0
        return GeomShape(int(mujoco.mjtGeom.mjGEOM_BOX), (float(h[0]), float(h[1]), float(h[2])))
    if isinstance(obstacle, Sphere):
        return GeomShape(int(mujoco.mjtGeom.mjGEOM_SPHERE), (float(obstacle.radius), 0.0, 0.0))
    if isinstance(obstacle, Cylinder):
        return GeomShape(int(mujoco.mjtGeom.mjGEOM_CYLINDER), (float(obstacle.radius), obstacle.height / 2.0, 0.0))
    if isinstance(obstacle, Capsule):
        # A zero-length capsule is a sphere (MuJoCo needs a positive half length).
        if obstacle.height <= 1e-9:
            return GeomShape(int(mujoco.mjtGeom.mjGEOM_SPHERE), (float(obstacle.radius), 0.0, 0.0))
        return GeomShape(int(mujoco.mjtGeom.mjGEOM_CAPSULE), (float(obstacle.radius), obstacle.height / 2.0, 0.0))
    if isinstance(obstacle, Mesh):
        V = np.ascontiguousarray(obstacle.scaled_vertices, dtype=float)
        V.setflags(write=False)
        return GeomShape(int(mujoco.mjtGeom.mjGEOM_MESH), (0.0, 0.0, 0.0), V)
    raise InvalidInputError(
        f"obstacle {getattr(obstacle, 'name', obstacle)!r}: unsupported shape {type(obstacle).__name__}; "
        "valid: Cuboid, Sphere, Cylinder, Capsule, Mesh"
    )


def add_obstacle_body(spec: mujoco.MjSpec, name: str, shape: GeomShape) -> None:
    """Add `name` as a mocap body with one colliding geom (pose set after compiling)."""
    body = spec.worldbody.add_body(name=OBSTACLE_PREFIX + name, mocap=True)
    kwargs = dict(name=OBSTACLE_PREFIX + name, type=mujoco.mjtGeom(shape.type), contype=1, conaffinity=1,
                  group=1, rgba=[0.2, 0.4, 0.9, 0.5])
    if shape.vertices is not None:
        # MuJoCo recentres the mesh on its centroid and moves the geom frame to match, so the
        # hull stays where the vertices put it in the body (= obstacle) frame.
        mesh = spec.add_mesh(name=OBSTACLE_PREFIX + name, uservert=shape.vertices.ravel().tolist())
        kwargs["meshname"] = mesh.name
    else:
        kwargs["size"] = list(shape.size)
    body.add_geom(**kwargs)
