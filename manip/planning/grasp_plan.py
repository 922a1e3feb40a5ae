"""`GraspPlan`: what `MotionGenerator.plan_grasp` / `plan_place` return, and joining stages into one trajectory."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from manip.planning.result import PlanResult, PlanStatus
from manip.trajectory import Trajectory
from manip.status import truth_is_success


@dataclass(frozen=True)
class GraspPlan:
    """A task-level motion: several planned stages executed in order, at rest between them.

    Attributes:
        success: True when every stage succeeded (each stage's trajectory is certified like
            any plan's, with the contacts the stage allows, see `planning.grasp`).
        status: SUCCESS, or the status of the stage that failed for the candidate that got
            furthest (`message` says which stage of which candidates failed, and why).
        message: the failures per candidate and stage (on success, of the candidates skipped
            before the one chosen; "" when it was the first).
        grasp_index: the index of the candidate (grasp or placement pose) used (None on failure).
        segments: the `PlanResult` of each stage, in order (plan_grasp: "free", "approach",
            "lift"; plan_place: "free", "descend", "retreat"; `stages` names them).
        stages: the stage names of `segments`.
        trajectory: all stages as one trajectory (None on failure).
        timings: seconds spent per stage name, and "total".
    """

    __bool__ = truth_is_success   # `if result:` tests `.success` (not the object)

    success: bool
    status: PlanStatus
    message: str = ""
    grasp_index: int | None = None
    segments: tuple[PlanResult, ...] = ()
    stages: tuple[str, ...] = ()
    trajectory: Trajectory | None = None
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def motion_time(self) -> float:
        """Duration [s] of the whole trajectory (nan on failure)."""
        return self.trajectory.duration if self.trajectory is not None else float("nan")

    def segment(self, stage: str) -> PlanResult:
        """The PlanResult of the stage named `stage` (KeyError lists the stages)."""
        if stage not in self.stages:
            raise KeyError(f"stage '{stage}' not in this plan; stages: {list(self.stages)}")
        return self.segments[self.stages.index(stage)]


def join(trajectories: Sequence[Trajectory]) -> Trajectory:
    """The trajectories (each starting where the previous ends, at rest) as one, on one grid of dt.

    A trajectory whose last step is shorter than dt rests at its end until the next multiple
    of dt, where the next one starts (those samples are exact: the robot is at rest there).
    """
    dt = trajectories[0].dt
    arrays: list[list[np.ndarray]] = [[], [], [], []]
    whole_before = False
    for k, tr in enumerate(trajectories):
        steps = tr.times[-1] / dt
        whole = abs(steps - round(steps)) <= 1e-9 * max(1.0, steps)
        last = k == len(trajectories) - 1
        keep = slice(1 if (k > 0 and whole_before) else 0, tr.num_samples if (last or whole) else tr.num_samples - 1)
        for out, a in zip(arrays, (tr.positions, tr.velocities, tr.accelerations, tr.jerks)):
            out.append(a[keep])
        whole_before = whole
    P, V, A, J = (np.concatenate(a) for a in arrays)
    times = np.arange(P.shape[0]) * dt
    tail = trajectories[-1]
    if tail.num_samples > 1 and P.shape[0] > 1:
        times[-1] = times[-2] + (tail.times[-1] - tail.times[-2])
    return Trajectory(times=times, positions=P, velocities=V, accelerations=A, jerks=J, dt=dt,
                      joint_names=trajectories[0].joint_names)


def failure_message(failures: list[tuple[int, str, PlanStatus, str]], candidates: int, what: str) -> str:
    """One line per failed candidate: "candidate 3: approach: LINEAR_PATH_FAIL: ...", at most 8."""
    if not failures:
        return f"no {what} candidate was tried"
    lines = [f"candidate {i}: {stage}: {status.name}: {why}" for i, stage, status, why in failures[:8]]
    more = len(failures) - 8
    head = f"none of the {candidates} {what} candidates has a feasible sequence"
    return head + "; " + "; ".join(lines) + (f"; and {more} more" if more > 0 else "")
