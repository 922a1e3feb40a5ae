"""Controllers with Isaac Sim's interfaces: `BaseController`, `DifferentialController`,
`WheelBasePoseController`, and `BaseGripperController`-style helpers."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.utils.rotations import quat_to_euler_angles
from manip.validation import positive


class BaseController(ABC):
    """A controller turns observations into an `ArticulationAction` (Isaac's `BaseController`).

    Subclasses implement `forward(...)`; `reset()` clears internal state.
    """

    def __init__(self, name: str):
        self._name = name

    @property
    def name(self) -> str:
        return self._name

    @abstractmethod
    def forward(self, *args, **kwargs) -> ArticulationAction:
        """Compute the action."""

    def reset(self) -> None:
        """Clear internal state (nothing by default)."""


def _nonneg(value: float, what: str) -> float:
    """A speed limit: >= 0, inf allowed (no limit), unlike `manip.validation.non_negative`."""
    v = float(value)
    if math.isnan(v) or v < 0:
        raise InvalidInputError(f"{what} must be >= 0; got {value!r}")
    return v


class DifferentialController(BaseController):
    """Unicycle command [v, w] to the wheel velocities of a differential drive.

    left = (2 v - w b) / (2 r), right = (2 v + w b) / (2 r), where r is the wheel radius and
    b the wheel base; v is first clipped to +-max_linear_speed, w to +-max_angular_speed,
    and each wheel velocity to +-max_wheel_speed.

    Args:
        name: controller name.
        wheel_radius: r [m].
        wheel_base: b, distance between the wheel centres [m].
        max_linear_speed: [m/s]. max_angular_speed: [rad/s]. max_wheel_speed: [rad/s].
    """

    def __init__(self, name: str, wheel_radius: float, wheel_base: float, max_linear_speed: float = 1.0e20,
                 max_angular_speed: float = 1.0e20, max_wheel_speed: float = 1.0e20):
        super().__init__(name)
        self.wheel_radius = positive(wheel_radius, "wheel_radius", "m")
        self.wheel_base = positive(wheel_base, "wheel_base", "m")
        self.max_linear_speed = _nonneg(max_linear_speed, "max_linear_speed")
        self.max_angular_speed = _nonneg(max_angular_speed, "max_angular_speed")
        self.max_wheel_speed = _nonneg(max_wheel_speed, "max_wheel_speed")

    def forward(self, command) -> ArticulationAction:
        """Args: command: [v (m/s), w (rad/s)]. Returns joint_velocities [left, right] [rad/s]."""
        c = np.asarray(command, dtype=float)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise InvalidInputError(f"command must be 2 finite numbers [linear m/s, angular rad/s]; got {command!r}")
        v = float(np.clip(c[0], -self.max_linear_speed, self.max_linear_speed))
        w = float(np.clip(c[1], -self.max_angular_speed, self.max_angular_speed))
        r, b = self.wheel_radius, self.wheel_base
        wheels = np.array([(2 * v - w * b) / (2 * r), (2 * v + w * b) / (2 * r)])
        wheels = np.clip(wheels, -self.max_wheel_speed, self.max_wheel_speed)
        return ArticulationAction(joint_velocities=wheels)


class HolonomicController(BaseController):
    """Not provided: manip ships no holonomic base (kept so that imports fail clearly)."""

    def __init__(self, *args, **kwargs):
        raise NotImplementedError("HolonomicController is not implemented in manip.sim (no holonomic robot)")

    def forward(self, *args, **kwargs):  # pragma: no cover
        raise NotImplementedError


def wrap_angle(a: float) -> float:
    """Angle wrapped to [-pi, pi) [rad]."""
    return (a + math.pi) % (2 * math.pi) - math.pi


class WheelBasePoseController(BaseController):
    """Drive a differential base to a goal position: turn in place, then go straight.

    Each call: if the planar distance to the goal is below `position_tol`, stop; else if
    the heading error (angle to the goal minus the yaw, wrapped to [-pi, pi)) exceeds
    `heading_tol`, turn in place at +-yaw_velocity toward the goal; else drive forward at
    `lateral_velocity`. (Isaac compares the mean absolute coordinate error with
    position_tol and does not wrap the heading error; here the Euclidean distance and the
    wrapped error are used.)

    Args:
        name: controller name.
        open_loop_wheel_controller: turns [v, w] into wheel actions (a DifferentialController).
        is_holonomic: must be False (holonomic bases are not provided).
    """

    def __init__(self, name: str, open_loop_wheel_controller: BaseController, is_holonomic: bool = False):
        super().__init__(name)
        if is_holonomic:
            raise InvalidInputError("is_holonomic=True is not supported (no holonomic controller in manip.sim)")
        self.open_loop_wheel_controller = open_loop_wheel_controller

    def forward(self, start_position, start_orientation, goal_position, lateral_velocity: float = 0.2,
                yaw_velocity: float = 0.5, heading_tol: float = 0.05, position_tol: float = 0.04) -> ArticulationAction:
        """Args: start_position (3,) [m], start_orientation (4,) (w, x, y, z), goal_position
        (2,) or (3,) [m]; velocities [m/s], [rad/s]; tolerances [rad], [m]."""
        p = np.asarray(start_position, dtype=float).ravel()
        g = np.asarray(goal_position, dtype=float).ravel()
        if p.size < 2 or g.size < 2 or not (np.all(np.isfinite(p)) and np.all(np.isfinite(g))):
            raise InvalidInputError("start_position and goal_position need finite x, y")
        dx, dy = g[0] - p[0], g[1] - p[1]
        if math.hypot(dx, dy) < position_tol:
            command = [0.0, 0.0]
        else:
            yaw = quat_to_euler_angles(start_orientation)[2]
            err = wrap_angle(math.atan2(dy, dx) - yaw)
            if abs(err) > heading_tol:
                command = [0.0, math.copysign(yaw_velocity, err)]
            else:
                command = [lateral_velocity, 0.0]
        return self.open_loop_wheel_controller.forward(command)

    def reset(self) -> None:
        self.open_loop_wheel_controller.reset()
