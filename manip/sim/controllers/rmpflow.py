"""`RMPFlowController`: Isaac Sim's name for a reactive end-effector controller.

It is NOT RMPflow. Isaac's `RMPFlowController` runs Lula's RMPflow (Riemannian motion
policies: acceleration fields blended by their metrics). This one is manip's
`manip.control.ReactiveController`: differential inverse kinematics as one quadratic
program per physics step (mink tasks; joint position, velocity and collision limits),
under Isaac's class name and interface so that Isaac's follow-target example runs with its
imports changed:

    controller = RMPFlowController(name="target_follower_controller", robot_articulation=franka)
    action = controller.forward(target_end_effector_position=p, target_end_effector_orientation=q)
    franka.get_articulation_controller().apply_action(action)

What to expect instead of RMPflow's behaviour: the end effector converges to a reachable
target within a step or two of its motion (dead-beat tracking, limited by the joint
velocity limits) rather than along RMPflow's smooth attractor; obstacles are hard
constraints (the arm keeps `safety_margin` from them, and stops there when the target is
behind one) rather than repulsive fields; joint accelerations are bounded by the robot
configuration's acceleration limits, and a target that jumps is approached at
`max_speed` (1 m/s) rather than along RMPflow's damped attractor.

Targets are world poses of the robot configuration's tool centre point (the Franka's
`panda_hand_tcp`, where Isaac's RMPflow places "right_gripper"), whatever the articulation's
`end_effector` is, as in Isaac (a `frame=` keyword chooses another). The controller
integrates its own joint command from step to step (as Isaac's RMPflow does) and starts
again from the measured joints after `reset()` or when the robot is more than
`resync_tolerance` away from the command (blocked, or moved by hand):
`manip.sim.motion_generation.joint_command`, shared with `RmpFlow`.
"""

from __future__ import annotations

import logging
from typing import Any

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.control import ReactiveController, StepResult
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.robot_config import RobotConfig, load_robot_config
from manip.sim.controllers.base_controller import BaseController
from manip.sim.controllers.controller_policy import ControllerMotionPolicy
from manip.sim.motion_generation.joint_command import JointCommand
from manip.sim.motion_generation.sim_obstacles import TrackedObstacles, label, obstacle_from_prim
from manip.sim.scenes.stage import SimulationError
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.validation import positive, unit_quat, vec

logger = logging.getLogger(__name__)


class RMPFlowController(BaseController):
    """Follow an end-effector target while avoiding obstacles (Isaac's `RMPFlowController`
    interface; a QP controller, not RMPflow: see the module docstring).

    Args:
        name: controller name.
        robot_articulation: the robot (a `manip.sim.Franka`, after `world.reset()`).
        physics_dt: the period of `forward` calls [s] (default 1/60, Isaac's).
        robot: robot configuration name or `RobotConfig` (default "franka").
        resync_tolerance: largest gap [rad] between the command and the measured joints
            before the command restarts from the measurement (default 0.1).
        safety_margin: distance [m] kept from obstacles and between the robot's links
            (default 0.02: the simulated drives lag the command by up to about 1 cm when the
            arm stops at an obstacle). Links closer than twice this at the robot's default
            joint positions keep half their distance there (`ReactiveController.self_margins`).
        **controller_options: other keywords of `manip.control.ReactiveController`
            (`frame`, `solver`, `weights`, `velocity_scale`, `max_speed`, ...).

    Raises:
        InvalidInputError: bad arguments (named in the message).
    """

    def __init__(self, name: str, robot_articulation: Any, physics_dt: float = 1.0 / 60.0, *,
                 robot: str | RobotConfig = "franka", resync_tolerance: float = 0.1, safety_margin: float = 0.02,
                 **controller_options: Any):
        super().__init__(name)
        self._robot = robot_articulation
        self._dt = positive(physics_dt, "physics_dt", "s")
        self._command = JointCommand(resync_tolerance)
        config = robot if isinstance(robot, RobotConfig) else load_robot_config(robot)
        controller_options["safety_margin"] = safety_margin
        self._ctrl = ReactiveController(config, **controller_options)  # frame: the configuration's TCP
        self._obstacles = TrackedObstacles(self._ctrl)
        self._policy = ControllerMotionPolicy(self._ctrl, self._obstacles, self._base_from_world, self._forget_command)
        self._arm_idx: np.ndarray | None = None
        self._last: StepResult | None = None

    # ------------------------------------------------------------------ accessors
    @property
    def controller(self) -> ReactiveController:
        """The underlying `manip.control.ReactiveController`."""
        return self._ctrl

    @property
    def last_result(self) -> StepResult | None:
        """The `StepResult` of the last `forward` call (errors, clearance, timing)."""
        return self._last

    @property
    def physics_dt(self) -> float:
        return self._dt

    def get_motion_policy(self) -> ControllerMotionPolicy:
        """RmpFlow's world interface on this controller (`add_obstacle`, `add_cuboid`, ...,
        `update_world`, `set_robot_base_pose`, `reset`; `manip.sim.controllers.controller_policy`
        says what differs from an RmpFlow)."""
        return self._policy

    def get_default_physics_dt(self) -> float:
        return self._dt

    def set_default_physics_dt(self, physics_dt: float) -> None:
        self._dt = positive(physics_dt, "physics_dt", "s")

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """Forget the obstacles and the joint command (the next `forward` starts from the
        measured joints), as Isaac's (its RmpFlow's reset empties its world; `World.reset()`
        removes FollowTarget's obstacles): add obstacles again after a reset."""
        self._policy.reset()

    def _forget_command(self) -> None:
        self._command.reset()
        self._last = None
        self._ctrl.reset()

    def _bind(self) -> np.ndarray:
        names = getattr(self._robot, "dof_names", None)
        if names is None:
            raise SimulationError(f"{self.name}: the robot is not simulated yet; call world.reset() before forward()")
        if self._arm_idx is None:
            self._arm_idx = np.array([self._robot.get_dof_index(j) for j in self._ctrl.joint_names], dtype=int)
        return self._arm_idx

    def _base_from_world(self) -> Pose:
        pose = self._robot.get_world_pose()
        if pose is None:
            raise SimulationError(f"{self.name}: the robot has no pose yet; call world.reset() before forward()")
        return Pose(np.asarray(pose[0], dtype=float), np.asarray(pose[1], dtype=float)).inverse()

    # ------------------------------------------------------------------ obstacles
    def add_obstacle(self, obstacle: Any, static: bool = False) -> None:
        """Avoid `obstacle` (a manip.sim shape object) from now on; its pose is read at
        every `forward` (`static` is accepted for Isaac's signature; poses are always read).
        An obstacle added again is kept once, with a warning (as Isaac's Lula world does).

        Raises:
            InvalidInputError: not a shape object.
        """
        if obstacle in self._obstacles:
            logger.warning("RMPFlowController.add_obstacle: %r was already added; it is kept once", label(obstacle))
            return
        self._obstacles.add(obstacle, self._base_from_world(), static=static)

    def remove_obstacle(self, obstacle: Any) -> None:
        """Stop avoiding `obstacle`.

        Raises:
            InvalidInputError: it was not added.
        """
        if obstacle not in self._obstacles:
            raise InvalidInputError(f"remove_obstacle: {label(obstacle)!r} was not added")
        self._obstacles.remove(obstacle)

    # ------------------------------------------------------------------ control
    def forward(self, target_end_effector_position, target_end_effector_orientation=None) -> ArticulationAction:
        """The arm's joint targets for the next physics step.

        Args:
            target_end_effector_position: (3,) world position [m] of the end effector.
            target_end_effector_orientation: (4,) world orientation (w, x, y, z), or None
                for any orientation (position only).

        Returns:
            ArticulationAction with joint_positions and joint_velocities for the arm
            joints (joint_indices set; the fingers are left alone).

        Raises:
            InvalidInputError: a NaN or a wrong shape (named in the message).
            SimulationError: before `world.reset()`.
        """
        position = vec(target_end_effector_position, 3, "target_end_effector_position")
        orientation = None
        if target_end_effector_orientation is not None:
            orientation = unit_quat(target_end_effector_orientation, "target_end_effector_orientation")
        idx = self._bind()
        base_T_world = self._base_from_world()
        self._obstacles.sync(base_T_world)
        q_start, velocity = self._command.start(np.asarray(self._robot.get_joint_positions(), dtype=float)[idx],
                                                np.asarray(self._robot.get_joint_velocities(), dtype=float)[idx])
        if orientation is None:
            target: Any = (base_T_world @ Pose(position)).position
        else:
            target = base_T_world @ Pose(position, orientation)
        r = self._ctrl.step(q_start, target, self._dt, velocity=velocity)
        self._last = r
        self._command.update(r.q, r.velocities)
        return ArticulationAction(joint_positions=r.q.copy(), joint_velocities=r.velocities.copy(), joint_indices=idx)


declare_not_supported(RMPFlowController)

__all__ = ["RMPFlowController", "obstacle_from_prim"]
