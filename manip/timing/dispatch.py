"""The entry points: `time_path` + `JointLimits` (one call for every mode) and the wrappers.

`time_parameterize` and `time_parameterize_for_robot` keep their historical signatures.
This is the only module that imports both algorithms (`waypoints` and `dense`).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, Literal, Sequence

import numpy as np

from manip.errors import InvalidInputError
from manip.limits import JointLimits
from manip.timing.checks import check_deviation_tolerance, check_inputs, check_mode
from manip.timing.dense import time_parameterize_dense
from manip.timing.result import TimingResult
from manip.timing.waypoints import time_waypoints

if TYPE_CHECKING:
    from manip.robot_config import RobotConfig

#: Default `deviation_tolerance` [rad] of the "blend" mode.
BLEND_DEVIATION = 0.05
#: Default `stop_angle` [rad] of the "blend" mode.
STOP_ANGLE = float(np.deg2rad(100.0))


#: The limits of a timing call: `manip.limits.JointLimits` (the old name, kept).
TimingLimits = JointLimits


def _run(
    mode: str, path: Any, velocity: Any, acceleration: Any, jerk: Any, deviation_tolerance: float | None,
    stop_angle: float, **options: Any,
) -> TimingResult:
    """The algorithm of `mode` (already checked); `options` are the keywords of `check_inputs`."""
    if mode == "along_path":
        return time_parameterize_dense(path, velocity, acceleration, jerk, deviation_tolerance=deviation_tolerance,
                                       **options)
    t_start = time.perf_counter()
    check_deviation_tolerance(deviation_tolerance)
    checked = check_inputs(path, velocity, acceleration, jerk, **options)
    return time_waypoints(
        checked, mode=mode, deviation_tolerance=deviation_tolerance, stop_angle=stop_angle, dt=options["dt"],
        duration=options["duration"], t_start=t_start,
    )


def time_path(
    path: np.ndarray | Sequence[Sequence[float]],
    limits: TimingLimits,
    *,
    mode: Literal["exact", "blend", "along_path"] = "blend",
    dt: float = 1.0 / 60.0,
    position_tolerance: float = 1e-6,
    deviation_tolerance: float | None = None,
    velocity_scale: float = 1.0,
    acceleration_scale: float = 1.0,
    jerk_scale: float = 1.0,
    duration: float | None = None,
) -> TimingResult:
    """Time a joint path within `limits` with the algorithm of `mode` (one entry point for all).

    Args:
        path: (K, dof) waypoints [rad], K >= 1; the first is the start, the last the goal.
        limits: the joints' limits and names (`config.limits` of a `RobotConfig`).
        mode: "blend" (round corners within `deviation_tolerance`, `time_parameterize`),
            "exact" (stop at every corner) or "along_path" (one motion along a spline
            through dense points, `time_parameterize_dense`).
        dt: sample period of the returned trajectory [s].
        position_tolerance: waypoints may lie this far outside the position limits [rad].
        deviation_tolerance: max distance of the motion from the path [rad]; None means
            0.05 rad in "blend" mode and unchecked in "along_path" mode (unused in "exact").
        velocity_scale, acceleration_scale, jerk_scale: factors in (0, 1] on the limits.
        duration: desired total time [s] (uniform time stretch); None = fastest.

    Returns:
        The `TimingResult` of the mode's algorithm (identical to calling it directly).

    Raises:
        InvalidInputError: an unknown mode (the message lists the valid ones), `limits`
            not a `JointLimits` or for another number of joints, or any invalid input
            of the algorithm.
    """
    check_mode(mode)
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(
            f"limits must be a manip.JointLimits (e.g. RobotConfig.limits); got {type(limits).__name__}"
        )
    try:
        shape = np.shape(path)
    except ValueError:  # ragged: the algorithm's own check explains
        shape = ()
    if len(shape) == 2 and shape[1] != limits.dof:
        raise InvalidInputError(
            f"path has {shape[1]} joints per waypoint but limits are for {limits.dof} joints: {limits.joint_names}"
        )
    if deviation_tolerance is None and mode != "along_path":
        deviation_tolerance = BLEND_DEVIATION
    return _run(
        mode, path, limits.velocity, limits.acceleration, limits.jerk, deviation_tolerance, STOP_ANGLE,
        dt=dt, joint_names=limits.joint_names, lower_limits=limits.lower, upper_limits=limits.upper,
        position_tolerance=position_tolerance, velocity_scale=velocity_scale,
        acceleration_scale=acceleration_scale, jerk_scale=jerk_scale, duration=duration,
    )


def time_parameterize(
    path: np.ndarray | Sequence[Sequence[float]],
    velocity_limits: np.ndarray | Sequence[float],
    acceleration_limits: np.ndarray | Sequence[float],
    jerk_limits: np.ndarray | Sequence[float],
    *,
    dt: float = 1.0 / 60.0,
    joint_names: Sequence[str] | None = None,
    lower_limits: np.ndarray | Sequence[float] | None = None,
    upper_limits: np.ndarray | Sequence[float] | None = None,
    position_tolerance: float = 1e-6,
    mode: Literal["blend", "exact", "along_path"] = "blend",
    deviation_tolerance: float = BLEND_DEVIATION,
    stop_angle: float = STOP_ANGLE,
    velocity_scale: float = 1.0,
    acceleration_scale: float = 1.0,
    jerk_scale: float = 1.0,
    duration: float | None = None,
) -> TimingResult:
    """Time-parameterise a piecewise-linear joint path with ruckig (see `manip.timing`).

    Args:
        path: (K, dof) waypoints [rad], K >= 1; the first is the start, the last the goal.
        velocity_limits: (dof,) max |velocity| [rad/s] (or a scalar for all joints).
        acceleration_limits: (dof,) max |acceleration| [rad/s^2].
        jerk_limits: (dof,) max |jerk| [rad/s^3].
        dt: sample period of the returned trajectory [s] (default 1/60, the simulator's).
        joint_names: (dof,) names; default "joint_0", "joint_1", ...
        lower_limits: (dof,) lower position limits [rad]; None = unchecked.
        upper_limits: (dof,) upper position limits [rad]; None = unchecked.
        position_tolerance: waypoints may lie this far outside the position limits [rad]
            (a start a hair outside a limit is accepted); the motion is checked against
            the limits widened by the same amount.
        mode: "blend" (default, round corners, faster), "exact" (stop at every corner,
            stay on the straight segments) or "along_path" (one smooth motion along a
            spline through dense points: `time_parameterize_dense`, which gets
            `deviation_tolerance`; `stop_angle` is unused).
        deviation_tolerance: blend and along_path modes: max distance of the motion from
            the input path [rad] (joint-space Euclidean, which bounds the L-inf distance).
        stop_angle: blend mode: corners turning by more than this stop the motion [rad].
        velocity_scale: factor in (0, 1] applied to the velocity limits.
        acceleration_scale: factor in (0, 1] applied to the acceleration limits.
        jerk_scale: factor in (0, 1] applied to the jerk limits.
        duration: desired total time [s]; the fastest trajectory is stretched uniformly
            in time to it (rounded up to a multiple of `dt`). If it is shorter than the
            fastest feasible, the result has status DURATION_TOO_SHORT and
            `minimum_duration` says what is feasible.

    Returns:
        TimingResult (`success`, `status`, `trajectory`, `max_deviation`, ...).

    Raises:
        InvalidInputError: wrong shapes, non-finite values, non-positive limits, scales
            outside (0, 1], waypoints outside the position limits, unknown mode.
    """
    check_mode(mode)
    check_deviation_tolerance(deviation_tolerance)
    return _run(
        mode, path, velocity_limits, acceleration_limits, jerk_limits, deviation_tolerance, stop_angle,
        dt=dt, joint_names=joint_names, lower_limits=lower_limits, upper_limits=upper_limits,
        position_tolerance=position_tolerance, velocity_scale=velocity_scale,
        acceleration_scale=acceleration_scale, jerk_scale=jerk_scale, duration=duration,
    )


def time_parameterize_for_robot(
    path: np.ndarray | Sequence[Sequence[float]], config: RobotConfig, **options: Any
) -> TimingResult:
    """`time_parameterize` with the limits and joint names of a `RobotConfig`.

    Args:
        path: (K, dof) waypoints of the robot's arm joints [rad].
        config: `manip.RobotConfig` (velocity, acceleration, jerk and position limits,
            `arm_joints`).
        **options: any keyword of `time_parameterize` (overrides the config's values).
    """
    try:
        shape = np.asarray(path, dtype=float).shape
    except (TypeError, ValueError):
        shape = ()  # time_parameterize's own checks say what is wrong
    width = shape[-1] if len(shape) == 2 else None
    if width is not None and width != config.dof:
        raise InvalidInputError(
            f"path must have shape (K, {config.dof}): the arm joints {list(config.arm_joints)}; got {width} columns"
            + (f" (a full robot state, the gripper's last? pass path[:, :{config.dof}])" if width > config.dof else "")
        )
    kwargs = dict(
        joint_names=list(config.arm_joints),
        lower_limits=config.lower_limits,
        upper_limits=config.upper_limits,
    )
    kwargs.update(options)
    return time_parameterize(
        path, config.velocity_limits, config.acceleration_limits, config.jerk_limits, **kwargs
    )

