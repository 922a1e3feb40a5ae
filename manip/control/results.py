"""What one control step returns: `StepResult` and its `StepStatus`."""

from __future__ import annotations

import enum
from dataclasses import dataclass

import numpy as np


class StepStatus(enum.Enum):
    """How a control step ended."""

    #: The QP was solved: `q` follows the tasks as far as the limits allow.
    SOLVED = "solved"
    #: The QP had no solution (conflicting limits, e.g. a configuration already outside its
    #: joint limits by more than one step can fix) or the solver failed: the arm holds
    #: (`q` equals the input, zero velocity).
    HELD = "held"


@dataclass(frozen=True, eq=False)
class StepResult:
    """One `ReactiveController.step`.

    Attributes:
        q: (dof,) the next configuration [rad], `q_in + velocities * dt`, within the joint
            limits.
        velocities: (dof,) joint velocities over the step [rad/s], within the velocity limits.
        status: SOLVED or HELD.
        position_error: distance from the controlled frame to the target at the input
            configuration [m] (before the step).
        orientation_error: angle between the frame's and the target's orientations at the
            input configuration [rad] (0 for a position-only target).
        obstacle_clearance: smallest distance [m] between the robot and an obstacle at the
            input configuration among the pairs closer than the detection distance (inf if
            none is that close; negative if penetrating).
        self_clearance: the same for the checked self-collision pairs.
        active_collision_rows: number of collision constraints in this step's QP.
        solve_time: wall time of the whole step (kinematics, QP assembly and solve) [s].
    """

    q: np.ndarray
    velocities: np.ndarray
    status: StepStatus
    position_error: float
    orientation_error: float
    obstacle_clearance: float
    self_clearance: float
    active_collision_rows: int
    solve_time: float

    @property
    def solved(self) -> bool:
        """True unless the arm was held because the QP failed."""
        return self.status is StepStatus.SOLVED

    def __repr__(self) -> str:
        return (
            f"StepResult({self.status.name}, position_error={self.position_error:.4f} m, "
            f"orientation_error={self.orientation_error:.4f} rad, obstacle_clearance={self.obstacle_clearance:.4f} m, "
            f"solve_time={self.solve_time * 1e3:.3f} ms)"
        )
