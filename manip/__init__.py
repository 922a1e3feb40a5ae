"""manip: CPU motion generation and an Isaac-Sim-style MuJoCo world for robot manipulation.

Layers (each depends only on those before it in this list):
kinematics / collision / trajectory / timing -> planning -> MotionGenerator -> compat
(the tutorial wrapper) -> manip.sim.
`manip.sim` (the simulator) is imported separately: `from manip.sim import World, ...`.
"""

from __future__ import annotations

import warnings

from manip.articulation_action import ArticulationAction
from manip.collision import (
    Capsule,
    CollisionChecker,
    CollisionReport,
    Cuboid,
    Cylinder,
    DistanceReport,
    Mesh,
    Sphere,
    WorldConfig,
)
from manip.constraints import Constraint, OrientationConstraint, PositionConstraint, RelativePoseConstraint
from manip.errors import InvalidInputError, ManipError, RobotConfigError, UnknownNameError
from manip.ik import BatchIKResult, IKResult, IKSolutions, IKSolver, IKStatus
from manip.kinematics import Kinematics
from manip.limits import JointLimits
from manip.motion_generator import MotionGenerator
from manip.compat import TutorialMotionGen, wxyz_to_xyzw, xyzw_to_wxyz
from manip.planning import GraspPlan, PlanOptions, PlanResult, PlanStatus
from manip.pose import Pose
from manip.robot_config import RobotConfig, available_robots, load_robot_config, robots_root
from manip.timing import (
    TimingResult,
    TimingStatus,
    time_parameterize,
    time_parameterize_dense,
    time_parameterize_for_robot,
)
from manip.trajectory import CubicSplinePath, PathProfile, PiecewiseJerkProfile, Trajectory

__all__ = [
    "ArticulationAction",
    "BatchIKResult",
    "Capsule",
    "CollisionChecker",
    "CollisionReport",
    "Constraint",
    "CubicSplinePath",
    "Cuboid",
    "Cylinder",
    "DistanceReport",
    "GraspPlan",
    "IKResult",
    "IKSolutions",
    "IKSolver",
    "IKStatus",
    "InvalidInputError",
    "JointLimits",
    "Kinematics",
    "ManipError",
    "Mesh",
    "MotionGenerator",
    "OrientationConstraint",
    "PathProfile",
    "PiecewiseJerkProfile",
    "PlanOptions",
    "PlanResult",
    "PlanStatus",
    "Pose",
    "PositionConstraint",
    "RelativePoseConstraint",
    "RobotConfig",
    "RobotConfigError",
    "Sphere",
    "TimingResult",
    "TimingStatus",
    "Trajectory",
    "TutorialMotionGen",
    "UnknownNameError",
    "WorldConfig",
    "available_robots",
    "load_robot_config",
    "robots_root",
    "time_parameterize",
    "time_parameterize_dense",
    "time_parameterize_for_robot",
    "wxyz_to_xyzw",
    "xyzw_to_wxyz",
]


def __getattr__(name: str):
    """`manip.TutorialAPI`: the deprecated name of `TutorialMotionGen` (a DeprecationWarning)."""
    if name == "TutorialAPI":
        warnings.warn("manip.TutorialAPI is deprecated: use manip.TutorialMotionGen", DeprecationWarning, stacklevel=2)
        from manip.tutorial_api import TutorialAPI

        return TutorialAPI
    raise AttributeError(f"module 'manip' has no attribute {name!r}")
