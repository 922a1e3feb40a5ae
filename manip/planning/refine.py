"""The trajectory-optimisation stage of a plan: refine a valid timed trajectory.

The shortcut path's ruckig timing (valid, certified) seeds `optimize_trajectory`;
the optimised motion replaces it only when it is faster and passes the same certified
exact-mesh validation, so success never depends on the optimiser.
"""

from __future__ import annotations

import math

import numpy as np

from manip.collision.clearance import ClearanceModel
from manip.planning import bspline
from manip.planning.context import PlanContext
from manip.planning.finish import validate_trajectory
from manip.planning.trajopt import SMOOTH, TrajOptSettings, optimize_trajectory
from manip.planning.validity import Validity
from manip.timing import TimingLimits
from manip.timing.bounds import rest_to_rest_time
from manip.trajectory import Trajectory


def scaled_limits(limits: TimingLimits, ctx: PlanContext) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vmax, amax, jmax) (dof,) of this call: the robot's limits times the call's scales."""
    o = ctx.options
    return limits.velocity * o.velocity_scale, limits.acceleration * o.acceleration_scale, limits.jerk * o.jerk_scale


def refine(
    ctx: PlanContext, seed: Trajectory, limits: TimingLimits, validity: Validity, clearance: ClearanceModel,
    padding: float,
) -> Trajectory | None:
    """A faster valid trajectory between the same configurations than `seed`, or None.

    Skipped (None) when the call asks for a fixed `duration`.
    """
    o = ctx.options
    if o.duration is not None:
        return None
    vmax, amax, jmax = scaled_limits(limits, ctx)
    start, goal = seed.positions[0], seed.positions[-1]
    bound = rest_to_rest_time(start, goal, vmax, amax, jmax)
    if seed.duration <= bound * 1.03:
        return None
    settings = SMOOTH if o.smoothness == "smooth" else TrajOptSettings()
    # bounded by its rounds and iterations, not by the clock (the same seed gives the same
    # trajectory on any machine); only the call's time budget can cut it short
    result = optimize_trajectory(
        seed.positions, seed.times, vmax, amax, jmax, validity.kinematics.lower, validity.kinematics.upper,
        clearance, padding, ctx.deadline, settings=settings, min_duration=bound,
        max_duration=seed.duration,
    )
    if not result.success:
        return None
    n = result.control.shape[0] - 3
    steps = math.ceil(result.duration / o.dt - 1e-9)
    if steps * o.dt >= seed.duration:
        return None
    h = steps * o.dt / n  # a whole number of samples; slower than the limits need, never faster
    traj = Trajectory.from_profile(bspline.to_profile(result.control, h), o.dt, seed.joint_names)
    if validate_trajectory(traj, start, goal, validity):
        return None
    return traj
