"""`PlanResult` and `PlanStatus`: what a planning call returns."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from manip.trajectory import Trajectory


class PlanStatus(Enum):
    """Outcome of a planning call; each failure says what to change."""

    SUCCESS = "success"
    #: No collision-free IK solution for the goal pose: move the goal or clear around it.
    IK_FAIL = "ik_fail"
    #: No collision-free path found within the budget: raise `time_budget` or simplify the scene.
    PLAN_FAIL = "plan_fail"
    #: A path was found but no valid timed trajectory could be made from it.
    TRAJOPT_FAIL = "trajopt_fail"
    #: The start is outside the joint limits by more than the tolerance (1e-6 rad).
    INVALID_START_JOINT_LIMITS = "invalid_start_joint_limits"
    #: The start configuration collides with the robot itself.
    INVALID_START_SELF_COLLISION = "invalid_start_self_collision"
    #: The start configuration collides with the world (or an attached object does).
    INVALID_START_WORLD_COLLISION = "invalid_start_world_collision"
    #: The goal configuration is outside the limits or in collision.
    INVALID_GOAL = "invalid_goal"
    #: The time budget ran out before a path was found.
    TIMEOUT = "timeout"
    #: A straight-line (linear) motion is impossible: IK breaks, jumps or collides on the line.
    LINEAR_PATH_FAIL = "linear_path_fail"


@dataclass(frozen=True)
class PlanResult:
    """A planning outcome.

    Attributes:
        success: True when `trajectory` is valid (verified densely against collisions and
            within all limits, at rest at both ends, at the goal).
        status: why it succeeded or failed.
        trajectory: the timed trajectory (None on failure).
        path: (K, dof) collision-free joint-space waypoints the trajectory follows (None if
            planning failed before a path existed).
        goal_q: (dof,) the goal configuration reached (or aimed at).
        timings: seconds per stage ("ik", "plan", "optimize", "timing", "validate", "total").
        position_error: final link position error [m] (pose goals; 0 for joint goals).
        rotation_error: final link rotation error [rad] (pose goals; 0 for joint goals).
        attempts: planning attempts used.
        goal_index: for goal sets, the index of the pose reached.
        message: a human-readable detail of the status.
    """

    success: bool
    status: PlanStatus
    trajectory: Trajectory | None = None
    path: np.ndarray | None = None
    goal_q: np.ndarray | None = None
    timings: dict[str, float] = field(default_factory=dict)
    position_error: float = float("nan")
    rotation_error: float = float("nan")
    attempts: int = 0
    goal_index: int | None = None
    message: str = ""

    @property
    def plan_time(self) -> float:
        """Total planning wall time [s]."""
        return self.timings.get("total", float("nan"))

    @property
    def motion_time(self) -> float:
        """Duration of the trajectory [s] (nan on failure)."""
        return self.trajectory.duration if self.trajectory is not None else float("nan")
