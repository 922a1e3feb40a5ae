"""The planner's world and collision checking.

- `WorldConfig` and its shapes (`Cuboid`, `Sphere`, `Cylinder`, `Capsule`, `Mesh`), in
  cuRobo's world format, and `OccupancyMap` (occupied voxel cells, `manip.collision.occupancy`:
  what cameras saw, `manip.perception`).
- `CollisionChecker`: exact (coal) robot-vs-world and self-collision checks with a
  vectorised sphere broadphase generated automatically from the robot's meshes; what it
  returns (`Contact`, `CollisionReport`, `DistanceReport`, `PathCheck`, `AttachedObject`)
  is in `manip.collision.results`; `certify_path` proves a joint-space polyline free over
  its whole continuous interpolation (`manip.collision.certify`, a `MotionCertificate`);
  `snapshot()` gives a read-only view of one state of the world for other threads
  (`manip.collision.edits`), and `state` that state's tables as one read-only
  `CollisionState` (`manip.collision.state`: what certify, clearance and the planners read).
"""

from __future__ import annotations

from manip.collision.certify import MotionCertificate
from manip.collision.checker import CollisionChecker
from manip.collision.occupancy import OccupancyMap
from manip.collision.results import AttachedObject, CollisionReport, Contact, DistanceReport, PathCheck
from manip.collision.robot_geometry import RobotGeometry, RobotPart
from manip.collision.shapes import Capsule, Cuboid, Cylinder, Mesh, Obstacle, Sphere
from manip.collision.spheres import cover_with_spheres
from manip.collision.state import CollisionState
from manip.collision.world import WorldConfig

__all__ = [
    "AttachedObject",
    "Capsule",
    "CollisionChecker",
    "CollisionReport",
    "CollisionState",
    "Contact",
    "Cuboid",
    "Cylinder",
    "DistanceReport",
    "Mesh",
    "MotionCertificate",
    "Obstacle",
    "OccupancyMap",
    "PathCheck",
    "RobotGeometry",
    "RobotPart",
    "Sphere",
    "WorldConfig",
    "cover_with_spheres",
]
