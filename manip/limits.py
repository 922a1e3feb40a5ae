"""`JointLimits`: a robot's joint limits as one validated, read-only record.

Built once by `RobotConfig` (`config.limits`) and passed whole to kinematics, timing
(`timing.time_path`), planning, the trajectory optimiser and the reactive controller, instead
of loose (velocity, acceleration, jerk) arrays. A call's scaled limits are
`limits.scaled(velocity, acceleration)`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.validation import fraction, per_joint

__all__ = ["JointLimits"]


@dataclass(frozen=True, eq=False)
class JointLimits:
    """Position, velocity, acceleration and jerk limits of a robot's joints.

    Validated once at construction; the arrays are read-only copies, so a `JointLimits` can
    be shared by every part of a plan (and between threads).

    Attributes:
        velocity: (dof,) max |velocity| [rad/s] (a scalar given is used for every joint).
        acceleration: (dof,) max |acceleration| [rad/s^2] (or a scalar).
        jerk: (dof,) max |jerk| [rad/s^3] (or a scalar).
        lower: (dof,) lower position limits [rad]; None (with `upper`) = unbounded.
        upper: (dof,) upper position limits [rad]; None (with `lower`) = unbounded.
        joint_names: (dof,) names; None gives "joint_0", "joint_1", ...

    The number of joints is `len(joint_names)` when given, else the length of the first
    (dof,) array among the limits.

    Raises:
        InvalidInputError: wrong shapes, non-finite or non-positive limits, only one of
            `lower` / `upper`, `lower > upper`, or scalars only and no `joint_names`.
    """

    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    lower: np.ndarray | None = None
    upper: np.ndarray | None = None
    joint_names: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        kind = type(self).__name__
        dof = self._dof()
        for name in ("velocity", "acceleration", "jerk"):
            object.__setattr__(self, name, _frozen(per_joint(getattr(self, name), dof, f"{kind}.{name}",
                                                             positive=True)))
        if (self.lower is None) != (self.upper is None):
            raise InvalidInputError(f"{kind}: give both lower and upper, or neither")
        if self.lower is not None:
            lower = per_joint(self.lower, dof, f"{kind}.lower", positive=False)
            upper = per_joint(self.upper, dof, f"{kind}.upper", positive=False)
            if np.any(lower > upper):
                raise InvalidInputError(f"{kind}.lower must be <= upper; got {lower}, {upper}")
            object.__setattr__(self, "lower", _frozen(lower))
            object.__setattr__(self, "upper", _frozen(upper))
        names = (
            tuple(str(n) for n in self.joint_names)
            if self.joint_names is not None
            else tuple(f"joint_{i}" for i in range(dof))
        )
        object.__setattr__(self, "joint_names", names)

    def _dof(self) -> int:
        if self.joint_names is not None:
            return len(tuple(self.joint_names))
        for value in (self.velocity, self.acceleration, self.jerk, self.lower, self.upper):
            if value is not None and np.ndim(value) == 1:
                return int(np.size(value))
        raise InvalidInputError(
            f"{type(self).__name__} needs joint_names or at least one (dof,) array of limits to know the number "
            "of joints"
        )

    @property
    def dof(self) -> int:
        """Number of joints."""
        return len(self.joint_names)

    @classmethod
    def from_robot(cls, config: Any) -> JointLimits:
        """The limits and arm joint names of a `manip.RobotConfig` (the same as `config.limits`;
        `RobotConfig` builds its limits, so this module does not import it)."""
        return config.limits

    def scaled(self, velocity: float = 1.0, acceleration: float = 1.0, *, jerk: float = 1.0) -> JointLimits:
        """These limits with the velocity, acceleration and jerk limits times factors in (0, 1]
        (a call's `velocity_scale`, `acceleration_scale`, `jerk_scale`); positions unchanged.

        Raises:
            InvalidInputError: a factor outside (0, 1].
        """
        factors = (fraction(velocity, "velocity"), fraction(acceleration, "acceleration"), fraction(jerk, "jerk"))
        if factors == (1.0, 1.0, 1.0):
            return self
        return JointLimits(velocity=self.velocity * factors[0], acceleration=self.acceleration * factors[1],
                           jerk=self.jerk * factors[2], lower=self.lower, upper=self.upper,
                           joint_names=self.joint_names)


def _frozen(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a
