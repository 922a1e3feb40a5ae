"""`WorldEdits`: the planner's world, edited through a `MotionGenerator` (mixed into it).

Obstacles (`update_world`, `add_obstacle`, `remove_obstacle`, `update_obstacle_pose`), objects
carried by the robot (`attach_object`, `detach_object`), collision queries at one
configuration (`check_collision`, `distance`) and the simulator's objects
(`update_world_from_sim`), and what cameras see (`update_world_from_depth`,
`update_world_from_pointcloud`: an occupancy map, `manip.perception`). Every edit goes to the generator's `CollisionChecker`, which
serialises edits and hands each query and plan one snapshot (see `MotionGenerator`'s
threading contract).

Needs, from the class it is mixed into: `checker`, `kinematics`, `config`,
`default_joint_positions`, `_one_q`, `_arm_q` and `_link`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from manip.collision import WorldConfig
from manip.errors import InvalidInputError
from manip.perception import integrate_depth, integrate_pointcloud
from manip.planning.arms import shared_attachment
from manip.pose import Pose
from manip.sim_bridge import world_config_from_sim

__all__ = ["WorldEdits"]


class WorldEdits:
    """The world-editing calls of `MotionGenerator` (module docstring)."""

    @property
    def world(self) -> WorldConfig:
        """The planner's current obstacles (a copy)."""
        return self.checker.world

    def update_world(self, world: WorldConfig | dict) -> None:
        """Replace every obstacle with those of `world` (a WorldConfig or cuRobo-style dict; None: no obstacles)."""
        self.checker.set_world(WorldConfig() if world is None else world)

    def add_obstacle(self, obstacle) -> None:
        """Add one obstacle (Cuboid, Sphere, Cylinder, Capsule or Mesh)."""
        self.checker.add_obstacle(obstacle)

    def remove_obstacle(self, name: str) -> None:
        """Remove the obstacle called `name` (UnknownNameError lists the names)."""
        self.checker.remove_obstacle(name)

    def update_obstacle_pose(self, name: str, pose: Pose | Sequence[float]) -> None:
        """Move the obstacle called `name` to `pose` (a Pose, [x, y, z, qw, qx, qy, qz], or a
        position [x, y, z] alone, which keeps the obstacle's rotation).

        `add_obstacle`, `remove_obstacle` and this are incremental (well under a millisecond
        with a thousand obstacles, `benchmarks/world_edits.py`); `update_world` rebuilds all.
        """
        self.checker.update_obstacle_pose(name, pose)

    def check_collision(self, q: np.ndarray | Sequence[float]) -> bool:
        """True when `q` (dof,) collides with the world, an attached object or itself."""
        return bool(self.checker.in_collision(self._one_q(q, "q")))

    def distance(self, q: np.ndarray | Sequence[float]) -> float:
        """Signed distance [m] of `q` (dof,) to the world and to itself (< 0: penetration).

        The robot's link meshes enter through their convex hulls: exact for convex links (the
        Panda's), a lower bound for others (a UR5 forearm's hull may overlap its wrist by
        centimetres where the meshes are clear); `check_collision` is the exact answer."""
        return float(self.checker.distance(self._one_q(q, "q")))

    def attach_object(self, name_or_shape, q: np.ndarray | Sequence[float] | None = None, link: str | None = None,
                      **kwargs):
        """Carry an obstacle (or a new shape) with `link` (default the end-effector).

        The named obstacle leaves the world and moves rigidly with the link from its pose at
        configuration `q` (dof,), the grasp configuration: needed unless `pose_in_link` (the
        object's pose in the link frame) is given (as cuRobo's `attach_objects_to_robot` needs
        the joint state). Two links, `link=("left_panda_hand",
        "right_panda_hand")`: an object both hold moves with the first, and the second's links
        never count as touching it (plan with a `RelativePoseConstraint` of the two so that the
        second keeps its hold; `planning.arms.shared_attachment`).
        """
        qq = None if q is None else self._one_q(q, "q")
        if isinstance(link, (tuple, list)):
            link, kwargs["allowed_links"] = shared_attachment(self.checker.robot.parts, self.kinematics, link,
                                                              kwargs.get("allowed_links", ()))
        return self.checker.attach_object(name_or_shape, q=qq, link=self._link(link), **kwargs)

    def detach_object(self, q: np.ndarray | Sequence[float] | None = None, **kwargs):
        """Put attached objects back into the world at their pose at configuration `q` (dof,), the
        configuration at release (needed: cuRobo's `detach_object_from_robot` only drops the
        object, manip puts it back into the world where the hand leaves it)."""
        if q is None:
            raise InvalidInputError("detach_object needs q, the configuration at release (dof,) [rad]: the object is "
                                    "put back into the world at its pose there")
        qq = self._one_q(q, "q")
        return self.checker.detach_object(qq, **kwargs)

    def update_world_from_sim(self, world, robot, ignore: Sequence[str] = ()) -> WorldConfig:
        """Read every collision object of a `manip.sim` World into the planner's world.

        Objects are expressed in the robot's base frame (a multi-arm robot: `robot` is the list of
        its arms' simulated robots, in arm order). The robot itself and objects whose
        name or prim path starts with an entry of `ignore` are skipped. Attached objects
        stay attached. Returns the new WorldConfig.

        The ground plane (or table) the robot stands on stays an obstacle and needs no
        `ignore`: an obstacle wholly below the base frame's xy-plane (its top within 1 mm of
        z = 0) is not checked against the links fixed to the base (panda_link0), which no
        motion moves; every moving link is checked against it.

        Raises:
            InvalidInputError: called before the World's first `reset()`; `robot` not the
                articulation of this generator's robot; a malformed `ignore`.
            UnknownNameError: an `ignore` entry that names nothing in the World.
        """
        arms = self.config.arms if isinstance(robot, (list, tuple)) else ()   # one simulated robot per arm
        cfg = world_config_from_sim(world, robot, ignore, base_in_robot=arms[0].base_pose.inverse() if arms else None)
        dofs = None if isinstance(robot, (list, tuple)) else robot.dof_names
        if dofs is not None and not set(self.joint_names) <= set(dofs):
            raise InvalidInputError(
                f"robot {getattr(robot, 'name', robot)!r} has the joints {list(dofs)}, not this generator's "
                f"({self.config.name}: {self.joint_names}): read the World with the robot this generator plans for")
        self.update_world(cfg)
        return cfg

    def update_world_from_depth(self, depth, intrinsics, camera_pose, *, name="camera", resolution=0.02, q=None,
                                max_range=3.0, unknown="free", bounds=None, self_margin=0.01, fill="points"):
        """Integrate one depth image into the occupancy obstacle `name` (created on first use).

        Args:
            depth: (H, W) float32/float64 distance to the image plane [m] (inf or 0: no return).
            intrinsics: (3, 3) camera matrix [px].
            camera_pose: `Pose` of the camera in the robot base frame (Isaac's camera axes:
                +X forward, +Z up).
            name: the map's obstacle name; `remove_obstacle(name)` clears it.
            resolution: cell edge [m] (at most 0.5 m). max_range: farther returns are ignored [m].
            q: the robot's configuration (dof,), whose points are filtered out, or its full
                state (arm, then gripper joints: `franka.get_joint_positions()`), which places
                the fingers where they are; None: no self-filtering.
            unknown: "free" (cells never seen are free) or "occupied" (within `bounds`,
                ((3,), (3,)) [m] in the base frame, unseen cells are obstacles).
            self_margin: points within this of the robot's geometry are dropped [m].
            fill: what an occupied cell holds: "points" (the default: the convex hull of the
                points measured in it: surfaces as the camera saw them, what they hide unknown)
                or "cells" (the whole cell: surfaces inflated by up to a cell).

        Rays mark their end cells occupied and the cells they cross free; details and what the
        map guarantees: `manip.perception.integrate`.
        """
        return integrate_depth(self.checker, depth, intrinsics, camera_pose, q=q, name=name,
                               resolution=resolution, max_range=max_range, unknown=unknown, bounds=bounds,
                               self_margin=self_margin, fill=fill)

    def update_world_from_pointcloud(self, points, origin=None, *, name="camera", resolution=0.02, q=None,
                                     max_range=3.0, unknown="free", bounds=None, self_margin=0.01, fill="points"):
        """Integrate a point cloud `points` (N, 3) [m] (base frame) seen from `origin` (3,) [m] into
        the occupancy obstacle `name`; the other arguments as `update_world_from_depth` (without
        `origin`, no ray frees a cell)."""
        return integrate_pointcloud(self.checker, points, origin, q=q, name=name,
                                    resolution=resolution, max_range=max_range, unknown=unknown, bounds=bounds,
                                    self_margin=self_margin, fill=fill)
