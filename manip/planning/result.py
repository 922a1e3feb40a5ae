"""`PlanResult` and `PlanStatus`: what a planning call returns."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from manip import curobo_names
from manip.host_array import HostArray, host
from manip.status import Status, truth_is_success
from manip.trajectory import Trajectory


class PlanStatus(Status):
    """Outcome of a planning call; `hint` says what it means and what to change."""

    SUCCESS = "success"
    IK_FAIL = "ik_fail"
    PLAN_FAIL = "plan_fail"
    TRAJOPT_FAIL = "trajopt_fail"
    INVALID_START_JOINT_LIMITS = "invalid_start_joint_limits"
    INVALID_START_SELF_COLLISION = "invalid_start_self_collision"
    INVALID_START_WORLD_COLLISION = "invalid_start_world_collision"
    INVALID_GOAL = "invalid_goal"
    TIMEOUT = "timeout"
    LINEAR_PATH_FAIL = "linear_path_fail"
    INVALID_START_CONSTRAINT = "invalid_start_constraint"
    INVALID_GOAL_CONSTRAINT = "invalid_goal_constraint"
    CONSTRAINT_INFEASIBLE = "constraint_infeasible"
    RAISED = "raised"

    @classmethod
    def _hints(cls) -> dict:
        return _HINTS


_HINTS = {
    PlanStatus.SUCCESS: "a valid trajectory was found",
    PlanStatus.IK_FAIL: "no collision-free IK solution for the goal pose: move the goal or clear around it",
    PlanStatus.PLAN_FAIL: "no collision-free path found within the budget: raise time_budget or simplify the scene",
    PlanStatus.TRAJOPT_FAIL: (
        "a path was found but no valid timed trajectory could be made from it (or the requested duration is "
        "shorter than feasible): raise duration or time_budget"
    ),
    PlanStatus.INVALID_START_JOINT_LIMITS: "the start is outside the joint limits by more than 1e-4 rad",
    PlanStatus.INVALID_START_SELF_COLLISION: "the start configuration collides with the robot itself",
    PlanStatus.INVALID_START_WORLD_COLLISION: "the start collides with the world (or an attached object does)",
    PlanStatus.INVALID_GOAL: "the goal configuration is outside the limits or in collision",
    PlanStatus.TIMEOUT: "the time budget ran out before a path was found: raise time_budget",
    PlanStatus.LINEAR_PATH_FAIL: (
        "a straight-line (linear) motion is impossible: IK breaks, jumps or collides on the line"
    ),
    PlanStatus.INVALID_START_CONSTRAINT: (
        "the start violates a constraint of the `constraints` option (the message says by how much): start inside "
        "every constraint, or loosen it"
    ),
    PlanStatus.INVALID_GOAL_CONSTRAINT: (
        "the goal (or every collision-free IK solution of the goal poses) violates a constraint of the `constraints` "
        "option (the message says by how much): move the goal or loosen the constraint"
    ),
    PlanStatus.CONSTRAINT_INFEASIBLE: (
        "a collision-free path exists without the constraints, but none was found that keeps them: loosen the "
        "constraints (a larger tolerance or box), raise time_budget / search_iterations, or clear the way"
    ),
    PlanStatus.RAISED: (
        "planning this problem of a batch raised an exception (its type and text are in the message): an option "
        "valid on its own that fails once planned (e.g. a dt giving too many samples), or a bug to report"
    ),
}

#: Which optimisation produced a returned trajectory (`PlanResult.source`).
SOURCES = ("straight_line", "shortcut", "trajopt", "linear")


@dataclass(frozen=True)
class PlanResult:
    """A planning outcome.

    Attributes:
        success: True when `trajectory` is valid (certified collision-free over its continuous
            motion, within all limits, at rest at both ends, at the goal). A (1,) bool `HostArray`,
            the shape of cuRobo's `MotionGenResult.success` for one plan: `if result.success:`,
            `bool()`, `result.success[0]`, `.item()` (a Python bool), `.cpu()`, `.numpy()`,
            `.tolist()` (`[True]`) as on cuRobo's tensor (`manip.host_array`).
        status: why it succeeded or failed (`status.hint` says what to change).
        trajectory: the timed trajectory (None on failure).
        path: (K, dof) collision-free joint-space waypoints the trajectory follows (None if
            planning failed before a path existed).
        goal_q: (dof,) the goal configuration reached (or aimed at).
        timings: seconds per stage ("ik", "plan", "optimize" (shortcutting), "restarts"
            (more searches after a detour), "trajopt", "timing", "validate", "other" (input and
            start/goal checks: everything outside the named stages) and "total", their sum).
        position_error: final link position error [m] (pose goals; 0 for joint goals), (1,) as
            cuRobo's: `.item()`, `float()` and `f"{...:.4f}"` read the number.
        rotation_error: final link rotation error [rad] (pose goals; 0 for joint goals), (1,).
        attempts: planning attempts used.
        goal_index: for goal sets, the index of the pose reached.
        message: a human-readable detail of the status.
        source: which stage made the returned trajectory: "straight_line" (the joint-space
            line), "shortcut" (search + shortcutting + ruckig timing), "trajopt" (the
            trajectory optimiser) or "linear" (a Cartesian line); "" on failure.
    """

    __bool__ = truth_is_success   # `if result:` tests `.success` (not the object)

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
    source: str = ""

    def __post_init__(self):
        # cuRobo's results hold tensors: `result.success.item()`, `.cpu().numpy()`, `.tolist()` and
        # `result.position_error.item()` run as written (`manip.host_array`)
        object.__setattr__(self, "success", host(bool(self.success), shape=(1,)))
        object.__setattr__(self, "position_error", host(float(self.position_error), np.float64, (1,)))
        object.__setattr__(self, "rotation_error", host(float(self.rotation_error), np.float64, (1,)))

    @property
    def plan_time(self) -> float:
        """Total planning wall time [s]."""
        return self.timings.get("total", float("nan"))

    @property
    def goalset_index(self) -> HostArray | None:
        """cuRobo's name of `goal_index`: (1,) int64 (`.item()` reads it) for pose goals and goal
        sets, None for joint goals (cuRobo's default)."""
        return None if self.goal_index is None else host(int(self.goal_index), np.int64, (1,))

    @property
    def motion_time(self) -> float:
        """Duration of the trajectory [s] (nan on failure)."""
        return self.trajectory.duration if self.trajectory is not None else float("nan")

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's (get_interpolated_plan, ...) say where manip has them
        if name.startswith("__"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.RESULT, name)


class PlanResults(list):
    """What `plan_batch` returns: the N `PlanResult`s in order (a list: `results[i]`, `len`,
    iteration), also read as cuRobo's batched `MotionGenResult`: `success` (N,) bool and
    `position_error` / `rotation_error` (N,) `HostArray`s (`.cpu().numpy()`, `.all()`,
    `.tolist()`), `status` (N statuses); `get_paths()` the N trajectories (None where failed)."""

    @property
    def success(self) -> HostArray:
        return host(np.array([bool(r.success) for r in self], dtype=bool).reshape(len(self)))

    @property
    def position_error(self) -> HostArray:
        return host(np.array([float(r.position_error) for r in self], dtype=float).reshape(len(self)))

    @property
    def rotation_error(self) -> HostArray:
        return host(np.array([float(r.rotation_error) for r in self], dtype=float).reshape(len(self)))

    @property
    def status(self) -> list[PlanStatus]:
        return [r.status for r in self]

    def get_paths(self) -> list[Trajectory | None]:
        """cuRobo's per-problem trajectories: each result's `trajectory` (None where it failed)."""
        return [r.trajectory for r in self]

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's result names say where manip has them (on each result)
        if name.startswith("__"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.RESULT, name)
