"""The time-optimal rest-to-rest duration between two configurations (a lower bound).

ruckig state to state with time synchronisation: no motion between the two configurations
that starts and ends at rest under the same limits is faster. The planner uses it to pick,
among goal configurations, the one reachable fastest, and to stop optimising a duration
that is already close to it.
"""

from __future__ import annotations

import numpy as np
import ruckig

from manip.limits import JointLimits
from manip.timing.shared import RUCKIG_ERRORS


def rest_to_rest_time(start: np.ndarray, goal: np.ndarray, limits: JointLimits) -> float:
    """Duration [s] of the time-optimal motion from `start` to `goal` (dof,) at rest, under
    the velocity, acceleration and jerk limits of `limits` [rad/s, rad/s^2, rad/s^3]."""
    dof = len(start)
    if np.array_equal(start, goal):
        return 0.0
    otg = ruckig.Ruckig(dof)
    inp = ruckig.InputParameter(dof)
    inp.current_position = np.asarray(start, dtype=float).tolist()
    inp.target_position = np.asarray(goal, dtype=float).tolist()
    zeros = [0.0] * dof
    inp.current_velocity, inp.current_acceleration = zeros, zeros
    inp.target_velocity, inp.target_acceleration = zeros, zeros
    inp.max_velocity = limits.velocity.tolist()
    inp.max_acceleration = limits.acceleration.tolist()
    inp.max_jerk = limits.jerk.tolist()
    traj = ruckig.Trajectory(dof)
    try:
        result = otg.calculate(inp, traj)
    except RUCKIG_ERRORS:
        result = None
    if result in (ruckig.Result.Working, ruckig.Result.Finished):
        return float(traj.duration)
    # ruckig fails on motions of thousands of seconds (limits scaled down by 1e-4 or so)
    return float(np.max(single_joint_times(np.abs(np.asarray(goal, float) - start), limits.velocity,
                                           limits.acceleration, limits.jerk)))


def single_joint_times(distance: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(dof,) time-optimal rest-to-rest durations [s] of each joint alone over `distance` [rad]
    under its limits v, a, j (dof,): the closed form of the jerk-limited S-curve. Their maximum
    is a lower bound of the joints' synchronised motion (ruckig's)."""
    d, v, a, j = (np.asarray(x, dtype=float) for x in (distance, v, a, j))
    # the peak velocity with saturated acceleration (d = vp (vp / a + a / j)), else a jerk-only ramp
    vp = np.minimum(v, a / 2.0 * (np.sqrt((a / j) ** 2 + 4.0 * d / a) - a / j))
    vp = np.where(vp >= a * a / j, vp, np.minimum(v, np.cbrt((d * np.sqrt(j) / 2.0) ** 2)))
    ramp = np.where(vp >= a * a / j, vp / a + a / j, 2.0 * np.sqrt(vp / j))   # 0 -> vp [s]
    return np.where(d > 0.0, ramp + d / np.maximum(vp, 1e-300), 0.0)
