"""End-effector targets as the controller accepts them.

A target is given in the robot base frame as one of:

- a `Pose` (position and orientation);
- a position (3,) [m]: position only, the orientation floats for that target;
- a cuRobo pose (7,) [x, y, z, qw, qx, qy, qz];
- a homogeneous transform (4, 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.validation import as_real_array

_FORMS = "a Pose, a position [x, y, z], [x, y, z, qw, qx, qy, qz] or a 4x4 transform"


@dataclass(frozen=True)
class Target:
    """A checked target: position (3,) [m] and orientation (4,) (w, x, y, z) or None
    (position only)."""

    position: np.ndarray
    orientation: np.ndarray | None

    @property
    def position_only(self) -> bool:
        return self.orientation is None


def as_target(value, what: str = "target") -> Target:
    """A `Target` from any accepted form.

    Raises:
        InvalidInputError: another shape, non-finite values, a quaternion that is not of
            unit norm, a rotation block that is not a rotation; the message names `what`.
    """
    if isinstance(value, Target):
        return value
    if isinstance(value, Pose):
        if value.is_batch:
            raise InvalidInputError(f"{what} must be a single pose; got a batch of {len(value)}")
        return Target(np.array(value.position, dtype=float), np.array(value.quaternion, dtype=float))
    if value is None:
        raise InvalidInputError(f"{what} must be {_FORMS}; got None")
    try:
        a = as_real_array(value, what)
    except InvalidInputError as exc:
        raise InvalidInputError(f"{what} must be {_FORMS}; got {value!r}") from exc
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} has non-finite values (NaN or inf): {a.tolist()}")
    if a.shape == (3,):
        return Target(a.astype(float).copy(), None)
    if a.shape == (7,):
        return Target(a[:3].astype(float).copy(), quat.normalize(a[3:], what=f"{what} quaternion"))
    if a.shape == (4, 4):
        R = a[:3, :3]
        if np.abs(R @ R.T - np.eye(3)).max() > 1e-4 or np.linalg.det(R) < 0 or np.abs(a[3] - [0, 0, 0, 1]).max() > 1e-9:
            raise InvalidInputError(f"{what}: a 4x4 target must be a rigid transform (rotation block orthonormal, "
                                    "last row [0, 0, 0, 1])")
        return Target(a[:3, 3].astype(float).copy(), quat.from_matrix(R))
    raise InvalidInputError(f"{what} must be {_FORMS}; got an array of shape {a.shape}")
