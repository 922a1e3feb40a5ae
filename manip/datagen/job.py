"""What a dataset worker runs: build one scene's problems, plan them, verify the trajectories.

A `SceneTask` names a scene and the pairs of it still to plan; the worker makes the scene
(`problems.make_scene`, constant time), plans every pair on its warm generator (the world
is loaded once for the scene) and checks each returned trajectory with the independent
verifier (`manip.benchmarking.verify`). A pair whose planning raises is a failed result
(status RAISED, `manip.batch.worker.solve`), written as a failed row like any other.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

from manip.batch import worker
from manip.batch.problem import Task, problem_seed
from manip.benchmarking.verify import Verifier, default_verifier
from manip.datagen.problems import DataProblem, make_scene
from manip.planning.result import PlanResult

log = logging.getLogger(__name__)


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


@dataclass(frozen=True)
class SceneTask:
    """The pairs of one scene to plan (what a dataset worker receives).

    Attributes:
        id: the scene id, "<kind>-<scene:06d>".
        robot: robot name.
        kind: scene kind.
        scene: index of the scene among those of its kind.
        pairs: the pairs to plan.
        seed: dataset seed (scenes, pairs and planning seeds derive from it).
        options: planning options (validated by the caller; no `seed`).
    """

    id: str
    robot: str
    kind: str
    scene: int
    pairs: tuple[int, ...]
    seed: int
    options: dict[str, Any]


#: One planned problem: the problem, its planning seed, the result and the verdict.
Planned = tuple[DataProblem, int, PlanResult, Verdict]

# Per-process verifiers of the robots met (the Franka's is `default_verifier()`).
_VERIFIERS: dict[str, Verifier] = {}


def verifier(robot: str) -> Verifier:
    """This process's exact-mesh verifier of `robot` (built on first use)."""
    if robot == "franka":
        return default_verifier()
    if robot not in _VERIFIERS:
        _VERIFIERS[robot] = Verifier(robot)
    return _VERIFIERS[robot]


def plan_scene(task: SceneTask) -> tuple[str, list[Planned]]:
    """Build the scene's problems, plan and verify each (in a worker).

    Args:
        task: the scene and its pairs.

    Returns:
        (the scene id, one `Planned` per pair, in the order of `task.pairs`).
    """
    out: list[Planned] = []
    judge = verifier(task.robot)
    for p in make_scene(task.kind, task.scene, task.pairs, task.seed, judge, robot=task.robot):
        seed = problem_seed(task.seed, p.id)
        _, result = worker.solve(Task(p.id, task.robot, p.world, task.id, p.start, p.goal, {**task.options, "seed": seed}))
        traj = result.trajectory
        if traj is None:
            verdict = Verdict(False)
        else:
            try:
                v = judge.verify_trajectory(p.world, traj.times, traj.positions, traj.velocities,
                                            traj.accelerations, start_q=p.start, goal_q=p.goal)
                verdict = Verdict(bool(v.valid), tuple(v.reasons))
            except Exception as exc:  # a failed row, not a lost scene
                log.warning("problem %r: the verifier raised %s", p.id, type(exc).__name__, exc_info=True)
                verdict = Verdict(False, (f"the verifier raised {type(exc).__name__}: {exc}",))
        out.append((p, seed, result, verdict))
    return task.id, out
