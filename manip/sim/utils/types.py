"""Value types of the simulation API (Isaac's `isaacsim.core.utils.types`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.utils.bounds import bounded_vec
from manip.validation import unit_quat

__all__ = ["ArticulationAction", "DynamicState", "DynamicsViewState", "JointsState", "XFormPrimState", "XFormPrimViewState",
           "ArticulationActions", "ArticulationViewActions"]


@dataclass
class XFormPrimState:
    """Pose of a prim: position (3,) [m], orientation (4,) (w, x, y, z)."""

    position: np.ndarray
    orientation: np.ndarray


class DefaultPoseMixin:
    """`set_default_state` / `get_default_state` over a `self._default_state` XFormPrimState
    (the pose `post_reset()` restores), shared by scene objects and articulations."""

    _default_state: XFormPrimState

    def set_default_state(self, position=None, orientation=None) -> None:
        """Pose restored by `post_reset()` (i.e. by `World.reset()`); None keeps a part."""
        if position is not None:
            self._default_state.position = bounded_vec(position, "position", "position")
        if orientation is not None:
            self._default_state.orientation = unit_quat(orientation)

    def get_default_state(self) -> XFormPrimState:
        """The state `post_reset()` restores (a copy)."""
        s = self._default_state
        return XFormPrimState(s.position.copy(), s.orientation.copy())


def position_or_translation(position, translation):
    """The prim position given as `position` (world) or `translation` (local: the same here,
    prims have no parent transform), unchecked; None if neither.

    Raises:
        InvalidInputError: both are given.
    """
    if position is not None and translation is not None:
        raise InvalidInputError("give either position (world) or translation (local), not both")
    return position if position is not None else translation


@dataclass
class DynamicState(XFormPrimState):
    """Pose and velocities of a rigid body: linear (3,) [m/s] and angular (3,) [rad/s], world frame."""

    linear_velocity: np.ndarray
    angular_velocity: np.ndarray


@dataclass
class JointsState:
    """Joint positions [rad or m], velocities [rad/s or m/s] and efforts [N m or N], (num_dof,) each."""

    positions: np.ndarray | None
    velocities: np.ndarray | None
    efforts: np.ndarray | None


ArticulationActions = ArticulationAction


@dataclass
class ArticulationViewActions:
    """The drive targets a view returns (Isaac's `ArticulationActions` of
    `ArticulationView.get_applied_actions`): positions [rad or m], velocities [rad/s or m/s]
    and efforts [N m or N], (M, num_dof) each for M articulations."""

    joint_positions: np.ndarray
    joint_velocities: np.ndarray
    joint_efforts: np.ndarray
    joint_indices: np.ndarray | None = None


@dataclass
class XFormPrimViewState:
    """Poses of a view's prims: positions (K, 3) [m], orientations (K, 4) (w, x, y, z)."""

    positions: np.ndarray
    orientations: np.ndarray


@dataclass
class DynamicsViewState(XFormPrimViewState):
    """Poses and velocities of a view's bodies: linear (K, 3) [m/s], angular (K, 3) [rad/s], world frame."""

    linear_velocities: np.ndarray
    angular_velocities: np.ndarray
