"""What cameras see, as an obstacle of the planner's world: an occupancy map.

`integrate_depth` / `integrate_pointcloud` (`manip.perception.integrate`) update a
`manip.collision.OccupancyMap` of a `CollisionChecker`'s world from a depth image or a point
cloud; `MotionGenerator.update_world_from_depth` / `update_world_from_pointcloud` call them.
The compiled parts are in `manip.perception.kernels` (the images) and `manip.perception.observations`
(the map's state).
"""

from __future__ import annotations

from manip.perception.integrate import integrate_depth, integrate_pointcloud

__all__ = ["integrate_depth", "integrate_pointcloud"]
