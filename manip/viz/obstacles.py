"""The planner's world in a viser scene: one node per obstacle, attached objects apart.

Every obstacle type of `manip.collision` is drawn as what it is: a `Cuboid` as a box, a
`Sphere` as an icosphere, a `Cylinder` as a cylinder, a `Capsule` as a capsule mesh, a
`Mesh` as its (scaled) triangles, an `OccupancyMap` (what cameras saw) as the solids the
checks see (merged boxes, and the convex hulls of the cells that keep measured points) in
`MAP_COLOR`. Obstacles are nodes `<root>/<name>` in the base frame;
objects attached to the robot (`MotionGenerator.attach_object`) are drawn in their own
colour under `<attached_root>/<name>` and follow their link (`AttachedDrawing.update`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import numpy as np
import trimesh

from manip.collision.occupancy import OccupancyMap
from manip.collision.results import AttachedObject
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Obstacle, Sphere
from manip.collision.world import WorldConfig
from manip.errors import InvalidInputError
from manip.pose import Pose

logger = logging.getLogger(__name__)

#: Obstacle colour [0-255].
OBSTACLE_COLOR = (214, 140, 69)
#: Colour of the cells of occupancy maps [0-255].
MAP_COLOR = (90, 140, 220)
#: Colour of objects attached to the robot [0-255].
ATTACHED_COLOR = (80, 200, 120)


def add_obstacle(scene: Any, name: str, obstacle: Obstacle, color: tuple[int, int, int],
                 pose: Pose | None = None, opacity: float | None = None) -> Any:
    """Add one obstacle as a scene node.

    Args:
        scene: a viser `SceneApi`.
        name: scene-tree name of the node.
        obstacle: the shape.
        color: RGB [0-255].
        pose: where to draw it (default: the obstacle's own pose, base frame).
        opacity: None (opaque) or in (0, 1].

    Returns:
        The node's handle.

    Raises:
        InvalidInputError: `obstacle` is not one of the five shape types.
    """
    pose = obstacle.pose if pose is None else pose
    kw = dict(color=color, position=np.asarray(pose.position), wxyz=np.asarray(pose.quaternion), opacity=opacity)
    if isinstance(obstacle, Cuboid):
        return scene.add_box(name, dimensions=np.asarray(obstacle.dims, dtype=float), **kw)
    if isinstance(obstacle, Sphere):
        return scene.add_icosphere(name, radius=float(obstacle.radius), **kw)
    if isinstance(obstacle, Cylinder):
        return scene.add_cylinder(name, radius=float(obstacle.radius), height=float(obstacle.height), **kw)
    if isinstance(obstacle, Capsule):
        m = trimesh.creation.capsule(height=float(obstacle.height), radius=float(obstacle.radius))
        return scene.add_mesh_simple(name, m.vertices, m.faces, **kw)
    if isinstance(obstacle, OccupancyMap):
        kw["color"] = MAP_COLOR if color == OBSTACLE_COLOR else color
        V, F = obstacle.solids_mesh()   # the merged boxes and the hulls of the cells with points
        return scene.add_mesh_simple(name, V, F, **kw)
    if isinstance(obstacle, Mesh):
        return scene.add_mesh_simple(name, obstacle.scaled_vertices, obstacle.faces, side="double", **kw)
    raise InvalidInputError(
        f"cannot draw {type(obstacle).__name__} '{getattr(obstacle, 'name', '?')}'; "
        "valid: Cuboid, Sphere, Cylinder, Capsule, Mesh"
    )


class WorldDrawing:
    """The planner's obstacles as scene nodes under `root`, kept equal to a WorldConfig.

    Args:
        scene: a viser `SceneApi`.
        root: scene-tree prefix.
        color: RGB [0-255] of the obstacles.
    """

    def __init__(self, scene: Any, root: str = "/world", color: tuple[int, int, int] = OBSTACLE_COLOR):
        self._scene = scene
        self.root = root
        self.color = color
        self.handles: dict[str, Any] = {}
        self._drawn: dict[str, Obstacle] = {}

    def set_world(self, world: WorldConfig) -> None:
        """Draw exactly the obstacles of `world` (unchanged ones are not re-sent)."""
        if not isinstance(world, WorldConfig):
            raise InvalidInputError(f"world must be a WorldConfig; got {type(world).__name__}")
        wanted = {ob.name: ob for ob in world}
        for name in [n for n in self._drawn if n not in wanted]:
            self.handles.pop(f"{self.root}/{name}").remove()
            del self._drawn[name]
        for name, ob in wanted.items():
            if self._drawn.get(name) is ob:
                continue
            node = f"{self.root}/{name}"
            if node in self.handles:
                self.handles.pop(node).remove()
            self.handles[node] = add_obstacle(self._scene, node, ob, self.color)
            self._drawn[name] = ob


class AttachedDrawing:
    """Objects attached to the robot, drawn in their own colour and moved with their links.

    Args:
        scene: a viser `SceneApi`.
        link_pose: `(q, link) -> Pose` of a link at an arm configuration (base frame),
            e.g. `MotionGenerator.fk`.
        root: scene-tree prefix.
        color: RGB [0-255].
    """

    def __init__(self, scene: Any, link_pose: Callable[[np.ndarray, str], Pose], root: str = "/attached",
                 color: tuple[int, int, int] = ATTACHED_COLOR):
        self._scene = scene
        self._link_pose = link_pose
        self.root = root
        self.color = color
        self.handles: dict[str, Any] = {}
        self._objects: dict[str, AttachedObject] = {}

    def set_objects(self, objects: dict[str, AttachedObject], q: np.ndarray) -> None:
        """Draw exactly `objects` (name -> AttachedObject), placed at configuration q (dof,)."""
        for name in [n for n in self._objects if objects.get(n) is not self._objects[n]]:
            self.handles.pop(f"{self.root}/{name}").remove()
            del self._objects[name]
        for name, att in objects.items():
            if name in self._objects:
                continue
            node = f"{self.root}/{name}"
            self.handles[node] = add_obstacle(self._scene, node, att.obstacle, self.color,
                                              pose=self._pose(att, q))
            self._objects[name] = att
        self.update(q)

    def _pose(self, att: AttachedObject, q: np.ndarray) -> Pose:
        return self._link_pose(q, att.link) @ att.pose_in_link

    def update(self, q: np.ndarray) -> None:
        """Move every attached object with its link to configuration q (dof,) [rad]."""
        for name, att in self._objects.items():
            pose = self._pose(att, q)
            h = self.handles[f"{self.root}/{name}"]
            h.position = np.asarray(pose.position)
            h.wxyz = np.asarray(pose.quaternion)
