"""`RmpFlow`: Isaac Sim's RMPflow motion-policy interface on manip's QP controller.

    rmpflow = RmpFlow(**interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow"))
    rmpflow.set_robot_base_pose(position, orientation_wxyz)
    rmpflow.add_obstacle(cube)
    rmpflow.set_end_effector_target(target_position, target_orientation)
    rmpflow.update_world()                                  # re-read the obstacles' poses
    positions, velocities = rmpflow.compute_joint_targets(q, qd, [], [], 1 / 60)

It is NOT RMPflow. Isaac's RmpFlow integrates Lula's Riemannian motion policies (an
acceleration field blended by metrics, rolled out at `maximum_substep_size`). This class
runs manip's `manip.control.ReactiveController` instead: differential inverse kinematics as
one quadratic program per call (joint position, velocity and acceleration limits; a
`safety_margin` kept from obstacles and between the robot's links), under Isaac's names and
argument order. What differs, so that a script's expectations can be checked:

- Motion: the end effector converges to a reachable target within a few frames (dead-beat,
  capped by the joint limits and `max_speed`, 1 m/s), not along RMPflow's damped attractor.
  Obstacles are hard constraints: the arm stops `safety_margin` from them (and waits there
  when the target is behind one) instead of being pushed by a repulsive field.
- The joint state: Isaac's RMPflow restarts from the given (measured) joints every frame
  unless `ignore_robot_state_updates`; this controller integrates its own command and
  restarts from the given joints only when they are more than `RESYNC_TOLERANCE` (0.1 rad)
  away from it (`manip.sim.motion_generation.joint_command`: a command rebuilt from drives
  that sag under gravity sinks with them, into an obstacle below the arm). With
  `ignore_robot_state_updates` it never restarts, as Isaac's.
- `maximum_substep_size` is validated and kept, but there is one QP per frame: the
  controller is first order (positions and velocities), there is nothing to integrate.
- Collision geometry is the robot's MuJoCo model (`manip.control.model`), not the
  description's collision spheres: `visualize_collision_spheres` and the other debug
  drawings do nothing (logged once per RmpFlow).
- The robot: the URDF and robot description give the joints, frames and FK
  (`LulaKinematicsSolver`); the controller runs on the manip robot configuration the
  RMPflow YAML names (`manip.sim.motion_generation.rmpflow_config`). The end-effector frame
  is mapped onto a frame of that model (`manip.sim.motion_generation.end_effector_map`).
- Without an end-effector target the arm goes to the end-effector pose of the cspace
  target (`set_cspace_target`), the posture task resolving the rest; with a target the
  cspace target is the posture the redundancy is resolved towards, as in RMPflow.
- Errors stop at their line: an unknown frame, wrong shapes, NaN, non-unit quaternions
  raise InvalidInputError / UnknownNameError; removing, enabling or disabling an obstacle
  that was not added raises UnknownNameError (Isaac returns False). Adding one twice
  returns False with a warning, as Isaac.

Obstacles are manip.sim shape objects (`sim_obstacles.SHAPE_TYPES`: cuboids, spheres,
capsules, cylinders, cones as bounding cylinders, ground planes as Lula's thin slab); their poses are read when added and by
`update_world()` (the non-static ones; every one after the base moved), as Lula's world.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from manip import quaternion as quat
from manip.control import ReactiveController, StepResult
from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose
from manip.robot_config import available_robots, load_robot_config
from manip.sim.motion_generation.end_effector_map import EndEffectorMap
from manip.sim.motion_generation.joint_command import JointCommand
from manip.sim.motion_generation.kinematics_solver import LulaKinematicsSolver
from manip.sim.motion_generation.obstacle_interface import ObstacleInterface
from manip.sim.motion_generation.rmpflow_config import SECTION, load_rmpflow_config
from manip.sim.motion_generation.sim_obstacles import TrackedObstacles
from manip.sim.motion_generation.urdf_aliases import URDF_ALIASES, resolve_urdf
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.urdf import UrdfTree
from manip.validation import as_real_array, positive, unit_quat, vec

logger = logging.getLogger(__name__)

#: [rad] the given joints restart the command when this far from it (ignore_robot_state_updates False).
RESYNC_TOLERANCE = 0.1

_NO_SPHERES = "manip's controller has no collision spheres (it uses the robot's MuJoCo collision geoms)"
_NO_PRIMS = "manip draws no debug prims for RmpFlow"


def _flag(value: Any, what: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"{what} must be a bool; got {value!r}")
    return bool(value)


class RmpFlow(ObstacleInterface):
    """Isaac's `RmpFlow` motion policy, running manip's QP controller (see the module docstring).

    Args:
        robot_description_path: the Lula robot description YAML (its `cspace` are the active joints).
        urdf_path: the robot's URDF (or `.../lula_franka_gen.urdf`, mapped to manip's Franka).
        rmpflow_config_path: the RMPflow YAML; manip reads its `manip` section.
        end_effector_frame_name: a link of the URDF (Isaac's Franka: "right_gripper").
        maximum_substep_size: [s] > 0; kept for Isaac's interface (one QP per frame).
        ignore_robot_state_updates: True: each `compute_joint_targets` starts from the state it
            computed last (the given state is used once, on the first call), as Isaac's. False
            (Isaac's default, where RMPflow restarts from the given state every frame): from the
            state it computed last too, and from the given state when that is more than
            `RESYNC_TOLERANCE` away (`joint_command` says why: drives sag under gravity).

    Raises:
        FileNotFoundError: a file is missing.
        UnknownNameError: an unknown end-effector frame (the message lists the URDF's links).
        InvalidInputError: bad arguments or files (named in the message); a cspace that is not
            the arm of the controller's robot.
        RobotConfigError: the URDF and manip's robot model disagree.
    """

    def __init__(self, robot_description_path: str, urdf_path: str, rmpflow_config_path: str,
                 end_effector_frame_name: str, maximum_substep_size: float, ignore_robot_state_updates: bool = False):
        self.maximum_substep_size = positive(maximum_substep_size, "maximum_substep_size", "s")
        self._resync = RESYNC_TOLERANCE
        self._command = JointCommand(RESYNC_TOLERANCE)
        self.ignore_robot_state_updates = ignore_robot_state_updates
        self._paths = (robot_description_path, urdf_path)
        self._kinematics = LulaKinematicsSolver(robot_description_path, urdf_path)
        frames = self._kinematics.get_all_frame_names()
        if not isinstance(end_effector_frame_name, str) or end_effector_frame_name not in frames:
            raise UnknownNameError("end_effector_frame_name: frame", str(end_effector_frame_name), frames)
        self.end_effector_frame_name = end_effector_frame_name
        config = load_rmpflow_config(rmpflow_config_path)
        robot = config.robot or getattr(URDF_ALIASES.get(Path(str(urdf_path)).name), "robot", None)
        if robot is None:
            raise InvalidInputError(f"{config.path}: name the manip robot configuration the controller runs on "
                                    f"(`{SECTION}: {{robot: NAME}}`); available: {', '.join(available_robots())}")
        try:
            self._ctrl = ReactiveController(load_robot_config(robot), **config.controller_options)
        except InvalidInputError as exc:
            raise InvalidInputError(f"{config.path}: {exc}") from None
        self._cspace = self._kinematics.get_joint_names()
        arm = list(self._ctrl.joint_names)
        if sorted(self._cspace) != sorted(arm):
            raise InvalidInputError(f"robot_description_path: cspace {self._cspace} must be the arm joints of manip's "
                                    f"robot {robot!r}: {arm}")
        self._to_ctrl = np.array([self._cspace.index(n) for n in arm])
        self._to_cspace = np.array([arm.index(n) for n in self._cspace])
        desc = self._kinematics.description
        self._default = (desc.default_q.copy() if desc.default_q is not None
                         else self._ctrl.config.default_joint_positions[self._to_cspace].copy())
        self._ctrl.rest_configuration = self._default[self._to_ctrl]
        tree = UrdfTree(resolve_urdf(urdf_path))
        self._ee = EndEffectorMap(self._ctrl, tree, desc.root_link or tree.root_link, end_effector_frame_name,
                                  self._fk_root)
        self._weights = self._ctrl.weights
        self._obstacles = TrackedObstacles(self._ctrl)
        self._said: set[str] = set()
        self.reset()

    def _fk_root(self, frame: str, q_ctrl: np.ndarray) -> Pose:
        p, R = self._kinematics.compute_forward_kinematics(frame, np.asarray(q_ctrl)[self._to_cspace])
        return Pose(p, quat.from_matrix(R))

    # ------------------------------------------------------------------ manip's accessors
    @property
    def controller(self) -> ReactiveController:
        """The `manip.control.ReactiveController` doing the work."""
        return self._ctrl

    @property
    def controlled_frame(self) -> str:
        """The controller model's frame standing for the end effector (`end_effector_map`)."""
        return self._ee.frame

    @property
    def last_result(self) -> StepResult | None:
        """The controller's `StepResult` of the last `compute_joint_targets` (errors, clearance)."""
        return self._last

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """Back to the state after construction, as Isaac's: no obstacles, the base at the origin,
        no targets, the default cspace target, no internal joint state."""
        self._obstacles.clear()
        self._T_world_root = Pose(np.zeros(3))
        self._kinematics.set_robot_base_pose(np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]))
        self._base_moved = False
        self._target_position: np.ndarray | None = None
        self._target_orientation: np.ndarray | None = None
        self._command.reset()
        self._last: StepResult | None = None
        self._ctrl.reset()
        self._ctrl.rest_configuration = self._default[self._to_ctrl]
        self._set_position_free(False)

    @property
    def ignore_robot_state_updates(self) -> bool:
        """See the class's argument (Isaac's attribute; may be set)."""
        return self._ignore

    @ignore_robot_state_updates.setter
    def ignore_robot_state_updates(self, value: bool) -> None:
        self._ignore = _flag(value, "ignore_robot_state_updates")
        self._command.resync_tolerance = None if self._ignore else self._resync

    def set_ignore_state_updates(self, ignore_robot_state_updates: bool) -> None:
        """See the class's `ignore_robot_state_updates`."""
        self.ignore_robot_state_updates = ignore_robot_state_updates

    @property
    def resync_tolerance(self) -> float:
        """[rad] how far the given joints may be from the command before a step restarts from
        them (default `RESYNC_TOLERANCE`; not used with `ignore_robot_state_updates`). A tiny
        value restarts every frame, as Isaac's RMPflow (see the module docstring)."""
        return self._resync

    @resync_tolerance.setter
    def resync_tolerance(self, value: float) -> None:
        self._resync = positive(value, "resync_tolerance", "rad")
        self.ignore_robot_state_updates = self._ignore

    def set_robot_base_pose(self, robot_position, robot_orientation) -> None:
        """Place the robot description's root link in the world: position (3,) [m],
        orientation (4,) (w, x, y, z). Until called, the origin."""
        p = vec(robot_position, 3, "robot_position")
        q = unit_quat(robot_orientation, "robot_orientation")
        pose = Pose(p, q)
        old = self._T_world_root
        if not (np.array_equal(pose.position, old.position) and np.array_equal(pose.quaternion, old.quaternion)):
            self._base_moved = True
        self._T_world_root = pose
        self._kinematics.set_robot_base_pose(p, q)

    def _base_from_world(self) -> Pose:
        """The world in the controller's base frame."""
        return self._ee.T_base_root @ self._T_world_root.inverse()

    # ------------------------------------------------------------------ joints
    def get_active_joints(self) -> list[str]:
        """The joints controlled, in the order of every joint vector (the description's cspace)."""
        return list(self._cspace)

    def get_watched_joints(self) -> list[str]:
        """Always empty (as Isaac's RmpFlow)."""
        return []

    def _joints(self, values, what: str) -> np.ndarray:
        try:
            return vec(values, len(self._cspace), what)
        except InvalidInputError as exc:
            raise InvalidInputError(f"{exc} (active joints {self._cspace})") from None

    @staticmethod
    def _watched(values, what: str) -> None:
        if values is not None and as_real_array(values, what).size != 0:
            raise InvalidInputError(f"{what} must be empty (RmpFlow watches no joints); got {np.shape(values)}")

    def get_default_cspace_position_target(self) -> np.ndarray:
        """(dof,) the description's `default_q` (else the robot configuration's) [rad]."""
        return self._default.copy()

    def set_cspace_target(self, active_joint_targets) -> None:
        """The posture the controller resolves redundancy towards, and goes to without an
        end-effector target: (dof,) [rad] in `get_active_joints()` order."""
        self._ctrl.rest_configuration = self._joints(active_joint_targets, "active_joint_targets")[self._to_ctrl]

    def set_internal_robot_joint_states(self, active_joint_positions, active_joint_velocities,
                                        watched_joint_positions=None, watched_joint_velocities=None) -> None:
        """Overwrite the internal joint state (the next step starts from it)."""
        q = self._joints(active_joint_positions, "active_joint_positions")
        v = self._joints(active_joint_velocities, "active_joint_velocities")
        self._watched(watched_joint_positions, "watched_joint_positions")
        self._watched(watched_joint_velocities, "watched_joint_velocities")
        self._command.update(q, v)

    def get_internal_robot_joint_states(self) -> tuple[np.ndarray | None, np.ndarray | None, np.ndarray, np.ndarray]:
        """(positions, velocities, empty, empty): the state computed last (None before any)."""
        q, v = self._command.positions, self._command.velocities
        return (None if q is None else q.copy()), (None if v is None else v.copy()), np.empty(0), np.empty(0)

    # ------------------------------------------------------------------ kinematics
    def get_end_effector_pose(self, active_joint_positions) -> tuple[np.ndarray, np.ndarray]:
        """(position (3,) [m], rotation (3, 3)) of the end effector in the world."""
        q = self._joints(active_joint_positions, "active_joint_positions")
        return self._kinematics.compute_forward_kinematics(self.end_effector_frame_name, q)

    def get_kinematics_solver(self) -> LulaKinematicsSolver:
        """A new `LulaKinematicsSolver` of the same files, placed at this policy's base pose
        (the two base poses are updated separately from then on, as in Isaac)."""
        solver = LulaKinematicsSolver(*self._paths)
        solver.set_robot_base_pose(self._T_world_root.position, self._T_world_root.quaternion)
        return solver

    # ------------------------------------------------------------------ targets
    def set_end_effector_target(self, target_position=None, target_orientation=None) -> None:
        """The end effector's target in the world: position (3,) [m] and/or orientation (4,)
        (w, x, y, z); None leaves that part free (both None: go to the cspace target)."""
        position = None if target_position is None else vec(target_position, 3, "target_position")
        orientation = None if target_orientation is None else unit_quat(target_orientation, "target_orientation")
        self._target_position, self._target_orientation = position, orientation

    def _set_position_free(self, free: bool) -> None:
        weights = self._ctrl.weights
        if free and weights.position != 0.0:
            self._ctrl.set_weights(position=0.0)
        elif not free and weights.position != self._weights.position:
            self._ctrl.set_weights(position=self._weights.position)

    def _target(self, q_ctrl: np.ndarray) -> Any:
        """The controlled frame's target for `ReactiveController.step` (base frame)."""
        p, o = self._target_position, self._target_orientation
        self._set_position_free(p is None and o is not None)
        if p is None and o is None:
            return self._ctrl.forward_kinematics(self._ctrl.rest_configuration)
        T = self._base_from_world()
        if o is None:
            R_frame = self._ctrl.forward_kinematics(q_ctrl).rotation
            return self._ee.position_target(T.transform_points(p), R_frame)
        R = T.rotation @ quat.to_matrix(o)
        if p is None:
            now = self._ctrl.forward_kinematics(q_ctrl)
            return Pose(now.position, quat.from_matrix(self._ee.rotation_target(R)))
        return self._ee.pose_target(T @ Pose(p, o))

    def compute_joint_targets(self, active_joint_positions, active_joint_velocities, watched_joint_positions,
                              watched_joint_velocities, frame_duration: float) -> tuple[np.ndarray, np.ndarray]:
        """Joint targets for the end of the next frame.

        Args:
            active_joint_positions: (dof,) [rad], `get_active_joints()` order.
            active_joint_velocities: (dof,) [rad/s].
            watched_joint_positions: empty (RmpFlow watches no joints).
            watched_joint_velocities: empty.
            frame_duration: the frame [s] > 0.

        Returns:
            (positions (dof,) [rad], velocities (dof,) [rad/s]) for the active joints.

        Raises:
            InvalidInputError: a wrong shape, a NaN, a watched joint, frame_duration <= 0.
        """
        q = self._joints(active_joint_positions, "active_joint_positions")
        v = self._joints(active_joint_velocities, "active_joint_velocities")
        self._watched(watched_joint_positions, "watched_joint_positions")
        self._watched(watched_joint_velocities, "watched_joint_velocities")
        dt = positive(frame_duration, "frame_duration", "s")
        q, v = self._command.start(q, v)
        q_ctrl = q[self._to_ctrl]
        r = self._ctrl.step(q_ctrl, self._target(q_ctrl), dt, velocity=None if v is None else v[self._to_ctrl])
        self._last = r
        positions, velocities = r.q[self._to_cspace], r.velocities[self._to_cspace]
        self._command.update(positions, velocities)
        return positions, velocities

    # ------------------------------------------------------------------ world
    def update_world(self, updated_obstacles: Iterable[Any] | None = None) -> None:
        """Re-read obstacle poses: all non-static ones (None), or those listed; every obstacle,
        static ones too, when the base moved since the last update.

        Raises:
            UnknownNameError: a listed object was not added.
        """
        if updated_obstacles is not None and not isinstance(updated_obstacles, (list, tuple)):
            raise InvalidInputError(f"updated_obstacles must be a list of added obstacles or None; "
                                    f"got {type(updated_obstacles).__name__}")
        T = self._base_from_world()
        if self._base_moved:
            self._obstacles.sync(T, include_static=True)
        elif updated_obstacles is None:
            self._obstacles.sync(T, include_static=False)
        else:
            self._obstacles.sync(T, objects=updated_obstacles)
        self._base_moved = False

    # ------------------------------------------------------------------ debug drawing (none)
    def _log_once(self, what: str, why: str) -> None:
        if what not in self._said:
            self._said.add(what)
            logger.warning("RmpFlow.%s does nothing in manip: %s", what, why)

    def visualize_collision_spheres(self) -> None:
        self._log_once("visualize_collision_spheres", _NO_SPHERES)

    def stop_visualizing_collision_spheres(self) -> None:
        self._log_once("stop_visualizing_collision_spheres", _NO_SPHERES)

    def delete_collision_sphere_prims(self) -> None:
        self._log_once("delete_collision_sphere_prims", _NO_SPHERES)

    def get_collision_spheres_as_prims(self) -> list:
        """Empty: no collision spheres (logged once)."""
        self._log_once("get_collision_spheres_as_prims", _NO_SPHERES)
        return []

    def visualize_end_effector_position(self) -> None:
        self._log_once("visualize_end_effector_position", _NO_PRIMS)

    def stop_visualizing_end_effector(self) -> None:
        self._log_once("stop_visualizing_end_effector", _NO_PRIMS)

    def delete_end_effector_prim(self) -> None:
        self._log_once("delete_end_effector_prim", _NO_PRIMS)

    def __repr__(self) -> str:
        return (f"RmpFlow(end_effector={self.end_effector_frame_name!r} as {self._ee.frame!r}, "
                f"{len(self._obstacles)} obstacles, {self._ctrl!r})")


declare_not_supported(RmpFlow)

__all__ = ["RmpFlow"]
