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
    otg.calculate(inp, traj)
    return float(traj.duration)
