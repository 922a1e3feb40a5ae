"""Isaac Sim's motion-generation extension (`omni.isaac.motion_generation`, Isaac Sim 5:
`isaacsim.robot_motion.motion_generation`): its kinematics interface on manip.

- `LulaKinematicsSolver` (`kinematics_solver`): FK and IK of a robot given by a Lula robot
  description YAML (`robot_description`) and a URDF (`urdf_aliases` maps Isaac's
  `lula_franka_gen.urdf` to manip's Franka with its `right_gripper` frame).
- `ArticulationKinematicsSolver`, `ArticulationSubset` (`articulation_kinematics_solver`): the
  solver applied to a simulated robot, its answers as ArticulationActions; `KinematicsSolver`
  (`franka_kinematics_solver`): the Franka's, as Isaac's Franka extension ships it.
- `RmpFlow` (`rmpflow`): RMPflow's motion-policy interface on manip's QP controller
  (`manip.control.ReactiveController`; not RMPflow: the module docstring says what differs),
  with `rmpflow_config` (the RMPflow YAML), `end_effector_map` (the URDF end effector as a
  frame of the controller's model) and `sim_obstacles` (manip.sim objects as obstacles,
  shared with `manip.sim.RMPFlowController`).
- `ArticulationMotionPolicy` (`articulation_motion_policy`): a motion policy on a simulated
  robot, its targets as ArticulationActions; `MotionPolicyController`
  (`motion_policy_controller`): Isaac's controller stepping one.
- `interface_config_loader`: the supported robots' configuration files.
- `get_extension_path_from_name` (`extension`): the extension's folder (manip's files).

Not here: Lula's path planners (RRT) and trajectory generators.
"""

from __future__ import annotations

from manip.sim.motion_generation import interface_config_loader
from manip.sim.motion_generation.articulation_kinematics_solver import ArticulationKinematicsSolver, ArticulationSubset
from manip.sim.motion_generation.articulation_motion_policy import ArticulationMotionPolicy
from manip.sim.motion_generation.extension import get_extension_path_from_name
from manip.sim.motion_generation.franka_kinematics_solver import KinematicsSolver
from manip.sim.motion_generation.kinematics_solver import LulaKinematicsSolver
from manip.sim.motion_generation.motion_policy_controller import MotionPolicyController
from manip.sim.motion_generation.rmpflow import RmpFlow

__all__ = ["ArticulationKinematicsSolver", "ArticulationMotionPolicy", "ArticulationSubset", "KinematicsSolver",
           "LulaKinematicsSolver",
           "MotionPolicyController", "RmpFlow", "get_extension_path_from_name", "interface_config_loader"]
