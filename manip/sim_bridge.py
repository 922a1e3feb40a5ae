"""Read a simulated World's collision shapes into a planner `WorldConfig`.

Duck-typed over `manip.sim` (it calls `world.scene.get_collision_objects()` and
`robot.get_world_pose()`), so the motion generator does not import the simulator.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np

from manip.collision import Capsule, Cuboid, Cylinder, Mesh, Sphere, WorldConfig
from manip.pose import Pose

logger = logging.getLogger(__name__)

#: Planes become boxes this large [m] (x, y) and thick (z), their top face on the plane.
PLANE_SIZE = 20.0
PLANE_THICKNESS = 0.1


def _ignored(name: str, prim_path: str, ignore: Sequence[str]) -> bool:
    return any(name.startswith(p) or prim_path.startswith(p) for p in ignore if p)


def world_config_from_sim(world, robot, ignore: Sequence[str] = ()) -> WorldConfig:
    """Every collision object of `world`, in `robot`'s base frame, as a WorldConfig.

    Args:
        world: a `manip.sim.World` after `reset()`.
        robot: the planned robot (its own geoms are skipped; other robots are obstacles).
        ignore: names or prim-path prefixes to leave out (e.g. the object to pick, the ground).

    Ellipsoids become their bounding sphere (conservative); cones and meshes become meshes;
    planes become large boxes under their surface.
    """
    position, orientation = robot.get_world_pose()
    T_base_world = Pose(np.asarray(position, dtype=float), np.asarray(orientation, dtype=float)).inverse()
    robot_path = getattr(robot, "prim_path", None)
    cfg = WorldConfig()
    used: set[str] = set()
    for obj in world.scene.get_collision_objects():
        if obj.is_robot and obj.robot_prim_path == robot_path:
            continue
        if _ignored(obj.name, obj.prim_path, ignore):
            continue
        pose = T_base_world @ obj.pose
        name = obj.name
        k = 1
        while name in used:  # one scene object may own several geoms
            k += 1
            name = f"{obj.name}#{k}"
        used.add(name)
        dims = np.asarray(obj.dimensions, dtype=float)
        if obj.shape == "cuboid":
            cfg.add(Cuboid(name, dims, pose))
        elif obj.shape == "sphere":
            cfg.add(Sphere(name, float(dims[0]), pose))
        elif obj.shape == "cylinder":
            cfg.add(Cylinder(name, float(dims[0]), float(dims[1]), pose))
        elif obj.shape == "capsule":
            cfg.add(Capsule(name, float(dims[0]), float(dims[1]), pose))
        elif obj.shape == "ellipsoid":
            cfg.add(Sphere(name, float(np.max(dims)), pose))
        elif obj.shape in ("mesh", "cone"):
            if obj.vertices is None or obj.faces is None:
                logger.warning("skipping %s: mesh without vertices", name)
                continue
            cfg.add(Mesh(name, pose=pose, vertices=obj.vertices, faces=obj.faces))
        elif obj.shape == "plane":
            box = Pose(np.array([0.0, 0.0, -PLANE_THICKNESS / 2]))
            cfg.add(Cuboid(name, [PLANE_SIZE, PLANE_SIZE, PLANE_THICKNESS], pose @ box))
        else:
            logger.warning("skipping %s: unsupported shape %r", name, obj.shape)
    return cfg
