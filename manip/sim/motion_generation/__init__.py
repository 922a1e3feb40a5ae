"""Isaac Sim's motion-generation extension (`omni.isaac.motion_generation`, Isaac Sim 5:
`isaacsim.robot_motion.motion_generation`): its kinematics interface on manip.

- `LulaKinematicsSolver` (`kinematics_solver`): FK and IK of a robot given by a Lula robot
  description YAML (`robot_description`) and a URDF (`urdf_aliases` maps Isaac's
  `lula_franka_gen.urdf` to manip's Franka with its `right_gripper` frame).
- `ArticulationKinematicsSolver`, `ArticulationSubset` (`articulation_kinematics_solver`): the
  solver applied to a simulated robot, its answers as ArticulationActions.
- `interface_config_loader`: the supported robots' configuration files.
- `get_extension_path_from_name` (`extension`): the extension's folder (manip's files).

Not here: RMPflow (`RmpFlow`, `ArticulationMotionPolicy`; `manip.sim.RMPFlowController` is a
different, reactive controller) and Lula's path planners.
"""

from __future__ import annotations

from manip.sim.motion_generation import interface_config_loader
from manip.sim.motion_generation.articulation_kinematics_solver import ArticulationKinematicsSolver, ArticulationSubset
from manip.sim.motion_generation.extension import get_extension_path_from_name
from manip.sim.motion_generation.kinematics_solver import LulaKinematicsSolver

__all__ = ["ArticulationKinematicsSolver", "ArticulationSubset", "LulaKinematicsSolver",
           "get_extension_path_from_name", "interface_config_loader"]
