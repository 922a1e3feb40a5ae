"""`ArticulationAction`: joint targets for a simulated articulation (Isaac Sim's semantics).

It lives at the bottom layer so that planning results can be turned into actions without
importing the simulator; `manip.sim` re-exports it.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from manip.errors import InvalidInputError


def _field(values, name: str) -> np.ndarray | None:
    if values is None:
        return None
    a = np.array(
        [np.nan if v is None else v for v in np.ravel(np.asarray(values, dtype=object))], dtype=float
    )
    if np.any(np.isinf(a)):
        raise InvalidInputError(f"ArticulationAction.{name} has infinite entries: {a}")
    return a


class ArticulationAction:
    """Targets for some or all joints of an articulation.

    A field left None is untouched. A None/NaN entry of `joint_positions` or
    `joint_velocities` keeps that joint's current target; a None/NaN effort means 0.
    Infinite values raise InvalidInputError.

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
        self.joint_indices = None if joint_indices is None else np.asarray(joint_indices, dtype=int).ravel()
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
