"""Robots of the tutorials: `ParallelGripper`, `Franka`, `WheeledRobot` (and the Jetbot file)."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.robot_config import load_robot_config
from manip.sim.articulations.articulation import Robot
from manip.sim.robots.manipulator import SingleManipulator
from manip.sim.scenes.stage import SimHandle, SimulationError, add_reference_to_stage, get_assets_root_path
from manip.sim.utils.not_supported import declare as declare_not_supported

logger = logging.getLogger(__name__)


def franka_model_path() -> Path:
    """`robots/franka/franka.xml`."""
    return Path(get_assets_root_path()) / "franka" / "franka.xml"


def jetbot_model_path() -> Path:
    """`robots/jetbot/jetbot.xml` (wheel radius 0.03 m, wheel base 0.1125 m)."""
    return Path(get_assets_root_path()) / "jetbot" / "jetbot.xml"


def robot_model_path(robot: str) -> Path:
    """The MuJoCo model of a robot folder under `robots/` (its robot.yaml's `mjcf`), e.g.
    `add_reference_to_stage(robot_model_path("ur5"), "/World/ur5")` then `Robot("/World/ur5")`.

    Raises:
        UnknownNameError: no robot of that name (the message lists them).
        InvalidInputError: the robot has no MJCF.
    """
    config = load_robot_config(robot)
    if config.mjcf_path is None or not config.mjcf_path.is_file():
        raise InvalidInputError(f"robot '{robot}' has no MuJoCo model (robot.yaml 'mjcf'); build one with "
                                "robots/tools/make_mjcf.py")
    return config.mjcf_path


class ParallelGripper:
    """Two fingers driven by position targets (Isaac's `ParallelGripper`).

    Args:
        end_effector_prim_path: prim of the frame the fingers close around.
        joint_prim_names: the two finger joint names.
        joint_opened_positions: (2,) finger positions when open [m].
        joint_closed_positions: (2,) finger positions when closed [m].
        action_deltas: (2,) if given, "open"/"close" move each finger by this much from its
            current position instead of going to the opened/closed positions.
    """

    def __init__(self, end_effector_prim_path: str, joint_prim_names, joint_opened_positions,
                 joint_closed_positions, action_deltas=None, use_mimic_joints: bool = False):
        self.end_effector_prim_path = end_effector_prim_path
        self._joint_names = list(joint_prim_names)
        k = len(self._joint_names)
        self._opened = np.asarray(joint_opened_positions, dtype=float).ravel()
        self._closed = np.asarray(joint_closed_positions, dtype=float).ravel()
        for what, a in (("joint_opened_positions", self._opened), ("joint_closed_positions", self._closed)):
            if a.size != k or not np.all(np.isfinite(a)):
                raise InvalidInputError(f"{what} needs {k} finite values (one per finger joint); got {a}")
        self._deltas: np.ndarray | None = None
        self.set_action_deltas(action_deltas)
        self._apply: Callable | None = None
        self._get_q: Callable | None = None
        self._set_q: Callable | None = None
        self._indices: np.ndarray | None = None
        self._num_dof = 0
        self._default = self._opened.copy()

    def initialize(self, articulation_apply_action_func: Callable, get_joint_positions_func: Callable,
                   set_joint_positions_func: Callable, dof_names: list[str], physics_sim_view=None) -> None:
        """Bind to an articulation (done by `Franka` when the World compiles)."""
        missing = [n for n in self._joint_names if n not in dof_names]
        if missing:
            raise UnknownNameError("finger joint", missing[0], dof_names)
        self._indices = np.array([dof_names.index(n) for n in self._joint_names], dtype=int)
        self._num_dof = len(dof_names)
        self._apply = articulation_apply_action_func
        self._get_q = get_joint_positions_func
        self._set_q = set_joint_positions_func

    def _need(self) -> None:
        if self._indices is None:
            raise SimulationError("the gripper is used before World.reset() bound it to its robot")

    def set_action_deltas(self, value) -> None:
        """Finger steps (2,) [m] of "open" / "close" from the current positions (None: go to
        the opened / closed positions); from the next `forward`."""
        if value is None:
            self._deltas = None
            return
        a = np.asarray(value, dtype=float).ravel()
        if a.size != len(self._joint_names) or not np.all(np.isfinite(a)):
            raise InvalidInputError(f"action_deltas needs {len(self._joint_names)} finite values (one per finger "
                                    f"joint) or None; got {value!r}")
        self._deltas = a

    def get_action_deltas(self) -> np.ndarray | None:
        """The finger steps (2,) [m] of "open" / "close", or None (see `set_action_deltas`)."""
        return None if self._deltas is None else self._deltas.copy()

    @property
    def joint_opened_positions(self) -> np.ndarray:
        return self._opened.copy()

    @property
    def joint_closed_positions(self) -> np.ndarray:
        return self._closed.copy()

    @property
    def joint_dof_indices(self) -> np.ndarray | None:
        return None if self._indices is None else self._indices.copy()

    joint_dof_indicies = joint_dof_indices  # Isaac's spelling

    @property
    def joint_names(self) -> list[str]:
        return list(self._joint_names)

    def forward(self, action: str) -> ArticulationAction:
        """A full-length action (None/NaN for the other joints) that opens or closes the fingers.

        Args:
            action: "open" or "close".
        """
        self._need()
        if action not in ("open", "close"):
            raise InvalidInputError(f"gripper action must be 'open' or 'close'; got {action!r}")
        if self._deltas is None:
            target = self._opened if action == "open" else self._closed
        else:
            q = self._get_q(self._indices)
            target = q + self._deltas if action == "open" else q - self._deltas
        full = np.full(self._num_dof, np.nan)
        full[self._indices] = target
        return ArticulationAction(joint_positions=full)

    def open(self) -> None:
        self._apply(self.forward("open"))

    def close(self) -> None:
        self._apply(self.forward("close"))

    def apply_action(self, control_actions: ArticulationAction) -> None:
        """Apply an action given for the fingers only (length 2)."""
        self._need()
        if control_actions.get_length() not in (None, len(self._indices)):
            hint = (": gripper.forward() returns the whole robot's action, apply that with robot.apply_action(...)"
                    if control_actions.get_length() == self._num_dof else "")
            raise InvalidInputError(f"a gripper action needs {len(self._indices)} entries (the fingers' "
                                    f"{self._joint_names}); got {control_actions.get_length()}{hint}")
        self._apply(ArticulationAction(control_actions.joint_positions, control_actions.joint_velocities,
                                       control_actions.joint_efforts, self._indices))

    def get_joint_positions(self) -> np.ndarray:
        """Finger positions (2,) [m]."""
        self._need()
        return self._get_q(self._indices)

    def set_joint_positions(self, positions) -> None:
        """Teleport the fingers (and set their targets)."""
        self._need()
        self._set_q(positions, self._indices)

    def set_default_state(self, joint_positions) -> None:
        a = np.asarray(joint_positions, dtype=float).ravel()
        if a.size != len(self._joint_names) or not np.all(np.isfinite(a)):
            raise InvalidInputError(f"gripper default state needs {len(self._joint_names)} finite values")
        self._default = a

    def get_default_state(self) -> np.ndarray:
        return self._default.copy()

    def post_reset(self) -> None:
        """Fingers to their default positions (open unless changed)."""
        if self._indices is not None:
            self.set_joint_positions(self._default)


class Franka(SingleManipulator):
    """The Franka Emika Panda with its parallel gripper (Isaac's `Franka`).

    If nothing is referenced at `prim_path`, `usd_path` (default `robots/franka/franka.xml`)
    is referenced there. The default joint state is the model's "home" keyframe (the ready
    configuration, fingers open 0.04 m).

    `end_effector` is the tool centre point between the fingertips (`panda_hand_tcp`, 0.1034 m
    beyond the hand flange) by default; Isaac uses the right finger body, a poor grasp
    reference. Pass `end_effector_prim_name="panda_hand"` for the flange frame the motion
    generator plans for. `PickPlaceController` and `RMPFlowController` place the tool centre at
    their targets whatever `end_effector` is (as Isaac's place "right_gripper").

    Args:
        prim_path: e.g. "/World/Franka".
        name: scene name.
        usd_path: model file (MJCF).
        position, orientation: base pose (world) [m], (w, x, y, z).
        end_effector_prim_name: body or site of the model used as end effector.
        gripper_dof_names: the two finger joints.
        gripper_open_position / gripper_closed_position: (2,) [m] (default 0.04 / 0.0).
        deltas: (2,) gripper action deltas (see ParallelGripper).
    """

    def __init__(self, prim_path: str, name: str = "franka_robot", usd_path: str | None = None, position=None,
                 orientation=None, end_effector_prim_name: str | None = None, gripper_dof_names=None,
                 gripper_open_position=None, gripper_closed_position=None, deltas=None):
        ee = end_effector_prim_name or "panda_hand_tcp"
        gripper = ParallelGripper(
            f"{prim_path}/{ee}",
            gripper_dof_names or ["panda_finger_joint1", "panda_finger_joint2"],
            gripper_open_position if gripper_open_position is not None else [0.04, 0.04],
            gripper_closed_position if gripper_closed_position is not None else [0.0, 0.0],
            deltas,
        )
        super().__init__(prim_path, ee, name, position=position, orientation=orientation, gripper=gripper,
                         usd_path=usd_path if usd_path is not None else franka_model_path())

    @property
    def gripper(self) -> ParallelGripper:
        return self._gripper


class WheeledRobot(Robot):
    """A robot driven by wheels (Isaac's `WheeledRobot`); the wheels run in velocity mode
    after every reset.

    Args:
        prim_path: where the model is (or will be, with create_robot) referenced.
        name: scene name.
        wheel_dof_names: the wheel joints (or `wheel_dof_indices`).
        create_robot: reference `usd_path` at `prim_path` first.
        usd_path: the model: an Isaac asset path (`get_assets_root_path() +
            "/Isaac/Robots/Jetbot/jetbot.usd"`) or an MJCF/URDF file.
        position, orientation: initial and default pose [m], (w, x, y, z).
    """

    def __init__(self, prim_path: str, name: str = "wheeled_robot", robot_path: str | None = None,
                 wheel_dof_names=None, wheel_dof_indices=None, usd_path: str | None = None,
                 create_robot: bool = False, position=None, orientation=None):
        if create_robot:
            if usd_path is None:
                raise InvalidInputError("create_robot=True needs usd_path (the robot's model file)")
            add_reference_to_stage(usd_path, prim_path)
        if wheel_dof_names is None and wheel_dof_indices is None:
            raise InvalidInputError("give wheel_dof_names (or wheel_dof_indices)")
        self._wheel_names = None if wheel_dof_names is None else list(wheel_dof_names)
        self._wheel_idx_given = None if wheel_dof_indices is None else [int(i) for i in wheel_dof_indices]
        self._wheel_idx: np.ndarray | None = None
        super().__init__(prim_path, name, position=position, orientation=orientation)

    def bind_simulation(self, sim: SimHandle) -> None:
        super().bind_simulation(sim)
        if self._wheel_names is not None:
            self._wheel_idx = np.array([self.get_dof_index(n) for n in self._wheel_names], dtype=int)
        else:
            self._wheel_idx = self._core.indices(self._wheel_idx_given)

    @property
    def wheel_dof_indices(self) -> np.ndarray | None:
        return None if self._wheel_idx is None else self._wheel_idx.copy()

    def apply_wheel_actions(self, actions: ArticulationAction) -> None:
        """Apply an action given for the wheels only (its length must equal the number of wheels).

        Raises:
            InvalidInputError: wrong length (targets unchanged).
        """
        if self._wheel_idx is None:
            raise SimulationError(f"{self.name}: call world.reset() before applying wheel actions")
        if not isinstance(actions, ArticulationAction):
            raise InvalidInputError(f"expected an ArticulationAction; got {type(actions).__name__}")
        k = actions.get_length()
        if k is None:
            return
        if k != len(self._wheel_idx):
            raise InvalidInputError(
                f"the wheel action has {k} entries; {self.name} has {len(self._wheel_idx)} wheels "
                f"({[self._core.dof_names[i] for i in self._wheel_idx]})"
            )
        self.apply_action(ArticulationAction(actions.joint_positions, actions.joint_velocities,
                                             actions.joint_efforts, self._wheel_idx))

    def get_wheel_positions(self) -> np.ndarray | None:
        """Wheel angles (num_wheels,) [rad]; None before the first reset."""
        idx = self._bound_wheels("get_wheel_positions")
        return None if idx is None else self.get_joint_positions(idx)

    def get_wheel_velocities(self) -> np.ndarray | None:
        """Wheel velocities (num_wheels,) [rad/s]; None before the first reset."""
        idx = self._bound_wheels("get_wheel_velocities")
        return None if idx is None else self.get_joint_velocities(idx)

    def _bound_wheels(self, what: str) -> np.ndarray | None:
        if self._wheel_idx is None:
            logger.warning("%s.%s used before the first World.reset()", self.name, what)
        return self._wheel_idx

    def set_wheel_velocities(self, velocities) -> None:
        self.set_joint_velocities(velocities, self._wheel_idx)

    def set_wheel_positions(self, positions) -> None:
        self.set_joint_positions(positions, self._wheel_idx)

    def post_reset(self) -> None:
        super().post_reset()
        self.get_articulation_controller().switch_control_mode("velocity", self._wheel_idx)


declare_not_supported(ParallelGripper)
