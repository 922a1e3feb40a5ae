"""The last stages of a plan: time a path, then validate the timed trajectory.

`validate_trajectory` is the guarantee of every successful plan (the timing stage's and the
optimiser's, `planning.trajopt.refine`): the returned samples are what a user executes and what a
verifier checks, so the continuous linear interpolation between consecutive samples is
certified collision-free against the exact meshes with the padding
(`CollisionChecker.certify_path`: conservative advancement), whatever resolution a
verifier uses. The true motion between samples strays from that line by less than
max|acceleration| dt^2 / 8 (e.g. 0.3 mrad at 1/60 s). Limits are checked by the timing
stage (or the optimiser) on the exact profile.
"""

from __future__ import annotations

import time

import numpy as np

from manip.planning.context import PlanContext
from manip.planning.validity import Validity
from manip.limits import JointLimits
from manip.timing import time_path
from manip.trajectory import Trajectory
from manip.validation import MAX_SAMPLES

#: Position-limit tolerance [rad] of trajectories whose start is inside the limits.
LIMIT_TOLERANCE = 1e-6
#: Time step [s] of the check that a motion from a start outside the limits stays in once in.
REENTRY_STEP = 1e-3
#: How far [rad] the blended timing of a path may cut its corners (`timing.time_path`).
BLEND_DEVIATION = 0.05
#: Smaller corner cuts [rad] tried in turn for a path that must keep constraints.
CONSTRAINED_BLENDS = (0.02, 0.008)


def validate_trajectory(traj: Trajectory, start: np.ndarray, goal: np.ndarray, validity: Validity) -> str:
    """Why the timed trajectory is not acceptable ("" when it is): endpoints, and the
    certificate that its continuous interpolation is collision-free."""
    if np.max(np.abs(traj.positions[0] - start)) > 1e-9 or np.max(np.abs(traj.positions[-1] - goal)) > 1e-6:
        return "trajectory does not start at the start or end at the goal"
    if traj.num_samples > MAX_SAMPLES:
        return f"trajectory has {traj.num_samples} samples (more than MAX_SAMPLES = {MAX_SAMPLES})"
    if why := limits_reentered(traj, start, validity):
        return why
    certify = getattr(validity, "certify_trajectory", None)  # (tests hand in stand-in validities)
    cert = certify(traj) if certify is not None else validity.certify(traj.positions)
    if not cert.certified:
        t = traj.times[cert.first_failed_segment]
        if cert.reason.startswith("constraint"):
            proved = "violates a constraint" if cert.reason == "constraint" else "could not be certified to keep a constraint"
            return f"timed trajectory {proved} near t = {t:.3f} s: {cert.pair[0]}"
        what = "collides" if cert.reason == "collision" else "could not be certified collision-free"
        return f"timed trajectory {what} near t = {t:.3f} s ({cert.pair[0]} / {cert.pair[1]})"
    return ""


def limits_reentered(traj: Trajectory, start: np.ndarray, validity: Validity) -> str:
    """Why the motion of a start outside the position limits is not acceptable ("" when it is).

    Such a start (up to `context.START_LIMIT_TOLERANCE` out) is timed against limits widened by
    its excess (`time_once`); every joint must still stay within LIMIT_TOLERANCE of its limits
    from the first time it is inside them (a spline through IK points on a limit overshot it by
    2 urad mid-motion). Checked at the samples and every REENTRY_STEP [s] of the exact motion."""
    k = validity.kinematics
    excess = np.maximum(k.lower - start, start - k.upper)
    if not np.any(excess > LIMIT_TOLERANCE):
        return ""
    n = min(int(np.ceil(traj.duration / REENTRY_STEP)) + 1, MAX_SAMPLES)
    t = np.union1d(traj.times, np.linspace(0.0, traj.duration, max(n, 2)))
    q = traj.at_time(t)[0]
    out = np.maximum(k.lower - q, q - k.upper)
    inside = out <= LIMIT_TOLERANCE
    bad = np.maximum.accumulate(inside, axis=0) & ~inside
    if not bad.any():
        return ""
    i, j = np.argwhere(bad)[0]
    return (f"joint {k.joint_names[j]} leaves its limits again by {out[i, j]:.2g} rad near t = {t[i]:.3f} s "
            f"(the start is {float(np.max(excess)):.2g} rad outside)")


def time_once(ctx: PlanContext, path: np.ndarray, *, limits: JointLimits, validity: Validity, mode: str,
              deviation: float) -> tuple[Trajectory | None, str]:
    """(the path (K, dof) timed in `mode` (`timing.time_path`), "") or (None, why not);
    the stage time goes to ctx.timings ("timing")."""
    opts = ctx.options
    t = time.perf_counter()
    timed = time_path(
        path, limits, mode=mode, dt=opts.dt,
        position_tolerance=max(LIMIT_TOLERANCE, validity.limit_excess(path[0])),
        deviation_tolerance=deviation, velocity_scale=opts.velocity_scale,
        acceleration_scale=opts.acceleration_scale, jerk_scale=opts.jerk_scale, duration=opts.duration,
    )
    ctx.add_time("timing", t)
    return (timed.trajectory, "") if timed.success else (None, timed.message)


def time_and_validate(
    ctx: PlanContext,
    path: np.ndarray,
    goal_q: np.ndarray,
    *,
    limits: JointLimits,
    validity: Validity,
    deviation: float = BLEND_DEVIATION,
    dense_deviation: float | None = None,
    timed: dict[str, Trajectory] | None = None,
) -> tuple[Trajectory | None, str]:
    """Time the path (corners blended within `deviation` rad, else stopping at each) and validate.

    With `dense_deviation` given (a dense path sampled from a smooth curve, e.g. a linear
    motion), one smooth motion along a spline through its points, within `dense_deviation`
    rad of the path, is tried first. `timed`: timings of the path the caller has already, by
    mode ("blend", "exact"; validated, not timed again). Stage times go to ctx.timings
    ("timing", "validate").

    Returns:
        (the first valid trajectory, "") or (None, why the last try failed).
    """
    # a constrained path: corners cut less and less before stopping at each waypoint (a cut
    # corner leaves the certified segments, and a constraint's margin may be thin there)
    blends = [(mode, deviation) for mode in ("blend",)] + [("blend", d) for d in CONSTRAINED_BLENDS if d < deviation
                                                          and getattr(validity, "constraints", ())]
    modes = ([("along_path", dense_deviation)] if dense_deviation is not None else []) + blends + [("exact", deviation)]
    reason = ""
    for mode, dev in modes:
        if timed and mode in timed and dev == deviation:
            traj = timed[mode]
        else:
            traj, reason = time_once(ctx, path, limits=limits, validity=validity, mode=mode, deviation=dev)
            if traj is None:
                continue
        t = time.perf_counter()
        reason = validate_trajectory(traj, path[0], goal_q, validity)
        ctx.add_time("validate", t)
        if not reason:
            return traj, ""
    return None, reason
