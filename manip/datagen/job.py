"""What a dataset worker runs on a problem: plan it, then check the trajectory independently."""

from __future__ import annotations

from dataclasses import dataclass

from manip.batch import worker
from manip.batch.problem import ProblemId, Task
from manip.benchmarking.verify import default_verifier
from manip.planning.result import PlanResult


@dataclass(frozen=True)
class Verdict:
    """The independent verifier's verdict on a planned trajectory.

    Attributes:
        verified: the trajectory passed `manip.benchmarking.verify` (collision with exact
            meshes, limits, endpoints); False when there is no trajectory.
        reasons: why not (empty when verified or when there is no trajectory).
    """

    verified: bool
    reasons: tuple[str, ...] = ()


def plan_and_verify(task: Task) -> tuple[ProblemId, tuple[PlanResult, Verdict]]:
    """Plan `task` on the worker's warm generator and verify the trajectory it returns.

    Args:
        task: a joint-goal task whose world is a cuRobo-style dict.

    Returns:
        (id, (the PlanResult, the Verdict)).
    """
    pid, result = worker.solve(task)
    traj = result.trajectory
    if traj is None:
        return pid, (result, Verdict(False))
    v = default_verifier().verify_trajectory(task.world, traj.times, traj.positions, traj.velocities,
                                             traj.accelerations, start_q=task.start, goal_q=task.goal)
    return pid, (result, Verdict(bool(v.valid), tuple(v.reasons)))
