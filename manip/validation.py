"""Argument checks shared by the whole package: each returns the clean value or raises.

Caller errors raise `InvalidInputError` with what was wrong and what is valid; nothing is
silently clamped or coerced. `what` names the argument in the message (e.g. "time_budget").
"""

from __future__ import annotations

import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError


def positive(value, what: str, unit: str = "") -> float:
    """`value` as a positive finite float."""
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{what} must be a positive finite number{_unit(unit)}; got {value!r}") from exc
    if not np.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{what} must be a positive finite number{_unit(unit)}; got {value!r}")
    return v


def non_negative(value, what: str, unit: str = "") -> float:
    """`value` as a finite float >= 0."""
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{what} must be a finite number >= 0{_unit(unit)}; got {value!r}") from exc
    if not np.isfinite(v) or v < 0:
        raise InvalidInputError(f"{what} must be a finite number >= 0{_unit(unit)}; got {value!r}")
    return v


def fraction(value, what: str) -> float:
    """`value` as a float in (0, 1] (a scale factor)."""
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{what} must be a number in (0, 1]; got {value!r}") from exc
    if not (np.isfinite(v) and 0.0 < v <= 1.0):
        raise InvalidInputError(f"{what} must be a number in (0, 1]; got {value!r}")
    return v


def vec(value, n: int, what: str) -> np.ndarray:
    """`value` as a finite float array of shape (n,) (a copy)."""
    a = np.asarray(value, dtype=float)
    if a.shape == () and n == 1:
        a = a.reshape(1)
    if a.shape != (n,):
        raise InvalidInputError(f"{what} must have shape ({n},); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite; got {a}")
    return a.copy()


def per_joint(value, dof: int, what: str, *, positive: bool) -> np.ndarray:
    """(dof,) finite values, one per joint; a scalar is used for every joint."""
    a = np.array(value, dtype=float)
    if a.ndim == 0:
        a = np.full(dof, float(a))
    if a.shape != (dof,):
        raise InvalidInputError(f"{what} must have shape ({dof},) (one per joint); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} has non-finite entries: {a}")
    if positive and np.any(a <= 0):
        raise InvalidInputError(f"{what} must be > 0; got {a}")
    return a


def scale3(value, what: str = "scale") -> np.ndarray:
    """A scale given as a scalar or (3,), positive."""
    a = np.asarray(value, dtype=float)
    if a.shape == ():
        a = np.full(3, float(a))
    a = vec(a, 3, what)
    if np.any(a <= 0):
        raise InvalidInputError(f"{what} must be positive; got {a}")
    return a


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


def _unit(unit: str) -> str:
    return f" [{unit}]" if unit else ""
