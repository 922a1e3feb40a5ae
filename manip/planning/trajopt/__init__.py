"""Trajectory optimisation: a timed trajectory from a collision-free path, faster and smooth.

- `optimizer`: `optimize_trajectory` (a uniform cubic B-spline, `bspline`, improved by
  sequential convex optimisation, `sco`, one QP per step, `qp`); `settings`: `TrajOptSettings`.
- `refine`: the plan's use of it (seeded by the path's timing, certified, with retries).

`from manip.planning.trajopt import TrajOptSettings, optimize_trajectory` keeps working.
"""

from __future__ import annotations

from manip.planning.trajopt.optimizer import TrajOptResult, optimize_trajectory
from manip.planning.trajopt.settings import SMOOTH, TrajOptSettings

__all__ = ["SMOOTH", "TrajOptResult", "TrajOptSettings", "optimize_trajectory"]
