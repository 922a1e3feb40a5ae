"""Benchmarking tools: MotionBenchMaker problems, seeded scenes, quality metrics and an
independent verifier.

- `manip.benchmarking.mbm_problems`: the MotionBenchMaker Panda problem loader;
- `manip.benchmarking.quality`: per-problem lower bound on motion time, path length,
  straight-line length, max jerk;
- `manip.benchmarking.scenes`: seeded problem generators;
- `manip.benchmarking.verify`: the verifier, which deliberately shares no collision code with
  the planner it judges: it builds its own exact-mesh Pinocchio/coal model of the robot and
  world.
"""

from __future__ import annotations

from manip.benchmarking.mbm_problems import (
    MBM_SCENES,
    MBMProblem,
    dataset_available,
    default_dataset_path,
    goal_pose,
    load_mbm_problems,
)
from manip.benchmarking.quality import lower_bound_time, max_jerk, path_length, straight_line_length

__all__ = [
    "MBM_SCENES",
    "MBMProblem",
    "dataset_available",
    "default_dataset_path",
    "goal_pose",
    "load_mbm_problems",
    "lower_bound_time",
    "max_jerk",
    "path_length",
    "straight_line_length",
]
