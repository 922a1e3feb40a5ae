"""Rotation utilities with Isaac Sim's names, all quaternions (w, x, y, z): the single-rotation
ones of `isaacsim.core.utils.rotations` and the batched ones of `isaacsim.core.utils.numpy.rotations`
(`euler_angles_to_quats`, ...: (N, 3) / (N, 4) / (N, 3, 3) in and out, or one (3,) / (4,) / (3, 3))."""

from __future__ import annotations

import numpy as np

from manip import quaternion as qmath
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
    return qmath.from_matrix(euler_angles_to_rot_matrix(euler_angles, degrees, extrinsic))


def rot_matrix_to_quat(mat) -> np.ndarray:
    """Quaternion (4,) (w, x, y, z) of a rotation matrix (3, 3); w >= 0."""
    R = np.asarray(mat, dtype=float)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)):
        raise InvalidInputError(f"rotation matrix must be a finite (3, 3) array; got shape {R.shape}")
    q = qmath.from_matrix(R)
    return q if q[0] >= 0 else -q


def quat_to_rot_matrix(quat) -> np.ndarray:
    """Rotation matrix (3, 3) of a (w, x, y, z) quaternion (4,) (Isaac's argument name `quat`)."""
    return qmath.to_matrix(qmath.normalize(np.asarray(quat, dtype=float)))


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


def quat_to_euler_angles(quat, degrees: bool = False, extrinsic: bool = True) -> np.ndarray:
    """Angles (x, y, z) [rad, or deg] of a (w, x, y, z) quaternion `quat` (4,); inverse of
    `euler_angles_to_quat`. The last entry is the yaw about world z (extrinsic)."""
    return rot_matrix_to_euler_angles(quat_to_rot_matrix(quat), degrees, extrinsic)


def gf_quat_to_np_array(quaternion) -> np.ndarray:
    """Isaac's USD-quaternion helper: here quaternions already are (w, x, y, z) arrays."""
    return np.asarray(quaternion, dtype=float).copy()


def _batch(values, width: tuple[int, ...], what: str) -> tuple[np.ndarray, bool]:
    """`values` as a finite float array (N, *width) and whether it was one item (*width)."""
    a = np.asarray(values, dtype=float)
    single = a.shape == width
    if not single and (a.ndim != len(width) + 1 or a.shape[1:] != width):
        raise InvalidInputError(f"{what} must have shape {width} or (N, {', '.join(map(str, width))}); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite; got {values!r}")
    return (a[None] if single else a), single


def _axis_matrices(angles: np.ndarray, axis: int) -> np.ndarray:
    """Rotations (N, 3, 3) by `angles` (N,) [rad] about coordinate axis 0, 1 or 2."""
    c, s = np.cos(angles), np.sin(angles)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = np.zeros((len(angles), 3, 3))
    R[:, axis, axis] = 1.0
    R[:, i, i], R[:, i, j], R[:, j, i], R[:, j, j] = c, -s, s, c
    return R


def euler_angles_to_quats(euler_angles, degrees: bool = False, extrinsic: bool = True, device=None) -> np.ndarray:
    """Quaternions (N, 4) of angles (N, 3) (x, y, z) [rad, or deg] (one (3,) gives (4,));
    the conventions of `euler_angles_to_rot_matrix`. `device` is Isaac's and ignored (NumPy)."""
    a, single = _batch(euler_angles, (3,), "euler_angles")
    a = np.radians(a) if degrees else a
    rx, ry, rz = (_axis_matrices(a[:, k], k) for k in range(3))
    q = qmath.from_matrix(rz @ ry @ rx if extrinsic else rx @ ry @ rz)
    return q[0] if single else q


def quats_to_rot_matrices(quaternions, device=None) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of unit (w, x, y, z) quaternions (N, 4) (one (4,) gives (3, 3))."""
    q, single = _batch(quaternions, (4,), "quaternions")
    R = qmath.to_matrix(qmath.normalize(q, what="quaternions"))
    return R[0] if single else R


def rot_matrices_to_quats(rotation_matrices, device=None) -> np.ndarray:
    """Quaternions (N, 4) (w, x, y, z), w >= 0, of rotation matrices (N, 3, 3) (one (3, 3) gives (4,))."""
    R, single = _batch(rotation_matrices, (3, 3), "rotation_matrices")
    q = qmath.from_matrix(R)
    return q[0] if single else q


def quats_to_euler_angles(quaternions, degrees: bool = False, extrinsic: bool = True, device=None) -> np.ndarray:
    """Angles (N, 3) (x, y, z) [rad, or deg] of quaternions (N, 4); inverse of `euler_angles_to_quats`."""
    q, single = _batch(quaternions, (4,), "quaternions")
    out = np.array([quat_to_euler_angles(qi, degrees, extrinsic) for qi in q])
    return out[0] if single else out


def rotvecs_to_quats(rotation_vectors, degrees: bool = False, device=None) -> np.ndarray:
    """Quaternions (N, 4) of rotation vectors (N, 3) (axis times angle [rad, or deg])."""
    v, single = _batch(rotation_vectors, (3,), "rotation_vectors")
    v = np.radians(v) if degrees else v
    angle = np.linalg.norm(v, axis=-1)
    axis = np.divide(v, angle[:, None], out=np.tile([0.0, 0.0, 1.0], (len(v), 1)), where=angle[:, None] > 0)  # any axis at 0
    q = qmath.from_axis_angle(axis, angle)
    return q[0] if single else q


def quats_to_rotvecs(quaternions, device=None) -> np.ndarray:
    """Rotation vectors (N, 3) (axis times angle [rad], angle in [0, pi]) of quaternions (N, 4)."""
    q, single = _batch(quaternions, (4,), "quaternions")
    q = qmath.normalize(q, what="quaternions")
    q = q * np.where(q[:, :1] < 0, -1.0, 1.0)
    s = np.linalg.norm(q[:, 1:], axis=-1)
    angle = 2.0 * np.arctan2(s, q[:, 0])
    v = np.divide(q[:, 1:] * angle[:, None], s[:, None], out=np.zeros((len(q), 3)), where=s[:, None] > 0)
    return v[0] if single else v


def deg2rad(degree_value, device=None) -> np.ndarray:
    """Degrees to radians (any shape)."""
    return np.deg2rad(degree_value)


def rad2deg(radian_value, device=None) -> np.ndarray:
    """Radians to degrees (any shape)."""
    return np.rad2deg(radian_value)


def xyzw2wxyz(q, ret_torch: bool = False) -> np.ndarray:
    """Scalar-last (..., 4) quaternions to scalar-first (Isaac's name for `manip.quaternion.xyzw_to_wxyz`)."""
    return qmath.xyzw_to_wxyz(q)


def wxyz2xyzw(q, ret_torch: bool = False) -> np.ndarray:
    """Scalar-first (..., 4) quaternions to scalar-last (Isaac's name for `manip.quaternion.wxyz_to_xyzw`)."""
    return qmath.wxyz_to_xyzw(q)
