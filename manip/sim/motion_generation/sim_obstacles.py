"""manip.sim shape objects as obstacles of a `manip.control.ReactiveController`.

Shared by `RmpFlow` (Isaac's motion policy names) and `manip.sim.RMPFlowController`: both
keep the simulated objects a script gives them (`add_obstacle(cube)`) in the controller's
world, in the robot base frame, and re-read their poses when told to.

- `obstacle_from_prim(obj, name, pose)`: the planner shape of one object (a ground plane:
  a slab `GROUND_WIDTH` wide and `GROUND_THICKNESS` thick below the plane, as Lula makes it).
- `TrackedObstacles`: the objects added to one controller, by identity, with Isaac's
  `static` flag and enabled state; `sync` re-reads their world poses.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from manip.collision.shapes import Capsule, Cuboid, Cylinder, Obstacle, Sphere
from manip.control import ReactiveController
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose
from manip.sim.objects import (
    GroundPlane,
    DynamicCapsule,
    DynamicCone,
    DynamicCuboid,
    DynamicCylinder,
    DynamicSphere,
    FixedCapsule,
    FixedCone,
    FixedCuboid,
    FixedCylinder,
    FixedSphere,
    VisualCapsule,
    VisualCone,
    VisualCuboid,
    VisualCylinder,
    VisualSphere,
)
from manip.sim.scenes.stage import SimulationError

CUBOIDS = (VisualCuboid, FixedCuboid, DynamicCuboid)
SPHERES = (VisualSphere, FixedSphere, DynamicSphere)
CYLINDERS = (VisualCylinder, FixedCylinder, DynamicCylinder)
CAPSULES = (VisualCapsule, FixedCapsule, DynamicCapsule)
CONES = (VisualCone, FixedCone, DynamicCone)
#: Every object type accepted as an obstacle.
SHAPE_TYPES = CUBOIDS + SPHERES + CYLINDERS + CAPSULES + CONES + (GroundPlane,)
#: A ground plane's slab: width [m] (Lula's default) and thickness [m] (Lula's), top face on the plane.
GROUND_WIDTH = 50.0
GROUND_THICKNESS = 0.001


def check_shape(obj: Any, what: str = "add_obstacle") -> None:
    """Raise InvalidInputError unless `obj` is one of `SHAPE_TYPES`."""
    if not isinstance(obj, SHAPE_TYPES):
        raise InvalidInputError(
            f"{what}: expected a manip.sim shape object (Visual/Fixed/Dynamic Cuboid, Sphere, Cylinder, Capsule, "
            f"Cone, or a GroundPlane); got {type(obj).__name__}"
        )


def obstacle_from_prim(obj: Any, name: str, pose: Pose, ground_width: float = GROUND_WIDTH) -> Obstacle:
    """A planner shape for a manip.sim shape object at `pose` (robot base frame).

    Cuboids, spheres, cylinders and capsules are exact (scale included); a non-uniformly
    scaled sphere becomes its bounding sphere and a cone its bounding cylinder.

    Raises:
        InvalidInputError: not one of manip.sim's shape objects.
    """
    check_shape(obj)
    if isinstance(obj, GroundPlane):
        below = pose @ Pose(np.array([0.0, 0.0, -GROUND_THICKNESS / 2]))
        return Cuboid(name, [ground_width, ground_width, GROUND_THICKNESS], below)
    s = np.asarray(obj.get_local_scale(), dtype=float)
    if isinstance(obj, CUBOIDS):
        return Cuboid(name, obj.get_size() * s, pose)
    if isinstance(obj, SPHERES):
        return Sphere(name, obj.get_radius() * float(np.max(s)), pose)
    if isinstance(obj, CYLINDERS + CONES):
        return Cylinder(name, obj.get_radius() * float(max(s[0], s[1])), obj.get_height() * s[2], pose)
    return Capsule(name, obj.get_radius() * float(max(s[0], s[1])), obj.get_height() * s[2], pose)


def label(obj: Any) -> str:
    """The name an object is known by: its prim path (else its name)."""
    return str(getattr(obj, "prim_path", None) or getattr(obj, "name", None) or type(obj).__name__)


@dataclass
class _Entry:
    obj: Any
    name: str
    static: bool
    ground_width: float = GROUND_WIDTH
    enabled: bool = True


class TrackedObstacles:
    """The manip.sim objects a controller avoids, kept by identity.

    Args:
        controller: the controller whose world holds the obstacles (base frame).
    """

    def __init__(self, controller: ReactiveController):
        self._ctrl = controller
        self._entries: dict[int, _Entry] = {}

    def __contains__(self, obj: Any) -> bool:
        return id(obj) in self._entries

    def __len__(self) -> int:
        return len(self._entries)

    @property
    def names(self) -> list[str]:
        """The added objects' names (prim paths), in the order added."""
        return [e.name for e in self._entries.values()]

    def _entry(self, obj: Any, what: str) -> _Entry:
        entry = self._entries.get(id(obj))
        if entry is None:
            raise UnknownNameError(f"{what}: obstacle", label(obj), self.names)
        return entry

    @staticmethod
    def _pose(obj: Any, T_base_world: Pose) -> Pose:
        pose = obj.get_world_pose()
        if pose is None or pose[0] is None:
            raise SimulationError(f"obstacle {label(obj)!r} has no pose (removed from the stage?); "
                                  "remove_obstacle it before stepping on")
        return T_base_world @ Pose(np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float))

    def add(self, obj: Any, T_base_world: Pose, static: bool = False, ground_width: float = GROUND_WIDTH) -> None:
        """Avoid `obj` from now on, at its current pose (the caller checks `obj in self` first);
        `ground_width` [m]: a ground plane's slab.

        Raises:
            InvalidInputError: not a shape object (`SHAPE_TYPES`), or `static` not a bool.
        """
        if not isinstance(static, (bool, np.bool_)):
            raise InvalidInputError(f"static must be a bool; got {static!r}")
        check_shape(obj)
        name = label(obj)
        self._ctrl.add_obstacle(obstacle_from_prim(obj, name, self._pose(obj, T_base_world), ground_width))
        self._entries[id(obj)] = _Entry(obj, name, bool(static), ground_width)

    def remove(self, obj: Any, what: str = "remove_obstacle") -> None:
        """Stop avoiding `obj`.

        Raises:
            UnknownNameError: it was not added (the message lists those that were).
        """
        entry = self._entry(obj, what)
        if entry.enabled:
            self._ctrl.remove_obstacle(entry.name)
        del self._entries[id(obj)]

    def set_enabled(self, obj: Any, enabled: bool, T_base_world: Pose) -> None:
        """Disable (take out of the controller's world, kept here) or enable again.

        Raises:
            UnknownNameError: `obj` was not added.
        """
        entry = self._entry(obj, "enable_obstacle" if enabled else "disable_obstacle")
        if enabled and not entry.enabled:
            self._ctrl.add_obstacle(obstacle_from_prim(obj, entry.name, self._pose(obj, T_base_world),
                                                       entry.ground_width))
        elif not enabled and entry.enabled:
            self._ctrl.remove_obstacle(entry.name)
        entry.enabled = bool(enabled)

    def sync(self, T_base_world: Pose, objects: Iterable[Any] | None = None, include_static: bool = True) -> None:
        """Move the enabled obstacles to their current world poses.

        Args:
            T_base_world: the world expressed in the robot base frame.
            objects: only these (each must have been added); None: all.
            include_static: with `objects` None, also the obstacles added as static.

        Raises:
            UnknownNameError: an object of `objects` was not added.
        """
        if objects is None:
            entries = [e for e in self._entries.values() if include_static or not e.static]
        else:
            entries = [self._entry(o, "update_world: updated_obstacles") for o in objects]
        for e in entries:
            if e.enabled:
                self._ctrl.set_obstacle_pose(e.name, self._pose(e.obj, T_base_world))

    def clear(self) -> None:
        """Remove every obstacle."""
        for obj in [e.obj for e in self._entries.values()]:
            self.remove(obj)


__all__ = ["GROUND_THICKNESS", "GROUND_WIDTH", "SHAPE_TYPES", "TrackedObstacles", "check_shape", "label", "obstacle_from_prim"]
