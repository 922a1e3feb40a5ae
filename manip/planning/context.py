"""`PlanContext`: the state of one planning call (options, deadline, random generator,
per-stage timings, and the failure once there is one)."""

from __future__ import annotations

import logging
import time

import numpy as np

from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.limits import JointLimits
from manip.planning.options import PlanOptions
from manip.planning.result import PlanResult, PlanStatus
from manip.planning.validity import Validity, describe_contacts
from manip.validation import MAX_SAMPLES

logger = logging.getLogger(__name__)

#: A start this far outside a joint limit [rad] is accepted (and kept as given): simulated
#: joints settle a few microradians past a limit the previous motion ended on.
START_LIMIT_TOLERANCE = 1e-4
#: A joint goal this far outside a joint limit [rad] is moved onto the limit (a goal read
#: from a simulated joint resting on its limit); one further out is INVALID_GOAL.
GOAL_LIMIT_TOLERANCE = START_LIMIT_TOLERANCE
#: Ends the message of a start whose only contacts are an attached object's with the world (a
#: grasped object still on its support): how to lift it.
HELD_HINT = ("; an attached object touches the world at the start (still on its support?): plan the lift with "
             "plan_grasp, whose lift may leave the support, or attach it where it is clear")
#: Ends the message of a result returned after its time budget ran out. Every stage is bounded
#: by counts and stops early only when the budget has run out, so a result without this note
#: does not depend on the machine's speed or load; one with it may (a stage was perhaps cut
#: short by the clock).
SAFETY_NET = ("the time budget ran out during the plan: a stage may have stopped early, so this result may depend on "
              "the machine")


def _one_row(q: np.ndarray, what: str) -> str:
    """The hint for a (1, dof) configuration (cuRobo's `JointState.position` of one state)."""
    return f" (one configuration, as cuRobo's (1, dof) JointState.position: pass {what}[0])" if q.shape[0] == 1 else ""


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
            raise InvalidInputError(f"start_q must have shape ({kinematics.dof},); got {q.shape}{_one_row(q, 'start_q')}")
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
            held = all(c.kind == "attached_world" for c in report.contacts)
            self.fail(status, "start in collision: " + describe_contacts(report) + (HELD_HINT if held else ""))
            return q
        problem = validity.constraint_problem(q)
        if problem:
            self.fail(PlanStatus.INVALID_START_CONSTRAINT, "the start violates a constraint: " + problem)
        return q

    def check_goal(self, goal_q, kinematics: Kinematics, validity: Validity) -> np.ndarray:
        """The validated joint goal (dof,), clipped onto the limits when it lies within
        GOAL_LIMIT_TOLERANCE of them; records INVALID_GOAL (beyond that, or in collision)
        instead of raising.

        Raises:
            InvalidInputError: wrong shape or non-finite values.
        """
        q = kinematics.check_q(goal_q, "goal_q")
        if q.ndim != 1:
            raise InvalidInputError(f"goal_q must have shape ({kinematics.dof},); got {q.shape}{_one_row(q, 'goal_q')}")
        if kinematics.limit_violations(q, GOAL_LIMIT_TOLERANCE):
            problem = validity.goal_problem(q)
        else:
            q = np.clip(q, kinematics.lower, kinematics.upper)
            problem = validity.goal_problem(q)
        if problem and not self.failed:
            constraint = validity.constraint_problem(q)
            if constraint and constraint in problem:
                self.fail(PlanStatus.INVALID_GOAL_CONSTRAINT, "the goal violates a constraint: " + constraint)
            else:
                self.fail(PlanStatus.INVALID_GOAL, problem)
        return q

    def scaled_limits(self, limits: JointLimits) -> JointLimits:
        """The limits of this call: the robot's `limits` times the options' velocity,
        acceleration and jerk scales."""
        o = self.options
        return limits.scaled(o.velocity_scale, o.acceleration_scale, jerk=o.jerk_scale)

    def check_sample_count(self, start: np.ndarray, goal: np.ndarray, limits: JointLimits) -> None:
        """Refuse a call whose trajectory would have more than MAX_SAMPLES samples.

        Any motion from `start` to `goal` at rest lasts at least max over joints of d / v,
        2 sqrt(d / a) and (32 d / j)^(1/3) under the call's scaled limits (ruckig itself
        fails on absurd limits such as velocity_scale=1e-9).

        Raises:
            InvalidInputError: naming dt and the scales that were lowered.
        """
        o = self.options
        if o.duration is not None:
            return  # checked with the options
        d = np.abs(np.asarray(goal, dtype=float) - np.asarray(start, dtype=float))
        lim = self.scaled_limits(limits)
        bound = float(np.max(np.maximum.reduce([d / lim.velocity, 2.0 * np.sqrt(d / lim.acceleration),
                                                np.cbrt(32.0 * d / lim.jerk)])))
        if bound / o.dt + 1 > MAX_SAMPLES:
            scaled = [n for n in ("velocity_scale", "acceleration_scale") if getattr(o, n) < 1.0]
            what = " or ".join(["dt"] + scaled)
            raise InvalidInputError(
                f"{what}: the motion lasts at least {bound:.6g} s; sampled every dt = {o.dt:.6g} s it would have "
                f"more than MAX_SAMPLES = {MAX_SAMPLES} samples (manip.validation.MAX_SAMPLES)"
            )

    def fail(self, status: PlanStatus, message: str, path=None, goal_q=None, attempts: int = 1) -> PlanResult:
        """Record and return a failed PlanResult (its message ends with SAFETY_NET when the
        time budget has run out)."""
        message = self._finish(message)
        logger.info("planning failed: %s (%s)", status.name, message)
        self._failure = PlanResult(
            success=False, status=status, path=path, goal_q=goal_q, timings=dict(self.timings), message=message,
            attempts=attempts,
        )
        return self._failure

    def clear_failure(self) -> None:
        """Forget a recorded failure: a first try failed and the plan goes on another way."""
        self._failure = None

    def succeed(self, trajectory, path, goal_q, attempts: int, source: str) -> PlanResult:
        """A successful PlanResult with the timings so far (its message is SAFETY_NET when the
        time budget has run out, else empty)."""
        message = self._finish("")
        return PlanResult(
            success=True, status=PlanStatus.SUCCESS, trajectory=trajectory, path=path, goal_q=goal_q,
            timings=dict(self.timings), position_error=0.0, rotation_error=0.0, attempts=attempts, source=source,
            message=message,
        )

    def _finish(self, message: str) -> str:
        """Record the total time; `message` with SAFETY_NET added when the deadline has passed
        (then some stage may have seen it: every deadline check is `perf_counter() > deadline`)."""
        now = time.perf_counter()
        self.timings.pop("other", None)
        staged = sum(self.timings.get(k, 0.0) for k in self.timings if k != "total")
        # the stages account for all of "total": what ran outside them (input and start/goal
        # checks, the world snapshot) is "other"
        self.timings["other"] = max(0.0, (now - self.t0) - staged)
        self.timings["total"] = now - self.t0
        if now <= self.deadline:
            return message
        return f"{message}; {SAFETY_NET}" if message else SAFETY_NET
