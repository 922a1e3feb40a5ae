"""Isaac's `omni.isaac.core.utils.distance_metrics` (`isaacsim.core.utils.distance_metrics`):
distances between translations and rotations, as a task's `is_done` or a controller compares
an end effector's pose with its target.

Translations are (3,) vectors or (4, 4) transforms (their `[:3, 3]`); rotations are (3, 3)
matrices or (4, 4) transforms (their `[:3, :3]`), column-major as Isaac's NumPy matrices
(`manip.sim.tf_matrix_from_pose`). Bad shapes raise (Isaac logs an error and goes on).
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError


def _translation(t, what: str) -> np.ndarray:
    a = np.asarray(t, dtype=float)
    if a.shape == (4, 4):
        a = a[:3, 3]
    a = a.reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be a translation (3,) or a transform (4, 4); got shape {np.shape(t)}")
    return a


def _rotation(r, what: str) -> np.ndarray:
    a = np.asarray(r, dtype=float)
    if a.shape == (4, 4):
        a = a[:3, :3]
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be a rotation matrix (3, 3) or a transform (4, 4); got shape "
                                f"{np.shape(r)}")
    return a


def weighted_translational_distance(t1, t2, weight_matrix=None) -> float:
    """sqrt(x^T W x) [m] with x = t1 - t2 and W (3, 3) positive semidefinite (default identity:
    the Euclidean distance); W = R^T diag(w) R weights the axes of the frame R (3, 3)."""
    x = _translation(t1, "t1") - _translation(t2, "t2")
    W = np.eye(3) if weight_matrix is None else np.asarray(weight_matrix, dtype=float)
    if W.shape != (3, 3) or not np.all(np.isfinite(W)):
        raise InvalidInputError(f"weight_matrix must be a finite (3, 3) matrix; got shape {W.shape}")
    value = float(x @ W @ x)
    if value < -1e-12:
        raise InvalidInputError(f"weight_matrix must be positive semidefinite: x^T W x = {value:g} < 0")
    return float(np.sqrt(max(value, 0.0)))


def rotational_distance_angle(r1, r2) -> float:
    """The angle [rad] of the rotation from r2 to r1 (of r1 r2^T), in [0, pi]."""
    R = _rotation(r1, "r1") @ _rotation(r2, "r2").T
    return float(np.arccos(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)))


def rotational_distance_identity_matrix_deviation(r1, r2) -> float:
    """The Frobenius norm of I - r1 r2^T (0 for equal rotations, 2 sqrt(2) at most)."""
    return float(np.linalg.norm(np.eye(3) - _rotation(r1, "r1") @ _rotation(r2, "r2").T))


def rotational_distance_single_axis(r1, r2, axis) -> float:
    """The angle [rad] between `axis` (3,) turned by r1 and by r2 (e.g. how far a held cup's z
    axis leans from the world's)."""
    a = np.asarray(axis, dtype=float)
    norm = np.linalg.norm(a) if a.shape == (3,) else 0.0
    if not np.isfinite(norm) or norm < 1e-12:
        raise InvalidInputError(f"axis must be a non-zero finite 3-vector; got {axis!r}")
    a = a / norm
    return float(np.arccos(np.clip((_rotation(r1, "r1") @ a) @ (_rotation(r2, "r2") @ a), -1.0, 1.0)))
