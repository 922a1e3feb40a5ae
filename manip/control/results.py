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
    #: The QP was solved and the step applied, but the frame has not approached the still
    #: target for the controller's `stall_time`: a local minimum (the arm against its own
    #: margins or an obstacle, or the target out of reach). Stepping on does not help; plan
    #: a motion (`manip.MotionGenerator`) or move the target.
    STALLED = "stalled"


@dataclass(frozen=True, eq=False)
class StepResult:
    """One `ReactiveController.step`.

    Attributes:
        q: (dof,) the next configuration [rad], `q_in + velocities * dt`, within the joint
            limits.
        velocities: (dof,) joint velocities over the step [rad/s], within the velocity limits.
        status: SOLVED, STALLED (solved, but no progress towards a still target) or HELD.
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
        """True unless the arm was held because the QP failed (SOLVED or STALLED)."""
        return self.status is not StepStatus.HELD

    @property
    def stalled(self) -> bool:
        """True if the frame no longer approaches the still target (`StepStatus.STALLED`)."""
        return self.status is StepStatus.STALLED

    def __repr__(self) -> str:
        return (
            f"StepResult({self.status.name}, position_error={self.position_error:.4f} m, "
            f"orientation_error={self.orientation_error:.4f} rad, obstacle_clearance={self.obstacle_clearance:.4f} m, "
            f"solve_time={self.solve_time * 1e3:.3f} ms)"
        )
