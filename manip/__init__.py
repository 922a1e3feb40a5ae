"""manip: CPU motion generation and an Isaac-Sim-style MuJoCo world for robot manipulation."""

from __future__ import annotations

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, ManipError, RobotConfigError, UnknownNameError
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import RobotConfig, available_robots, load_robot_config, robots_root

__all__ = [
    "ArticulationAction",
    "InvalidInputError",
    "Kinematics",
    "ManipError",
    "Pose",
    "RobotConfig",
    "RobotConfigError",
    "UnknownNameError",
    "available_robots",
    "load_robot_config",
    "robots_root",
]

# Later layers: imported when present so the package stays importable while they are built.
try:
    from manip.ik import IKResult, IKSolver, IKStatus  # noqa: F401

    __all__ += ["IKResult", "IKSolver", "IKStatus"]
except ImportError:  # pragma: no cover
    pass
