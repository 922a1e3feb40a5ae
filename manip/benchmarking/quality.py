"""Trajectory quality metrics and the per-problem lower bound on motion time.

Units: positions [rad], times [s], velocities [rad/s], accelerations [rad/s^2],
jerks [rad/s^3]. Lengths are joint-space L2 lengths [rad] (the sum over joints is NOT
weighted), the way cuRobo's benchmark measures path length.

The lower bound (`lower_bound_time`) is the duration of ruckig's time-optimal
rest-to-rest motion from the start configuration to the goal configuration under per-joint
velocity, acceleration and jerk limits, every joint arriving at the same time
(`Synchronization.Time`, ruckig's default). Each joint of ANY motion that starts and ends
at rest under the same limits needs at least this long (ruckig's duration is the smallest
one at which every joint can arrive; with time synchronisation the joints need not stay on
the straight joint-space line, so this is never longer than the time-optimal straight
line, which is what manip's timing stage produces for an unobstructed problem). So
`motion_time / lower_bound >= 1` for every valid trajectory, and the ratio says how much
slower than the unobstructed optimum a planner's motion is.

For a pose goal the lower bound is taken from the start to the configuration the planner
actually reached (the last position of its trajectory): different IK solutions of the same
pose have very different bounds, and the bound should judge the timing of the motion the
planner chose, not its choice of IK solution.

ruckig is used only state to state (no intermediate waypoints, which the community build
computes remotely).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import ruckig

from manip.errors import InvalidInputError

__all__ = [
    "lower_bound_time",
    "path_length",
    "straight_line_length",
    "max_jerk",
    "safe_ratio",
]


def _vec(x: Any, n: int | None, what: str) -> np.ndarray:
    a = np.asarray(x, dtype=float).reshape(-1)
    if n is not None and a.shape != (n,):
        raise InvalidInputError(f"{what} must have {n} entries; got shape {np.shape(x)}")
    return a


def lower_bound_time(start: Any, goal: Any, vmax: Any, amax: Any, jmax: Any) -> float:
    """Time-optimal rest-to-rest duration from `start` to `goal` [s] (see the module docstring).

    Args:
        start: (dof,) start configuration [rad] (at rest).
        goal: (dof,) goal configuration [rad] (at rest).
        vmax: (dof,) or scalar velocity limits [rad/s], > 0.
        amax: (dof,) or scalar acceleration limits [rad/s^2], > 0.
        jmax: (dof,) or scalar jerk limits [rad/s^3], > 0; `math.inf` gives ruckig's
            acceleration-limited (second-order) profiles, the bound for planners that do
            not limit jerk.

    Returns:
        The duration of ruckig's one state-to-state calculation (zero velocities and
        accelerations at both ends, `Synchronization.Time`); 0.0 when start == goal.

    Raises:
        InvalidInputError: shapes differ, non-finite positions, or non-positive limits.
        RuntimeError: ruckig did not return `Result.Working`.
    """
    q0 = _vec(start, None, "start")
    dof = q0.size
    q1 = _vec(goal, dof, "goal")
    if not (np.all(np.isfinite(q0)) and np.all(np.isfinite(q1))):
        raise InvalidInputError(f"start and goal must be finite; got {q0}, {q1}")
    lims = []
    for what, lim in (("vmax", vmax), ("amax", amax), ("jmax", jmax)):
        a = np.broadcast_to(np.asarray(lim, dtype=float), (dof,)).copy()
        if np.any(~(a > 0)) or (what != "jmax" and not np.all(np.isfinite(a))):
            raise InvalidInputError(f"{what} must be positive (and finite, except jmax); got {a}")
        lims.append(a)
    if np.array_equal(q0, q1):
        return 0.0
    otg = ruckig.Ruckig(dof)
    inp = ruckig.InputParameter(dof)
    zeros = [0.0] * dof
    inp.current_position = q0.tolist()
    inp.current_velocity = zeros
    inp.current_acceleration = zeros
    inp.target_position = q1.tolist()
    inp.target_velocity = zeros
    inp.target_acceleration = zeros
    inp.max_velocity = lims[0].tolist()
    inp.max_acceleration = lims[1].tolist()
    inp.max_jerk = lims[2].tolist()
    traj = ruckig.Trajectory(dof)
    res = otg.calculate(inp, traj)
    if res != ruckig.Result.Working:
        raise RuntimeError(f"ruckig returned {res} for the lower bound from {q0} to {q1}")
    return float(traj.duration)


def path_length(positions: Any) -> float:
    """Sum of the joint-space L2 lengths of consecutive samples [rad].

    Args:
        positions: (T, dof) joint positions [rad].

    Returns:
        sum_i ||q_{i+1} - q_i||_2; 0.0 for fewer than two samples.
    """
    P = np.asarray(positions, dtype=float)
    if P.ndim != 2:
        raise InvalidInputError(f"positions must be (T, dof); got shape {P.shape}")
    if len(P) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


def straight_line_length(start: Any, goal: Any) -> float:
    """Joint-space L2 distance ||goal - start||_2 [rad] (the shortest possible path length)."""
    q0 = _vec(start, None, "start")
    return float(np.linalg.norm(_vec(goal, q0.size, "goal") - q0))


def max_jerk(trajectory: Any) -> float:
    """Largest |jerk| over time and joints [rad/s^3].

    Args:
        trajectory: an object with a `jerks` attribute (e.g. `manip.Trajectory`), or the
            (T, dof) jerk samples themselves [rad/s^3].

    Returns:
        max over samples t of max over joints j of |jerk[t, j]|; nan for an empty array.
    """
    J = getattr(trajectory, "jerks", trajectory)
    if J is None:
        return math.nan
    J = np.asarray(J, dtype=float)
    if J.size == 0:
        return math.nan
    return float(np.abs(J).max())


def safe_ratio(num: float, den: float) -> float:
    """num / den, or nan when either is not finite or den <= 0 (e.g. a zero lower bound)."""
    if not (math.isfinite(num) and math.isfinite(den)) or den <= 0:
        return math.nan
    return num / den
