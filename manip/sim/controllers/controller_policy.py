"""`ControllerMotionPolicy`: what `RMPFlowController.get_motion_policy()` returns.

Isaac's `RMPFlowController` wraps an `RmpFlow`, and scripts reach it to change the world:

    policy = controller.get_motion_policy()
    policy.add_obstacle(cube)                      # or add_cuboid / add_sphere / ... / add_ground_plane
    policy.set_robot_base_pose(*franka.get_world_pose())
    policy.update_world()

manip's `RMPFlowController` runs a QP controller directly (no `RmpFlow` inside), so this
object is RmpFlow's world interface bound to that controller: the obstacles added here are
the controller's (`controller.add_obstacle` sees them and the reverse), with RmpFlow's
return values (True; False with a warning for an obstacle added twice; UnknownNameError
for removing, enabling or disabling one that was not added). What differs from a real
`RmpFlow`, so that a script's expectations can be checked:

- The base pose: the controller reads the robot's world pose from the articulation at
  every `forward`, so `set_robot_base_pose` only checks the given pose against it and logs
  a warning when they differ (by more than 1 mm or 1 mrad); the articulation's pose is used.
- `update_world` re-reads the obstacles' poses, as RmpFlow's; `forward` does it anyway.
- `reset()` forgets the obstacles, the cspace target and the joint command (RmpFlow's
  reset); `RMPFlowController.reset()` is this reset, as Isaac's.
- Targets and joint targets come from `controller.forward(...)`: there is no
  `set_end_effector_target` or `compute_joint_targets` here.
- Debug drawings do nothing (logged once), as manip's `RmpFlow`.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from manip import quaternion as quat
from manip.control import ReactiveController
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.sim.motion_generation.obstacle_interface import ObstacleInterface
from manip.sim.motion_generation.sim_obstacles import TrackedObstacles
from manip.validation import unit_quat, vec

logger = logging.getLogger(__name__)

#: [m], [rad] a pose given to `set_robot_base_pose` this far from the articulation's is reported.
BASE_POSE_TOLERANCE = (1e-3, 1e-3)

_NO_DRAWING = "manip draws no debug prims (the controller's collision model is the robot's MuJoCo geoms)"


class ControllerMotionPolicy(ObstacleInterface):
    """RmpFlow's world interface over an `RMPFlowController` (see the module docstring).

    Args:
        controller: the controller's `ReactiveController`.
        obstacles: the controller's tracked obstacles (shared).
        base_from_world: returns the world expressed in the robot base frame, from the
            articulation's current world pose (the controller's).
        forget_command: makes the controller's next step start from the measured joints.
    """

    def __init__(self, controller: ReactiveController, obstacles: TrackedObstacles,
                 base_from_world: Callable[[], Pose], forget_command: Callable[[], None]):
        self._ctrl = controller
        self._obstacles = obstacles
        self._base_from_world = base_from_world
        self._forget_command = forget_command
        self._default = controller.rest_configuration
        self._said: set[str] = set()

    # ------------------------------------------------------------------ world
    def update_world(self, updated_obstacles: Iterable[Any] | None = None) -> None:
        """Re-read the poses of the listed obstacles (None: all of them).

        Raises:
            UnknownNameError: a listed object was not added.
        """
        if updated_obstacles is not None and not isinstance(updated_obstacles, (list, tuple)):
            raise InvalidInputError(f"updated_obstacles must be a list of added obstacles or None; "
                                    f"got {type(updated_obstacles).__name__}")
        self._obstacles.sync(self._base_from_world(), objects=updated_obstacles)

    def set_robot_base_pose(self, robot_position, robot_orientation) -> None:
        """Check a base pose (position (3,) [m], orientation (4,) w, x, y, z) against the
        articulation's world pose, which the controller uses; a warning if they differ.

        Raises:
            InvalidInputError: a wrong shape, a NaN, a non-unit quaternion.
        """
        p = vec(robot_position, 3, "robot_position")
        q = unit_quat(robot_orientation, "robot_orientation")
        measured = self._base_from_world().inverse()
        dp = float(np.linalg.norm(p - measured.position))
        dr = float(quat.angle_between(q, measured.quaternion))
        if dp > BASE_POSE_TOLERANCE[0] or dr > BASE_POSE_TOLERANCE[1]:
            logger.warning("set_robot_base_pose: the pose given is %.4g m, %.4g rad from the robot's world pose; "
                           "RMPFlowController follows the articulation's pose (move the robot with "
                           "set_world_pose instead)", dp, dr)

    def reset(self) -> None:
        """Forget the obstacles, the cspace target and the joint command (RmpFlow's reset)."""
        self._obstacles.clear()
        self._ctrl.rest_configuration = self._default
        self._forget_command()

    # ------------------------------------------------------------------ joints
    def get_active_joints(self) -> list[str]:
        """The arm joints the controller drives, in the order of its joint vectors."""
        return list(self._ctrl.joint_names)

    def get_watched_joints(self) -> list[str]:
        """Always empty (as RmpFlow's)."""
        return []

    def get_default_cspace_position_target(self) -> np.ndarray:
        """(dof,) the posture the controller resolves redundancy towards at construction [rad]."""
        return self._default.copy()

    def set_cspace_target(self, active_joint_targets) -> None:
        """The posture the controller resolves redundancy towards: (dof,) [rad] in
        `get_active_joints()` order."""
        self._ctrl.rest_configuration = active_joint_targets

    def get_end_effector_pose(self, active_joint_positions) -> tuple[np.ndarray, np.ndarray]:
        """(position (3,) [m], rotation (3, 3)) of the controlled frame in the world for the
        given (dof,) arm joints [rad], the base where the articulation is now."""
        pose = self._base_from_world().inverse() @ self._ctrl.forward_kinematics(active_joint_positions)
        return pose.position.copy(), quat.to_matrix(pose.quaternion)

    # ------------------------------------------------------------------ debug drawing (none)
    def _log_once(self, what: str) -> None:
        if what not in self._said:
            self._said.add(what)
            logger.warning("%s does nothing in manip: %s", what, _NO_DRAWING)

    def visualize_collision_spheres(self) -> None:
        self._log_once("visualize_collision_spheres")

    def stop_visualizing_collision_spheres(self) -> None:
        self._log_once("stop_visualizing_collision_spheres")

    def visualize_end_effector_position(self) -> None:
        self._log_once("visualize_end_effector_position")

    def stop_visualizing_end_effector(self) -> None:
        self._log_once("stop_visualizing_end_effector")

    def __repr__(self) -> str:
        return f"ControllerMotionPolicy({len(self._obstacles)} obstacles, {self._ctrl!r})"


__all__ = ["BASE_POSE_TOLERANCE", "ControllerMotionPolicy"]
