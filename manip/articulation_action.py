"""`ArticulationAction`: joint targets for a simulated articulation (Isaac Sim's semantics).

It lives at the bottom layer so that planning results can be turned into actions without
importing the simulator; `manip.sim` re-exports it.
"""

from __future__ import annotations

import numbers
from typing import Sequence

import numpy as np

from manip.errors import InvalidInputError


def _field(values, name: str) -> np.ndarray | None:
    """A target field as a float array (K,): None entries become NaN; anything that is not a
    real number (strings, complex, booleans) or an infinite value raises, naming the field."""
    if values is None:
        return None
    if isinstance(values, np.ndarray) and values.dtype.kind in "iuf":  # the common case, no per-entry loop
        out = values.astype(float).ravel()
        if np.any(np.isinf(out)):
            raise InvalidInputError(f"ArticulationAction.{name} has infinite entries: {out}")
        return out
    try:
        flat = np.ravel(np.asarray(values, dtype=object))
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"ArticulationAction.{name} must be a sequence of numbers; got {values!r}") from exc
    out = np.empty(flat.size)
    for k, v in enumerate(flat):
        if v is None:
            out[k] = np.nan
        elif isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
            raise InvalidInputError(
                f"ArticulationAction.{name}[{k}] must be a real number or None; got {v!r} ({type(v).__name__})"
            )
        else:
            out[k] = float(v)
    if np.any(np.isinf(out)):
        raise InvalidInputError(f"ArticulationAction.{name} has infinite entries: {out}")
    return out


def _indices(values) -> np.ndarray | None:
    """Joint indices as an int array (K,): non-negative integers (integral floats such as 2.0
    are accepted; 0.7 is not silently truncated)."""
    if values is None:
        return None
    try:
        a = np.ravel(np.asarray(values))
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"ArticulationAction.joint_indices must be integers; got {values!r}") from exc
    if a.dtype.kind in "iu":
        idx = a.astype(np.int64)
    elif a.dtype.kind == "f" and np.all(np.isfinite(a)) and np.all(a == np.round(a)):
        idx = a.astype(np.int64)
    elif a.dtype.kind == "O" and all(isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_)) for v in a):
        idx = a.astype(np.int64)
    else:
        raise InvalidInputError(f"ArticulationAction.joint_indices must be non-negative integers; got {values!r}")
    if np.any(idx < 0):
        raise InvalidInputError(f"ArticulationAction.joint_indices must be non-negative integers; got {values!r}")
    return idx


class ArticulationAction:
    """Targets for some or all joints of an articulation.

    A field left None is untouched. A None/NaN entry of `joint_positions` or
    `joint_velocities` keeps that joint's current target; a None/NaN effort means 0.
    Infinite values, entries that are not real numbers, and joint indices that are not
    non-negative integers (0.7 is refused, not truncated) raise InvalidInputError.

    Args:
        joint_positions: (K,) position targets [rad or m].
        joint_velocities: (K,) velocity targets [rad/s or m/s].
        joint_efforts: (K,) efforts [N m or N].
        joint_indices: (K,) indices of the joints the entries are for; None = all joints
            in order (then K must equal the articulation's number of DoF).
    """

    def __init__(
        self,
        joint_positions: Sequence[float | None] | np.ndarray | None = None,
        joint_velocities: Sequence[float | None] | np.ndarray | None = None,
        joint_efforts: Sequence[float | None] | np.ndarray | None = None,
        joint_indices: Sequence[int] | np.ndarray | None = None,
    ):
        self.joint_positions = _field(joint_positions, "joint_positions")
        self.joint_velocities = _field(joint_velocities, "joint_velocities")
        self.joint_efforts = _field(joint_efforts, "joint_efforts")
        self.joint_indices = _indices(joint_indices)
        lengths = {
            name: len(v)
            for name, v in (
                ("joint_positions", self.joint_positions),
                ("joint_velocities", self.joint_velocities),
                ("joint_efforts", self.joint_efforts),
                ("joint_indices", self.joint_indices),
            )
            if v is not None
        }
        if len(set(lengths.values())) > 1:
            raise InvalidInputError(f"ArticulationAction fields must have equal lengths; got {lengths}")

    def get_length(self) -> int | None:
        """Number of joints the action addresses (None if every field is None)."""
        for v in (self.joint_positions, self.joint_velocities, self.joint_efforts, self.joint_indices):
            if v is not None:
                return len(v)
        return None

    def get_dof_action(self, index: int) -> dict:
        """The entries for the `index`-th joint of the action, as a dict."""
        out = {}
        for name in ("joint_positions", "joint_velocities", "joint_efforts"):
            v = getattr(self, name)
            out[name] = None if v is None or np.isnan(v[index]) else float(v[index])
        return out

    def get_dict(self) -> dict:
        """The action as a dict of lists (None for absent fields)."""
        return {
            name: None if getattr(self, name) is None else getattr(self, name).tolist()
            for name in ("joint_positions", "joint_velocities", "joint_efforts", "joint_indices")
        }

    def __repr__(self) -> str:
        return f"ArticulationAction({self.get_dict()})"
