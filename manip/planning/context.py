"""`PlanContext`: the state of one planning call (options, deadline, random generator,
per-stage timings, and the failure once there is one)."""

from __future__ import annotations

import logging
import time

import numpy as np

from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.planning.options import PlanOptions
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity, describe_contacts

logger = logging.getLogger(__name__)

#: A start this far outside a joint limit [rad] is accepted (and kept as given): simulated
#: joints settle a few microradians past a limit the previous motion ended on.
START_LIMIT_TOLERANCE = 1e-4


class PlanContext:
    """Per-call planning state.

    Args:
        options: the call's validated options.
        t0: `time.perf_counter()` at the start of the call [s].
    """

    def __init__(self, options: PlanOptions, t0: float | None = None):
        self.options = options
        self.t0 = time.perf_counter() if t0 is None else t0
        self.deadline = self.t0 + options.time_budget
        self.rng = np.random.default_rng(options.seed)
        self.timings: dict[str, float] = {}
        self._failure: PlanResult | None = None

    @property
    def failed(self) -> bool:
        """True once `fail` was called."""
        return self._failure is not None

    @property
    def time_left(self) -> float:
        """Seconds left of the budget."""
        return self.deadline - time.perf_counter()

    def result(self) -> PlanResult:
        """The recorded failure."""
        assert self._failure is not None
        return self._failure

    def add_time(self, stage: str, since: float) -> None:
        """Add the time since `since` (a perf_counter value) to `stage`."""
        self.timings[stage] = self.timings.get(stage, 0.0) + time.perf_counter() - since

    def check_start(self, start_q, kinematics: Kinematics, validity: Validity) -> np.ndarray:
        """The validated start (dof,); records an INVALID_START_* failure instead of raising.

        Raises:
            InvalidInputError: wrong shape or non-finite values.
        """
        q = kinematics.check_q(start_q, "start_q")
        if q.ndim != 1:
            raise InvalidInputError(f"start_q must have shape ({kinematics.dof},); got {q.shape}")
        bad = kinematics.limit_violations(q, START_LIMIT_TOLERANCE)
        if bad:
            self.fail(PlanStatus.INVALID_START_JOINT_LIMITS, "start outside the joint limits: " + "; ".join(bad))
            return q
        if validity.checker.in_collision(q):
            report = validity.checker.collision_report(q)
            status = (
                PlanStatus.INVALID_START_WORLD_COLLISION if report.world_collision
                else PlanStatus.INVALID_START_SELF_COLLISION
            )
            self.fail(status, "start in collision: " + describe_contacts(report))
        return q

    def fail(self, status: PlanStatus, message: str, path=None, goal_q=None, attempts: int = 1) -> PlanResult:
        """Record and return a failed PlanResult."""
        self.timings["total"] = time.perf_counter() - self.t0
        logger.info("planning failed: %s (%s)", status.name, message)
        self._failure = PlanResult(
            success=False, status=status, path=path, goal_q=goal_q, timings=dict(self.timings), message=message,
            attempts=attempts,
        )
        return self._failure

    def succeed(self, trajectory, path, goal_q, attempts: int, source: str) -> PlanResult:
        """A successful PlanResult with the timings so far."""
        self.timings["total"] = time.perf_counter() - self.t0
        return PlanResult(
            success=True, status=PlanStatus.SUCCESS, trajectory=trajectory, path=path, goal_q=goal_q,
            timings=dict(self.timings), position_error=0.0, rotation_error=0.0, attempts=attempts, source=source,
        )
