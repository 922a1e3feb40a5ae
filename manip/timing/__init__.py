"""Time-parameterisation of a joint-space path with ruckig (state-to-state only).

`time_path(path, config.limits, mode=...)` (or `time_parameterize(path,
...)`) turns the piecewise-linear, collision-checked joint path of a planner into a
`Trajectory` at rest at both ends that respects velocity, acceleration and jerk limits
everywhere (checked on the profile and on the samples). Three modes:

* ``"exact"``: stop at every corner; the motion stays on the straight segments
  (`manip.timing.waypoints`).
* ``"blend"`` (default): pass through the interior waypoints with a non-zero velocity,
  within `deviation_tolerance` [rad] of the path; never slower than exact. The caller
  should collision-check the timed motion (its samples or `at_time` densely) and fall
  back to ``mode="exact"`` if it collides (`manip.timing.waypoints`).
* ``"along_path"`` (`time_parameterize_dense`): for DENSE paths sampled from a smooth
  curve; one time scaling along a C2 spline through all the points
  (`manip.timing.dense`), with "blend" as the fallback.

Speed and duration control: `velocity_scale`, `acceleration_scale` and `jerk_scale`
scale the limits (MoveIt-style scaling factors in (0, 1]); `duration` stretches the
fastest trajectory uniformly in time to a chosen duration (uniform time scaling by a
factor `k >= 1` divides velocities by `k`, accelerations by `k^2` and jerks by `k^3`,
so limits still hold and the geometric path is unchanged). The total duration is always
rounded up to a whole number of `dt` (by the same uniform stretch), so samples are
evenly spaced and the last one is exactly at the goal, at rest.

Layout: `result` (TimingStatus, TimingResult), `checks` (input validation), `shared`
(helpers of both algorithms), `segments` + `waypoints` (exact/blend), `dense`
(along_path), `dispatch` (time_path and the public wrappers).
"""

from manip.limits import JointLimits
from manip.timing.checks import MODES
from manip.timing.dense import time_parameterize_dense
from manip.timing.dispatch import TimingLimits, time_parameterize, time_parameterize_for_robot, time_path
from manip.timing.result import TimingResult, TimingStatus

__all__ = [
    "MODES",
    "JointLimits",
    "TimingLimits",  # the old name of JointLimits
    "TimingResult",
    "TimingStatus",
    "time_parameterize",
    "time_parameterize_dense",
    "time_parameterize_for_robot",
    "time_path",
]
