"""Argument checks shared by the simulation classes (caller errors raise InvalidInputError)."""

from __future__ import annotations

import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError


def vec(value, n: int, what: str) -> np.ndarray:
    """`value` as a finite float array of shape (n,)."""
    a = np.asarray(value, dtype=float)
    if a.shape == () and n == 1:
        a = a.reshape(1)
    if a.shape != (n,):
        raise InvalidInputError(f"{what} must have shape ({n},); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite; got {a}")
    return a.copy()


def scale3(value, what: str = "scale") -> np.ndarray:
    """A scale given as a scalar or (3,), positive."""
    a = np.asarray(value, dtype=float)
    if a.shape == ():
        a = np.full(3, float(a))
    a = vec(a, 3, what)
    if np.any(a <= 0):
        raise InvalidInputError(f"{what} must be positive; got {a}")
    return a


def positive(value, what: str) -> float:
    v = float(value)
    if not np.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{what} must be a positive finite number; got {value!r}")
    return v


def unit_quat(value, what: str = "orientation") -> np.ndarray:
    """A (w, x, y, z) quaternion, normalised (norm must be within 1e-3 of 1)."""
    a = np.asarray(value, dtype=float)
    if a.shape != (4,):
        raise InvalidInputError(f"{what} must be a (w, x, y, z) quaternion of shape (4,); got {a.shape}")
    return quat.normalize(a)


def batch(value, n_rows: int, n: int, what: str) -> np.ndarray:
    """A finite (n_rows, n) array; a single (n,) row is broadcast."""
    a = np.asarray(value, dtype=float)
    if a.shape == (n,):
        a = np.broadcast_to(a, (n_rows, n))
    if a.shape != (n_rows, n):
        raise InvalidInputError(f"{what} must have shape ({n_rows}, {n}); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite")
    return np.array(a)
