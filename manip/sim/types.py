"""Value types of the simulation API (Isaac's `isaacsim.core.utils.types`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip.articulation_action import ArticulationAction

__all__ = ["ArticulationAction", "DynamicState", "JointsState", "XFormPrimState", "ArticulationActions"]


@dataclass
class XFormPrimState:
    """Pose of a prim: position (3,) [m], orientation (4,) (w, x, y, z)."""

    position: np.ndarray
    orientation: np.ndarray


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
