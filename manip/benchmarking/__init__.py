"""Benchmarking tools: MotionBenchMaker problems, seeded scenes and an independent verifier.

The verifier (`manip.benchmarking.verify`) deliberately shares no collision code with the
planner it judges: it builds its own exact-mesh Pinocchio/coal model of the robot and world.
"""

from __future__ import annotations

from manip.benchmarking.mbm import (
    MBM_SCENES,
    MBMProblem,
    dataset_available,
    default_dataset_path,
    goal_pose,
    load_mbm_problems,
)

__all__ = [
    "MBM_SCENES",
    "MBMProblem",
    "dataset_available",
    "default_dataset_path",
    "goal_pose",
    "load_mbm_problems",
]
