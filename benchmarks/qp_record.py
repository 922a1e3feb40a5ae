"""The trajectory optimiser's QPs of MotionBenchMaker plans, recorded for solver comparisons
(`benchmarks/qp_banded.py`; issue 33).

`record(limit_per_scene, scenes)` plans the first valid problems of each scene (joint and pose
goals, seed 0) and returns every `planning.trajopt.qp.solve` call's arguments, each a dict:
P (CSC), q, G_T (dense, G transposed), h, A (CSC or None), b, lb, ub.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from manip import MotionGenerator, WorldConfig  # noqa: E402
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems  # noqa: E402
from manip.benchmarking.verify import Verifier  # noqa: E402
from manip.planning.trajopt import qp  # noqa: E402


def record(limit_per_scene: int, scenes: list[str] | None = None) -> list[dict]:
    """The QPs of the first `limit_per_scene` valid problems of each scene (all, or `scenes`; both goal kinds)."""
    recorded = []
    solve = qp.solve

    def recording(P, q, G, h, A, b, lb, ub, solver):
        recorded.append({"P": P.copy(), "q": q.copy(), "G_T": G.toarray().T, "h": h.copy(),
                         "A": None if A is None else A.copy(), "b": None if b is None else b.copy(),
                         "lb": lb.copy(), "ub": ub.copy()})
        return solve(P, q, G, h, A, b, lb, ub, solver)

    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    problems = [p for p in load_mbm_problems(limit_per_scene=limit_per_scene)
                if (scenes is None or p.scene in scenes) and verifier.check_problem(p).valid]
    qp.solve = recording
    try:
        for p in problems:
            mg.update_world(WorldConfig.from_dict(p.world))
            mg.plan_joints(p.start, p.goal, seed=0)
            mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0)
    finally:
        qp.solve = solve
    return recorded
