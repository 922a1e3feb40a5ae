"""Argument checks shared by the whole package: each returns the clean value or raises.

Caller errors raise `InvalidInputError` with what was wrong and what is valid; nothing is
silently clamped or coerced. `what` names the argument in the message (e.g. "time_budget").
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError

#: The largest number of samples a trajectory (or a sampled motion) may have: requests
#: that would produce more (a tiny `dt`, a huge `duration`, a tiny `velocity_scale`, a
#: tiny `linear_step`) raise InvalidInputError naming the argument instead of allocating
#: gigabytes or running for minutes. 100,000 samples are 27 min of motion at 60 Hz, or
#: 100 s at 1 kHz (22 MB of positions, velocities, accelerations and jerks for 7 joints).
MAX_SAMPLES = 100_000


def _number(value, what: str, expected: str) -> float:
    """A real number (int, float, NumPy real scalar or 0-d array) as a float; bools, complex
    numbers, strings and anything else raise InvalidInputError naming `what`."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InvalidInputError(f"{what} must be {expected}; got {value!r} ({type(value).__name__})")
    return float(value)


def positive(value, what: str, unit: str = "") -> float:
    """`value` as a positive finite float."""
    expected = f"a positive finite number{_unit(unit)}"
    v = _number(value, what, expected)
    if not np.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{what} must be {expected}; got {value!r}")
    return v


def non_negative(value, what: str, unit: str = "") -> float:
    """`value` as a finite float >= 0."""
    expected = f"a finite number >= 0{_unit(unit)}"
    v = _number(value, what, expected)
    if not np.isfinite(v) or v < 0:
        raise InvalidInputError(f"{what} must be {expected}; got {value!r}")
    return v


def fraction(value, what: str) -> float:
    """`value` as a float in (0, 1] (a scale factor)."""
    v = _number(value, what, "a number in (0, 1]")
    if not (np.isfinite(v) and 0.0 < v <= 1.0):
        raise InvalidInputError(f"{what} must be a number in (0, 1]; got {value!r}")
    return v


def integer(value, what: str, minimum: int | None = None) -> int:
    """`value` as an int (Python or NumPy integer; bools and floats such as 1.5 or 2.0 raise)."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    bound = "" if minimum is None else f" >= {minimum}"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise InvalidInputError(f"{what} must be an integer{bound}; got {value!r} ({type(value).__name__})")
    if minimum is not None and value < minimum:
        raise InvalidInputError(f"{what} must be an integer{bound}; got {value!r}")
    return int(value)


def flag(value, what: str) -> bool:
    """A boolean argument: True/False (or a NumPy bool); 1, "no", None and the like raise."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"{what} must be True or False; got {value!r}")
    return bool(value)


def as_real_array(value, what: str) -> np.ndarray:
    """`value` as a float array; complex, boolean, string or object entries (None, ragged
    nested lists) raise InvalidInputError naming `what` (NumPy would drop an imaginary part
    or say "could not convert string to float")."""
    if isinstance(value, np.ndarray):
        a = value
    else:
        try:
            a = np.asarray(value)
        except (TypeError, ValueError) as exc:  # ragged nested sequences
            raise InvalidInputError(f"{what} must be an array of real numbers; got {_short(value)} ({exc})") from exc
    if a.dtype.kind in "iuf":
        return a.astype(float, copy=False)
    if a.dtype.kind == "O":
        try:
            if all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) for v in a.flat):
                return a.astype(float)
        except TypeError:
            pass
    kind = {"c": "complex", "b": "boolean", "U": "string", "S": "bytes", "O": "non-numeric"}.get(a.dtype.kind, a.dtype.name)
    hint = ""
    if a.ndim == 0 and hasattr(value, "position"):  # cuRobo's JointState (or a Pose-like object)
        hint = (" (it has a .position, as cuRobo's JointState: pass the configuration itself as a NumPy array, "
                "e.g. js.position[0], with .cpu().numpy() for a torch tensor)")
    raise InvalidInputError(f"{what} must be an array of real numbers; got {kind} values {_short(value)}{hint}")


def sample_count(duration: float, dt: float, what: str = "dt") -> int:
    """Number of samples of a motion of `duration` [s] sampled every `dt` [s] (ends included).

    Raises:
        InvalidInputError: more than `MAX_SAMPLES`; the message names `what` (the argument
            the caller should change).
    """
    n = math.ceil(duration / dt - 1e-9) + 1 if duration > 0 else 1
    if n > MAX_SAMPLES:
        raise InvalidInputError(
            f"{what}: a {duration:.6g} s motion sampled every {dt:.6g} s would have {n} samples; "
            f"the maximum is {MAX_SAMPLES} (manip.validation.MAX_SAMPLES)"
        )
    return n


def vec(value, n: int, what: str) -> np.ndarray:
    """`value` as a finite float array of shape (n,) (a copy)."""
    a = as_real_array(value, what)
    if a.shape == () and n == 1:
        a = a.reshape(1)
    if a.shape != (n,):
        raise InvalidInputError(f"{what} must have shape ({n},); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite; got {a}")
    return a.copy()


def per_joint(value, dof: int, what: str, *, positive: bool) -> np.ndarray:
    """(dof,) finite values, one per joint; a scalar is used for every joint."""
    a = np.array(as_real_array(value, what), dtype=float)
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
    a = as_real_array(value, what)
    if a.shape == ():
        a = np.full(3, float(a))
    a = vec(a, 3, what)
    if np.any(a <= 0):
        raise InvalidInputError(f"{what} must be positive; got {a}")
    return a


def unit_quat(value, what: str = "orientation") -> np.ndarray:
    """A (w, x, y, z) quaternion, normalised (norm must be within 1e-3 of 1)."""
    a = as_real_array(value, what)
    if a.shape != (4,):
        raise InvalidInputError(f"{what} must be a (w, x, y, z) quaternion of shape (4,); got {a.shape}")
    return quat.normalize(a, what=what)


def batch(value, n_rows: int, n: int, what: str) -> np.ndarray:
    """A finite (n_rows, n) array; a single (n,) row is broadcast."""
    a = as_real_array(value, what)
    if a.shape == (n,):
        a = np.broadcast_to(a, (n_rows, n))
    if a.shape != (n_rows, n):
        raise InvalidInputError(f"{what} must have shape ({n_rows}, {n}); got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(f"{what} must be finite")
    return np.array(a)


def _unit(unit: str) -> str:
    return f" [{unit}]" if unit else ""


def _short(value, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + "..."
