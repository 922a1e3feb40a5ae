"""`KinematicsSolver`: the Franka's ready-made IK (Isaac's `omni.isaac.franka.KinematicsSolver`,
Isaac 5's `isaacsim.robot.manipulators.examples.franka.KinematicsSolver`), the one its
"follow target with IK" example uses.

As Isaac's: an `ArticulationKinematicsSolver` on a `LulaKinematicsSolver` loaded from the
supported Franka configuration (`interface_config_loader`), end effector "right_gripper" by
default (0.1 m beyond panda_hand; see `manip.sim.motion_generation.urdf_aliases`).
"""

from __future__ import annotations

from typing import Any

from manip.sim.motion_generation import interface_config_loader
from manip.sim.motion_generation.articulation_kinematics_solver import ArticulationKinematicsSolver
from manip.sim.motion_generation.kinematics_solver import LulaKinematicsSolver


class KinematicsSolver(ArticulationKinematicsSolver):
    """The Franka's kinematics solver applied to a simulated Franka.

    Args:
        robot_articulation: the Franka (initialised by `world.reset()` before the first call).
        end_effector_frame_name: a frame of the Franka's Lula solver (default "right_gripper").

    Raises:
        UnknownNameError: an unknown end-effector frame (the message lists the frames).
    """

    def __init__(self, robot_articulation: Any, end_effector_frame_name: str | None = None):
        self._kinematics = LulaKinematicsSolver(
            **interface_config_loader.load_supported_lula_kinematics_solver_config("Franka"))
        super().__init__(robot_articulation, self._kinematics,
                         "right_gripper" if end_effector_frame_name is None else end_effector_frame_name)
