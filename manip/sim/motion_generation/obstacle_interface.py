"""`ObstacleInterface`: RmpFlow's obstacle calls over `TrackedObstacles`, written once.

`RmpFlow` and `ControllerMotionPolicy` (what `RMPFlowController.get_motion_policy()` returns)
both take manip.sim shape objects as obstacles the way Isaac's `RmpFlow` does: `add_obstacle`
or the typed `add_cuboid` / `add_sphere` / `add_capsule` / `add_cylinder` / `add_cone` /
`add_ground_plane` (True; False with a warning for an object added twice), and
`remove_obstacle` / `disable_obstacle` / `enable_obstacle` (True; UnknownNameError for an
object that was not added). A class using it has `_obstacles` (the `TrackedObstacles`) and
`_base_from_world()` (the world expressed in the robot base frame, a `Pose`).
"""

from __future__ import annotations

import logging
from typing import Any

from manip.errors import InvalidInputError
from manip.sim.motion_generation.sim_obstacles import (CAPSULES, CONES, CUBOIDS, CYLINDERS, GROUND_WIDTH, SPHERES,
                                                      check_shape, label)
from manip.sim.objects import GroundPlane
from manip.validation import positive

logger = logging.getLogger(__name__)


class ObstacleInterface:
    """RmpFlow's obstacle methods (see the module docstring)."""

    def add_obstacle(self, obstacle: Any, static: bool = False) -> bool:
        """Avoid a manip.sim shape object from now on, at its current pose. `static`: its pose
        is re-read only when the base moves. Returns True, or False (with a warning) if it was
        already added.

        Raises:
            InvalidInputError: not a shape object (the message lists the accepted types).
        """
        check_shape(obstacle)
        if isinstance(obstacle, GroundPlane):
            return self.add_ground_plane(obstacle)
        if obstacle in self._obstacles:
            logger.warning("%s.add_obstacle: %r was already added; it is kept once", type(self).__name__,
                           label(obstacle))
            return False
        self._obstacles.add(obstacle, self._base_from_world(), static=static)
        return True

    def _add_typed(self, obstacle: Any, types: tuple, what: str, static: bool) -> bool:
        if not isinstance(obstacle, types):
            raise InvalidInputError(f"{what}: expected one of {', '.join(t.__name__ for t in types)}; "
                                    f"got {type(obstacle).__name__}")
        return self.add_obstacle(obstacle, static)

    def add_cuboid(self, cuboid: Any, static: bool = False) -> bool:
        return self._add_typed(cuboid, CUBOIDS, "add_cuboid", static)

    def add_sphere(self, sphere: Any, static: bool = False) -> bool:
        return self._add_typed(sphere, SPHERES, "add_sphere", static)

    def add_capsule(self, capsule: Any, static: bool = False) -> bool:
        return self._add_typed(capsule, CAPSULES, "add_capsule", static)

    def add_cylinder(self, cylinder: Any, static: bool = False) -> bool:
        """A cylinder (Lula has none; here it is exact)."""
        return self._add_typed(cylinder, CYLINDERS, "add_cylinder", static)

    def add_cone(self, cone: Any, static: bool = False) -> bool:
        """A cone, avoided as its bounding cylinder (Lula has none)."""
        return self._add_typed(cone, CONES, "add_cone", static)

    def add_ground_plane(self, ground_plane: Any, plane_width: float = GROUND_WIDTH) -> bool:
        """A `GroundPlane`, avoided as Lula does: a static slab `plane_width` [m] wide, 1 mm thick,
        its top face on the plane (the robot's base link is not checked against obstacles)."""
        if not isinstance(ground_plane, GroundPlane):
            raise InvalidInputError(f"add_ground_plane: expected a GroundPlane; got {type(ground_plane).__name__}")
        width = positive(plane_width, "plane_width", "m")
        if ground_plane in self._obstacles:
            logger.warning("%s.add_ground_plane: %r was already added; it is kept once", type(self).__name__,
                           label(ground_plane))
            return False
        self._obstacles.add(ground_plane, self._base_from_world(), static=True, ground_width=width)
        return True

    def remove_obstacle(self, obstacle: Any) -> bool:
        """Stop avoiding an added obstacle; True. Raises UnknownNameError if it was not added."""
        self._obstacles.remove(obstacle)
        return True

    def disable_obstacle(self, obstacle: Any) -> bool:
        """Ignore an added obstacle until `enable_obstacle`; True (UnknownNameError if not added)."""
        self._obstacles.set_enabled(obstacle, False, self._base_from_world())
        return True

    def enable_obstacle(self, obstacle: Any) -> bool:
        """Avoid a disabled obstacle again; True (UnknownNameError if not added)."""
        self._obstacles.set_enabled(obstacle, True, self._base_from_world())
        return True
