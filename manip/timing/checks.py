"""Input validation shared by both timing algorithms (caller errors raise `InvalidInputError`)."""

from __future__ import annotations

from typing import Any, NamedTuple, Sequence

import numpy as np

from manip.errors import InvalidInputError
from manip.limits import JointLimits
from manip.validation import fraction, non_negative, per_joint, positive

#: The timing modes: stop at every corner, round the corners, one motion along a spline.
MODES = ("exact", "blend", "along_path")

# Position limits are checked to within this round-off [rad] (a motion along a segment that
# ends exactly on a limit computes its end as start + direction * length).
POSITION_ROUNDOFF = 1e-12


class Checked(NamedTuple):
    """Validated inputs of a timing call."""

    path: np.ndarray  #: (K, dof) waypoints [rad] (a copy)
    #: the scaled velocity, acceleration and jerk limits, the joint names and the position
    #: limits widened by the tolerance (None: unbounded)
    limits: JointLimits


def check_mode(mode: Any) -> str:
    """`mode` if it is one of `MODES`."""
    if mode not in MODES:
        valid = ", ".join(repr(m) for m in MODES)
        raise InvalidInputError(f"mode must be one of {valid}; got {mode!r}")
    return mode


def check_deviation_tolerance(value: Any, optional: bool = False) -> float | None:
    """A deviation tolerance [rad] >= 0 (None passes through when `optional`)."""
    if optional:
        return None if value is None else non_negative(value, "deviation_tolerance (or None)", "rad")
    return non_negative(value, "deviation_tolerance", "rad")


def check_inputs(
    path: Any,
    velocity_limits: Any,
    acceleration_limits: Any,
    jerk_limits: Any,
    dt: float,
    joint_names: Sequence[str] | None,
    lower_limits: Any,
    upper_limits: Any,
    position_tolerance: float,
    velocity_scale: float,
    acceleration_scale: float,
    jerk_scale: float,
    duration: float | None,
) -> Checked:
    """Validated inputs (the arguments of `time_parameterize`); limits scaled, position limits widened.

    Raises:
        InvalidInputError: wrong shapes, non-finite values, non-positive limits, scales
            outside (0, 1], dt <= 0, negative tolerance or duration, waypoints outside the
            position limits (widened by `position_tolerance`).
    """
    w = np.array(path, dtype=float)
    if w.ndim != 2 or w.shape[0] < 1 or w.shape[1] < 1:
        raise InvalidInputError(f"path must have shape (K, dof) with K >= 1; got {w.shape}")
    if not np.all(np.isfinite(w)):
        bad = np.argwhere(~np.isfinite(w))[0]
        raise InvalidInputError(f"path has a non-finite value at waypoint {bad[0]}, joint {bad[1]}")
    dof = w.shape[1]
    vmax = per_joint(velocity_limits, dof, "velocity_limits", positive=True) * fraction(
        velocity_scale, "velocity_scale"
    )
    amax = per_joint(acceleration_limits, dof, "acceleration_limits", positive=True) * fraction(
        acceleration_scale, "acceleration_scale"
    )
    jmax = per_joint(jerk_limits, dof, "jerk_limits", positive=True) * fraction(jerk_scale, "jerk_scale")
    positive(dt, "dt", "s")
    non_negative(position_tolerance, "position_tolerance", "rad")
    if duration is not None:
        non_negative(duration, "duration (or None)", "s")
    names = tuple(joint_names) if joint_names is not None else tuple(f"joint_{i}" for i in range(dof))
    if len(names) != dof:
        raise InvalidInputError(f"joint_names has {len(names)} names for {dof} joints")
    lower = upper = None
    if (lower_limits is None) != (upper_limits is None):
        raise InvalidInputError("give both lower_limits and upper_limits, or neither")
    if lower_limits is not None:
        lower = per_joint(lower_limits, dof, "lower_limits", positive=False) - position_tolerance - POSITION_ROUNDOFF
        upper = per_joint(upper_limits, dof, "upper_limits", positive=False) + position_tolerance + POSITION_ROUNDOFF
        if np.any(lower > upper):
            raise InvalidInputError(f"lower_limits must be <= upper_limits; got {lower_limits}, {upper_limits}")
        outside = np.argwhere((w < lower) | (w > upper))
        if outside.size:
            i, jj = outside[0]
            raise InvalidInputError(
                f"path waypoint {i} joint {jj} ({names[jj]}) = {w[i, jj]:.6f} rad is outside the position "
                f"limits [{lower_limits[jj]:.6f}, {upper_limits[jj]:.6f}] (+- {position_tolerance} rad); "
                f"{len(outside)} violation(s) in total"
            )
    return Checked(w, JointLimits(velocity=vmax, acceleration=amax, jerk=jmax, lower=lower, upper=upper,
                                  joint_names=names))
