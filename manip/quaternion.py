"""Quaternion helpers. Every public API of manip uses (w, x, y, z); conversions live here.

All functions accept a single quaternion (4,) or a batch (N, 4).
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError

#: Quaternions whose norm differs from 1 by more than this are rejected, not normalised.
UNIT_NORM_TOLERANCE = 1e-3


def wxyz_to_xyzw(q: np.ndarray) -> np.ndarray:
    """Reorder scalar-first (w, x, y, z) to scalar-last (x, y, z, w)."""
    q = np.asarray(q, dtype=float)
    return q[..., [1, 2, 3, 0]]


def xyzw_to_wxyz(q: np.ndarray) -> np.ndarray:
    """Reorder scalar-last (x, y, z, w) to scalar-first (w, x, y, z)."""
    q = np.asarray(q, dtype=float)
    return q[..., [3, 0, 1, 2]]


def normalize(q: np.ndarray, tolerance: float = UNIT_NORM_TOLERANCE, what: str = "quaternion") -> np.ndarray:
    """Return `q` (..., 4) scaled to unit norm (`what` names the argument in messages).

    Raises:
        InvalidInputError: if `q` is not real and finite or its norm is further than
            `tolerance` from 1 (a quaternion that far off, e.g. zero, is a bug upstream,
            not rounding drift).
    """
    q = _real(q, what)
    if q.ndim == 0 or q.shape[-1] != 4:
        raise InvalidInputError(f"{what} must have 4 components (w, x, y, z); got shape {q.shape}")
    if not np.all(np.isfinite(q)):
        raise InvalidInputError(f"{what} has non-finite components: {q}")
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    bad = np.abs(norm - 1.0) > tolerance
    if np.any(bad):
        raise InvalidInputError(
            f"{what} norm must be 1 within {tolerance} (got {norm[bad].ravel()[:5]}); "
            "quaternions are (w, x, y, z), normalise yours first"
        )
    return q / norm


def _real(q, what: str) -> np.ndarray:
    """`q` as a float array; complex, boolean or non-numeric entries raise (naming `what`)."""
    try:
        a = np.asarray(q)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{what} must be an array of real numbers; got {q!r}") from exc
    if a.dtype.kind not in "iuf":
        try:
            ok = a.dtype.kind == "O" and all(isinstance(v, (int, float, np.integer, np.floating))
                                            and not isinstance(v, bool) for v in a.flat)
        except TypeError:
            ok = False
        if not ok:
            raise InvalidInputError(f"{what} must be an array of real numbers; got {a.dtype.name} values {q!r}")
    return a.astype(float)


def multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a * b of (w, x, y, z) quaternions, broadcasting over leading axes."""
    aw, ax, ay, az = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    bw, bx, by, bz = np.moveaxis(np.asarray(b, dtype=float), -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def conjugate(q: np.ndarray) -> np.ndarray:
    """Conjugate (the inverse of a unit quaternion)."""
    q = np.asarray(q, dtype=float)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of unit (w, x, y, z) quaternions (..., 4)."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )


def from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit (w, x, y, z) quaternions (..., 4) with w >= 0 of rotation matrices (..., 3, 3).

    Shepperd's method: pick the largest of w, x, y, z to divide by, for stability.
    """
    R = np.asarray(R, dtype=float)
    batch = R.shape[:-2]
    R = R.reshape(-1, 3, 3)
    m00, m11, m22 = R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]
    trace = m00 + m11 + m22
    cand = np.stack([trace, m00, m11, m22], axis=-1)
    k = np.argmax(cand, axis=-1)
    q = np.empty((R.shape[0], 4))
    for case in range(4):
        idx = k == case
        if not np.any(idx):
            continue
        r = R[idx]
        if case == 0:
            s = np.sqrt(1.0 + trace[idx]) * 2
            q[idx] = np.stack([0.25 * s, (r[:, 2, 1] - r[:, 1, 2]) / s, (r[:, 0, 2] - r[:, 2, 0]) / s, (r[:, 1, 0] - r[:, 0, 1]) / s], -1)
        elif case == 1:
            s = np.sqrt(1.0 + r[:, 0, 0] - r[:, 1, 1] - r[:, 2, 2]) * 2
            q[idx] = np.stack([(r[:, 2, 1] - r[:, 1, 2]) / s, 0.25 * s, (r[:, 0, 1] + r[:, 1, 0]) / s, (r[:, 0, 2] + r[:, 2, 0]) / s], -1)
        elif case == 2:
            s = np.sqrt(1.0 + r[:, 1, 1] - r[:, 0, 0] - r[:, 2, 2]) * 2
            q[idx] = np.stack([(r[:, 0, 2] - r[:, 2, 0]) / s, (r[:, 0, 1] + r[:, 1, 0]) / s, 0.25 * s, (r[:, 1, 2] + r[:, 2, 1]) / s], -1)
        else:
            s = np.sqrt(1.0 + r[:, 2, 2] - r[:, 0, 0] - r[:, 1, 1]) * 2
            q[idx] = np.stack([(r[:, 1, 0] - r[:, 0, 1]) / s, (r[:, 0, 2] + r[:, 2, 0]) / s, (r[:, 1, 2] + r[:, 2, 1]) / s, 0.25 * s], -1)
    q *= np.where(q[:, :1] < 0, -1.0, 1.0)
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return q.reshape(*batch, 4)


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] in [0, pi] taking unit quaternion `a` to `b` (sign-invariant)."""
    d = np.abs(np.sum(np.asarray(a, dtype=float) * np.asarray(b, dtype=float), axis=-1))
    return 2.0 * np.arccos(np.clip(d, -1.0, 1.0))


def from_axis_angle(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Quaternion (w, x, y, z) of a rotation by `angle` [rad] about unit `axis` (3,) (or
    broadcast batches: axis (..., 3), angle (...)).

    Raises:
        InvalidInputError: `axis` not 3 real finite components of norm within
            `UNIT_NORM_TOLERANCE` of 1 (a zero or unnormalised axis would give a quaternion
            that is not a rotation), or `angle` not real and finite.
    """
    axis = _real(axis, "axis")
    angle = _real(angle, "angle")
    if axis.ndim == 0 or axis.shape[-1] != 3:
        raise InvalidInputError(f"axis must have 3 components (x, y, z); got shape {axis.shape}")
    if not (np.all(np.isfinite(axis)) and np.all(np.isfinite(angle))):
        raise InvalidInputError(f"axis and angle must be finite; got axis {axis}, angle {angle}")
    n = np.linalg.norm(axis, axis=-1)
    if np.any(np.abs(n - 1.0) > UNIT_NORM_TOLERANCE):
        raise InvalidInputError(f"axis must be a unit vector (norm within {UNIT_NORM_TOLERANCE:g} of 1); got {axis} "
                                f"of norm {n}: pass axis / |axis|")
    half = 0.5 * angle[..., None]
    return np.concatenate([np.cos(half), np.sin(half) * axis], axis=-1)
