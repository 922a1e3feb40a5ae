"""`Trajectory`: a timed joint-space motion, sampled every `dt` and exact in between.

A trajectory produced by `manip.timing.time_parameterize` carries its underlying
piecewise-constant-jerk profile (`PiecewiseJerkProfile`, one cubic polynomial per phase
and joint, as computed by ruckig), so `at_time` and `resample` are exact rather than
interpolated. `time_parameterize_dense` gives a `PathProfile` instead: a cubic spline
`q(s)` through a dense path traversed by a 1-D constant-jerk profile `s(t)`, equally exact.
A trajectory built from samples alone (e.g. from another planner) falls back to
interpolation of its samples (documented on `Trajectory.at_time`).

Layout: `profiles` (PiecewiseJerkProfile, evaluate_pieces), `spline` (CubicSplinePath,
PathProfile), `trajectory` (Trajectory, sample_times). The simulator bridge
(`Trajectory.to_articulation_actions`) lives in `manip.sim_bridge`.
"""

from manip.trajectory.profiles import PiecewiseJerkProfile, evaluate_pieces
from manip.trajectory.spline import CubicSplinePath, PathProfile
from manip.trajectory.trajectory import Trajectory, sample_times

__all__ = [
    "CubicSplinePath",
    "PathProfile",
    "PiecewiseJerkProfile",
    "Trajectory",
    "evaluate_pieces",
    "sample_times",
]
