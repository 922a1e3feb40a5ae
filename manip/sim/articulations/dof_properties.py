"""Isaac's `dof_properties`: one structured record per joint of an articulation."""

from __future__ import annotations

import numpy as np

from manip.sim.articulations.articulation_core import ArticulationCore

#: `dof_properties` fields, as Isaac's. type: 1 revolute, 2 prismatic; driveMode: 0 effort
#: (no drive gains), 1 position (kp > 0), 2 velocity (kp = 0, kd > 0).
DOF_PROPERTIES_DTYPE = np.dtype(
    [
        ("type", np.int32),
        ("hasLimits", bool),
        ("lower", np.float32),
        ("upper", np.float32),
        ("driveMode", np.int32),
        ("maxVelocity", np.float32),
        ("maxEffort", np.float32),
        ("stiffness", np.float32),
        ("damping", np.float32),
    ]
)


def dof_properties(core: ArticulationCore) -> np.ndarray:
    """(num_dof,) array of DOF_PROPERTIES_DTYPE: limits [rad or m], max velocity [rad/s or
    m/s], max effort [N m or N], stiffness and damping of the drives, as they are now."""
    out = np.zeros(core.n, dtype=DOF_PROPERTIES_DTYPE)
    out["type"] = core.types
    out["hasLimits"] = core.has_limits
    out["lower"] = core.lower
    out["upper"] = core.upper
    out["driveMode"] = core.drive_modes()
    out["maxVelocity"] = core.max_velocities
    out["maxEffort"] = core.max_efforts
    out["stiffness"] = core.kps
    out["damping"] = core.kds
    return out
