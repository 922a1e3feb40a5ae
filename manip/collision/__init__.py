"""The planner's world and collision checking.

- `WorldConfig` and its shapes (`Cuboid`, `Sphere`, `Cylinder`, `Capsule`, `Mesh`), in
  cuRobo's world format.
- `CollisionChecker`: exact (coal) robot-vs-world and self-collision checks with a
  vectorised sphere broadphase generated automatically from the robot's meshes; what it
  returns (`Contact`, `CollisionReport`, `DistanceReport`, `PathCheck`, `AttachedObject`)
  is in `manip.collision.results`.
"""

from __future__ import annotations

from manip.collision.checker import CollisionChecker
from manip.collision.results import AttachedObject, CollisionReport, Contact, DistanceReport, PathCheck
from manip.collision.robot_geometry import RobotGeometry, RobotPart
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Obstacle, Sphere
from manip.collision.spheres import cover_with_spheres
from manip.collision.world import WorldConfig

__all__ = [
    "AttachedObject",
    "Capsule",
    "CollisionChecker",
    "CollisionReport",
    "Contact",
    "Cuboid",
    "Cylinder",
    "DistanceReport",
    "Mesh",
    "Obstacle",
    "PathCheck",
    "RobotGeometry",
    "RobotPart",
    "Sphere",
    "WorldConfig",
    "cover_with_spheres",
]
