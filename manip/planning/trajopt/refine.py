"""The trajectory-optimisation stage of a plan: refine a valid timed trajectory.

The shortcut path's ruckig timing (stopping at each waypoint) seeds `optimize_trajectory`;
the optimised motion is returned only when it is faster than that timing and passes the
certified exact-mesh validation; otherwise the caller validates the path's timings, so success
never depends on the optimiser.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace


from manip.collision.clearance import ClearanceModel
from manip.planning.trajopt import bspline
from manip.planning.context import PlanContext
from manip.planning.time_and_validate import validate_trajectory
from manip.planning.trajopt.optimizer import SMOOTH, TrajOptSettings, optimize_trajectory
from manip.planning.validity import Validity
from manip.limits import JointLimits
from manip.timing.bounds import rest_to_rest_time
from manip.trajectory import Trajectory


#: Ray points (`TrajOptSettings.ray_points`) of the optimiser's further tries when its motion
#: fails the exact validation (near an obstacle the sphere cover is too coarse: more of the
#: seed's approach to an end is kept). One try: without a second one with 4, no motion changed
#: in 2 x 1252 MotionBenchMaker plans. Measurements: BENCHMARKS.md, "Constants" and round sixteen.
RETRY_RAY_POINTS = (2,)
#: QPs of all the optimiser's tries of one plan together (a count: the same seed gives the
#: same trajectory on any machine).
QP_BUDGET = 50
#: Samples per piece (`TrajOptSettings.samples_per_interval`) of the repair of an optimised
#: motion that touched an obstacle between the optimiser's clearance samples.
REPAIR_SAMPLES = 8


def refine(
    ctx: PlanContext, seed: Trajectory, *, limits: JointLimits, validity: Validity, clearance: ClearanceModel,
    padding: float,
) -> Trajectory | None:
    """A faster valid trajectory between the same configurations than `seed`, or None.

    Skipped (None) when the call asks for a fixed `duration`. An optimised motion that fails
    the validation is first optimised on from itself with denser clearance samples
    (`REPAIR_SAMPLES`), then again from the seed with more of the seed's ends kept
    (`RETRY_RAY_POINTS`). The seed itself need not be valid (the caller validates it only when
    this gives nothing). Stage times go to ctx.timings ("trajopt"; "validate" for the
    certification).
    """
    o = ctx.options
    if o.duration is not None:
        return None
    limits = ctx.scaled_limits(limits)
    start, goal = seed.positions[0], seed.positions[-1]
    bound = rest_to_rest_time(start, goal, limits)
    if seed.duration <= bound * 1.03:
        return None
    settings = SMOOTH if o.smoothness == "smooth" else TrajOptSettings()
    left = QP_BUDGET

    def optimize(motion: Trajectory, s: TrajOptSettings) -> tuple[Trajectory | None, int]:
        """(the optimised motion sampled at dt if faster than the seed, else None; its ends tied)."""
        nonlocal left
        t = time.perf_counter()
        # bounded by its rounds, iterations and QP budget, not by the clock (the same seed
        # gives the same trajectory on any machine); only the call's time budget can cut it short
        result = optimize_trajectory(
            motion.positions, motion.times, limits=limits, clearance=clearance, padding=padding,
            deadline=ctx.deadline, settings=s, min_duration=bound, max_duration=seed.duration, max_solves=left,
        )
        left -= result.solves
        steps = math.ceil(result.duration / o.dt - 1e-9) if result.success else 0
        traj = None
        if result.success and steps * o.dt < seed.duration:
            h = steps * o.dt / (result.control.shape[0] - 3)  # a whole number of samples; never faster than the limits
            traj = Trajectory.from_profile(bspline.to_profile(result.control, h), o.dt, seed.joint_names)
        ctx.add_time("trajopt", t)
        return traj, result.ends_tied

    def valid(traj: Trajectory) -> bool:
        t = time.perf_counter()
        why = validate_trajectory(traj, start, goal, validity)
        ctx.add_time("validate", t)
        return not why

    def tries():
        """The settings of each try: the call's, then more ray points (built only when needed:
        validating a settings object costs ~0.1 ms)."""
        yield settings
        for k in RETRY_RAY_POINTS:
            if settings.ray_points < k <= settings.intervals // 2 - 2:
                yield replace(settings, ray_points=k)

    for attempt, s in enumerate(tries()):
        if left < 1:
            break
        traj, ends_tied = optimize(seed, s)
        if traj is None:
            if attempt == 0:
                return None  # retries are for motions that failed the validation
            continue
        if valid(traj):
            return traj
        if attempt == 0 and left >= 1:
            # it touched an obstacle between the samples the optimiser kept clear: on from it
            repaired, _ = optimize(traj, replace(s, samples_per_interval=REPAIR_SAMPLES))
            if repaired is not None and valid(repaired):
                return repaired
        if ends_tied == 0:
            return None  # the retries would give the same motion
    return None
