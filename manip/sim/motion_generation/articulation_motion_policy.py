"""`ArticulationMotionPolicy`: a motion policy (`RmpFlow`) driving a simulated robot.

    policy = ArticulationMotionPolicy(franka, rmpflow, default_physics_dt=1 / 60)
    action = policy.get_next_articulation_action()      # or policy.move()
    franka.apply_action(action)

As Isaac's: each call reads the policy's active (and watched) joints from the articulation
by name (`ArticulationSubset`), gives them to `compute_joint_targets` with the frame's
duration, and returns the position and velocity targets as an ArticulationAction for those
joints (`joint_indices` their indices in the articulation; the fingers are left alone).

Differences from Isaac, so that a mistake stops at its line: a policy without Isaac's
MotionPolicy methods, or a bad `physics_dt`, raises InvalidInputError; an articulation used
before the first `world.reset()` raises SimulationError (Isaac logs an error).
"""

from __future__ import annotations

from typing import Any

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.motion_generation.articulation_kinematics_solver import ArticulationSubset
from manip.validation import positive

#: The MotionPolicy methods this wrapper calls.
POLICY_METHODS = ("get_active_joints", "get_watched_joints", "compute_joint_targets")


class ArticulationMotionPolicy:
    """A motion policy applied to a simulated robot.

    Args:
        robot_articulation: the robot (`Articulation`, `Franka`, ...), initialised by
            `world.reset()` before the first action.
        motion_policy: an `RmpFlow` (or any object with `POLICY_METHODS`).
        default_physics_dt: the frame duration [s] used when a call gives none (default 1/60).

    Raises:
        InvalidInputError: not an articulation, a policy lacking a method, a bad dt.
    """

    def __init__(self, robot_articulation: Any, motion_policy: Any, default_physics_dt: float = 1.0 / 60.0):
        missing = [m for m in POLICY_METHODS if not callable(getattr(motion_policy, m, None))]
        if missing:
            raise InvalidInputError(f"motion_policy must be a MotionPolicy (RmpFlow); {type(motion_policy).__name__} "
                                    f"has no {', '.join(missing)}")
        self._default_physics_dt = positive(default_physics_dt, "default_physics_dt", "s")
        self.physics_dt = self._default_physics_dt
        self._robot_articulation = robot_articulation
        self.motion_policy = motion_policy
        self._active_joints_view = ArticulationSubset(robot_articulation, motion_policy.get_active_joints())
        self._watched_joints_view = ArticulationSubset(robot_articulation, motion_policy.get_watched_joints())

    def move(self, physics_dt: float | None = None) -> None:
        """Compute the next action and apply it to the robot (its articulation controller)."""
        self._robot_articulation.apply_action(self.get_next_articulation_action(physics_dt))

    def get_next_articulation_action(self, physics_dt: float | None = None) -> ArticulationAction:
        """The joint targets at the end of the next frame.

        Args:
            physics_dt: this frame's duration [s]; None: the default (not changed by this call).

        Returns:
            ArticulationAction with joint_positions, joint_velocities and joint_indices of the
            policy's active joints.

        Raises:
            SimulationError: before the first `world.reset()`.
        """
        dt = self._default_physics_dt if physics_dt is None else positive(physics_dt, "physics_dt", "s")
        active, watched = self._active_joints_view, self._watched_joints_view
        positions, velocities = self.motion_policy.compute_joint_targets(
            active.get_joint_positions(), active.get_joint_velocities(), watched.get_joint_positions(),
            watched.get_joint_velocities(), dt)
        return active.make_articulation_action(positions, velocities)

    def get_active_joints_subset(self) -> ArticulationSubset:
        return self._active_joints_view

    def get_watched_joints_subset(self) -> ArticulationSubset:
        return self._watched_joints_view

    def get_robot_articulation(self) -> Any:
        return self._robot_articulation

    def get_motion_policy(self) -> Any:
        return self.motion_policy

    def get_default_physics_dt(self) -> float:
        return self._default_physics_dt

    def set_default_physics_dt(self, physics_dt: float) -> None:
        """The frame duration [s] used when a call gives none."""
        self._default_physics_dt = positive(physics_dt, "physics_dt", "s")


__all__ = ["ArticulationMotionPolicy"]
