"""`ArticulationKinematicsSolver` and `ArticulationSubset`: a kinematics solver on a simulated robot.

    art_kin = ArticulationKinematicsSolver(franka, kinematics_solver, "right_gripper")
    action, success = art_kin.compute_inverse_kinematics(target_position, target_orientation)
    if success:
        franka.apply_action(action)
    position, rotation = art_kin.compute_end_effector_pose()

As Isaac's: the solver's joints are read from the articulation by name (`ArticulationSubset`),
its IK starts from the robot's current joints, and its answer comes back as an
ArticulationAction for those joints (`joint_indices` their indices in the articulation).
The solver is any object with Isaac's `KinematicsSolver` methods (`LulaKinematicsSolver`).

Differences from Isaac, chosen so that a mistake stops at its line: an end-effector frame
the solver does not have raises UnknownNameError listing the frames (Isaac 4 logs an error,
Isaac 5 raises ValueError); using an articulation before the first `world.reset()` raises
SimulationError (Isaac logs an error and returns None).
"""

from __future__ import annotations

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.sim.scenes.stage import SimulationError

#: The methods of Isaac's KinematicsSolver interface this wrapper calls.
SOLVER_METHODS = ("get_joint_names", "get_all_frame_names", "compute_forward_kinematics", "compute_inverse_kinematics")


class ArticulationSubset:
    """Some joints of an articulation, by name, in a given order (Isaac's ArticulationSubset).

    Args:
        articulation: the robot (`Articulation`, `Robot`, `Franka`, ...).
        joint_names: its joints, in the order of the vectors this subset reads and writes
            (may be empty: a motion policy's watched joints).
    """

    def __init__(self, articulation, joint_names: list[str]):
        if not hasattr(articulation, "get_dof_index") or not hasattr(articulation, "apply_action"):
            raise InvalidInputError(f"articulation must be a manip.sim Articulation; got {type(articulation).__name__}")
        names = list(joint_names)
        if not all(isinstance(n, str) for n in names):
            raise InvalidInputError(f"joint_names must be a list of str; got {joint_names!r}")
        self._articulation = articulation
        self._names = names
        self._indices: np.ndarray | None = None

    @property
    def joint_names(self) -> list[str]:
        return list(self._names)

    @property
    def num_joints(self) -> int:
        return len(self._names)

    @property
    def joint_indices(self) -> np.ndarray:
        """(K,) the joints' indices in the articulation.

        Raises:
            SimulationError: before the first `world.reset()`.
            UnknownNameError: a joint the articulation does not have (the message lists its joints).
        """
        art = self._articulation
        if not art.handles_initialized:
            raise SimulationError(f"{art.name} is not initialised: call world.reset() before using its joints")
        if self._indices is None:
            self._indices = np.array([art.get_dof_index(n) for n in self._names], dtype=np.int64)
        return self._indices.copy()

    def get_joint_positions(self) -> np.ndarray:
        """(K,) positions of the joints [rad or m]."""
        idx = self.joint_indices
        return self._articulation.get_joint_positions(joint_indices=idx) if idx.size else np.empty(0)

    def get_joint_velocities(self) -> np.ndarray:
        """(K,) velocities of the joints [rad/s or m/s]."""
        idx = self.joint_indices
        return self._articulation.get_joint_velocities(joint_indices=idx) if idx.size else np.empty(0)

    def make_articulation_action(self, joint_positions, joint_velocities=None) -> ArticulationAction:
        """An ArticulationAction setting these joints' targets ((K,) each, or None)."""
        return ArticulationAction(joint_positions=joint_positions, joint_velocities=joint_velocities,
                                  joint_indices=self.joint_indices)

    def apply_action(self, joint_positions, joint_velocities=None) -> None:
        """Apply `make_articulation_action(...)` to the articulation."""
        self._articulation.apply_action(self.make_articulation_action(joint_positions, joint_velocities))


class ArticulationKinematicsSolver:
    """A kinematics solver applied to a simulated robot's end effector.

    Args:
        robot_articulation: the robot, initialised by `world.reset()` before the first call.
        kinematics_solver: a `LulaKinematicsSolver` (or any object with `SOLVER_METHODS`).
        end_effector_frame_name: a frame of `kinematics_solver.get_all_frame_names()`.

    Raises:
        InvalidInputError: the solver lacks a method of `SOLVER_METHODS`.
        UnknownNameError: unknown end-effector frame (the message lists the frames).
    """

    def __init__(self, robot_articulation, kinematics_solver, end_effector_frame_name: str):
        missing = [m for m in SOLVER_METHODS if not callable(getattr(kinematics_solver, m, None))]
        if missing:
            raise InvalidInputError(f"kinematics_solver must be a KinematicsSolver (LulaKinematicsSolver); "
                                    f"{type(kinematics_solver).__name__} has no {', '.join(missing)}")
        self._robot_articulation = robot_articulation
        self._kinematics_solver = kinematics_solver
        self.set_end_effector_frame(end_effector_frame_name)
        self._joints_view = ArticulationSubset(robot_articulation, kinematics_solver.get_joint_names())

    def set_end_effector_frame(self, end_effector_frame_name: str) -> None:
        """Use another frame of the solver as the end effector."""
        frames = self._kinematics_solver.get_all_frame_names()
        if not isinstance(end_effector_frame_name, str) or end_effector_frame_name not in frames:
            raise UnknownNameError("end_effector_frame_name: frame", str(end_effector_frame_name), frames)
        self._ee_frame = end_effector_frame_name

    def get_end_effector_frame(self) -> str:
        return self._ee_frame

    def get_joints_subset(self) -> ArticulationSubset:
        """The solver's joints on the articulation, in the solver's order."""
        return self._joints_view

    def get_kinematics_solver(self):
        return self._kinematics_solver

    def compute_end_effector_pose(self, position_only: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """(position (3,) [m], rotation (3, 3)) of the end effector in the world at the robot's
        current joints (the solver's base pose must be the robot's: `set_robot_base_pose`)."""
        q = self._joints_view.get_joint_positions()
        return self._kinematics_solver.compute_forward_kinematics(self._ee_frame, q, position_only=position_only)

    def compute_inverse_kinematics(self, target_position, target_orientation=None,
                                   position_tolerance: float | None = None,
                                   orientation_tolerance: float | None = None) -> tuple[ArticulationAction, bool]:
        """IK of the end effector from the robot's current joints.

        Args:
            target_position: (3,) [m], world frame.
            target_orientation: (4,) (w, x, y, z), world frame; None: position only.
            position_tolerance: [m]; None: the solver's default.
            orientation_tolerance: [rad]; None: the solver's default.

        Returns:
            (ArticulationAction with the solver's joints' positions and their indices in the
            articulation, success). On failure the action holds the best configuration found;
            Isaac's scripts apply it only on success.
        """
        warm_start = self._joints_view.get_joint_positions()
        q, success = self._kinematics_solver.compute_inverse_kinematics(
            self._ee_frame, target_position, target_orientation, warm_start, position_tolerance, orientation_tolerance)
        return self._joints_view.make_articulation_action(q, None), success
