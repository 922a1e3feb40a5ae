"""Rotation utilities with Isaac Sim's names (`isaacsim.core.utils.rotations`), all (w, x, y, z)."""

from __future__ import annotations

import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError


def _rx(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _ry(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rz(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _angles(euler_angles, degrees: bool) -> np.ndarray:
    a = np.asarray(euler_angles, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InvalidInputError(f"euler_angles must be 3 finite angles (x, y, z); got {euler_angles!r}")
    return np.radians(a) if degrees else a


def euler_angles_to_rot_matrix(euler_angles, degrees: bool = False, extrinsic: bool = True) -> np.ndarray:
    """Rotation matrix (3, 3) of angles (x, y, z) [rad, or deg if `degrees`].

    Extrinsic (fixed axes) X then Y then Z: R = Rz(z) Ry(y) Rx(x). Intrinsic (moving
    axes) X, Y', Z'': R = Rx(x) Ry(y) Rz(z).
    """
    x, y, z = _angles(euler_angles, degrees)
    return _rz(z) @ _ry(y) @ _rx(x) if extrinsic else _rx(x) @ _ry(y) @ _rz(z)


def euler_angles_to_quat(euler_angles, degrees: bool = False, extrinsic: bool = True) -> np.ndarray:
    """Quaternion (4,) (w, x, y, z) of angles (x, y, z); see `euler_angles_to_rot_matrix`."""
    return quat.from_matrix(euler_angles_to_rot_matrix(euler_angles, degrees, extrinsic))


def rot_matrix_to_quat(mat) -> np.ndarray:
    """Quaternion (4,) (w, x, y, z) of a rotation matrix (3, 3); w >= 0."""
    R = np.asarray(mat, dtype=float)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)):
        raise InvalidInputError(f"rotation matrix must be a finite (3, 3) array; got shape {R.shape}")
    q = quat.from_matrix(R)
    return q if q[0] >= 0 else -q


def quat_to_rot_matrix(quaternion) -> np.ndarray:
    """Rotation matrix (3, 3) of a (w, x, y, z) quaternion (4,)."""
    return quat.to_matrix(quat.normalize(np.asarray(quaternion, dtype=float)))


def rot_matrix_to_euler_angles(mat, degrees: bool = False, extrinsic: bool = True) -> np.ndarray:
    """Angles (x, y, z) of a rotation matrix, inverse of `euler_angles_to_rot_matrix`.

    At the singularity (|pitch| = 90 deg) the x angle is set to 0.
    """
    R = np.asarray(mat, dtype=float)
    if extrinsic:  # R = Rz Ry Rx
        y = np.arcsin(np.clip(-R[2, 0], -1.0, 1.0))
        if abs(R[2, 0]) < 1.0 - 1e-9:
            x = np.arctan2(R[2, 1], R[2, 2])
            z = np.arctan2(R[1, 0], R[0, 0])
        else:
            x = 0.0
            z = np.arctan2(-R[0, 1], R[1, 1])
    else:  # R = Rx Ry Rz
        y = np.arcsin(np.clip(R[0, 2], -1.0, 1.0))
        if abs(R[0, 2]) < 1.0 - 1e-9:
            x = np.arctan2(-R[1, 2], R[2, 2])
            z = np.arctan2(-R[0, 1], R[0, 0])
        else:
            x = 0.0
            z = np.arctan2(R[1, 0], R[1, 1])
    out = np.array([x, y, z], dtype=float)
    return np.degrees(out) if degrees else out


def quat_to_euler_angles(quaternion, degrees: bool = False, extrinsic: bool = True) -> np.ndarray:
    """Angles (x, y, z) [rad, or deg] of a (w, x, y, z) quaternion; inverse of
    `euler_angles_to_quat`. The last entry is the yaw about world z (extrinsic)."""
    return rot_matrix_to_euler_angles(quat_to_rot_matrix(quaternion), degrees, extrinsic)


def gf_quat_to_np_array(quaternion) -> np.ndarray:
    """Isaac's USD-quaternion helper: here quaternions already are (w, x, y, z) arrays."""
    return np.asarray(quaternion, dtype=float).copy()
