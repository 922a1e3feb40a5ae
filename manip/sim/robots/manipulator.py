"""`SingleManipulator`: a robot arm with an end-effector frame and an optional gripper
(Isaac's `omni.isaac.manipulators.SingleManipulator`, the "Adding a New Manipulator" tutorial).

Composition, as in Isaac: the gripper (e.g. a `ParallelGripper`) is built by the script and
handed over; the manipulator binds it to its joints when the World compiles and restores its
default (opened) positions at every reset. `Franka` is a SingleManipulator with its gripper
built in.
"""

from __future__ import annotations

from typing import Any, Protocol

from manip.errors import InvalidInputError
from manip.sim.articulations.articulation import Robot
from manip.sim.prims.xform_prim import XFormPrim
from manip.sim.scenes.stage import SimHandle, add_reference_to_stage, get_current_stage


class Gripper(Protocol):
    """What a manipulator needs from its gripper (`ParallelGripper` is one)."""

    def initialize(self, articulation_apply_action_func: Any, get_joint_positions_func: Any,
                   set_joint_positions_func: Any, dof_names: list[str], physics_sim_view: Any = None) -> None: ...

    def get_default_state(self) -> Any: ...

    def post_reset(self) -> None: ...


class SingleManipulator(Robot):
    """A referenced robot arm with an end effector and an optional gripper.

    Args:
        prim_path: where the model is (or, with usd_path, will be) referenced, e.g. "/World/Franka".
        end_effector_prim_name: body or site of the model used as end effector, e.g.
            "panda_rightfinger" (the frame is `prim_path + "/" + end_effector_prim_name`).
        name: scene name.
        usd_path: a model to reference at `prim_path` if nothing is referenced there (an
            Isaac asset path or an MJCF/URDF file; see `add_reference_to_stage`).
        position / translation, orientation: base pose (world) [m], (w, x, y, z).
        gripper: a gripper (e.g. `ParallelGripper`), bound to the robot's joints at reset.
        end_effector_prim_path: the full path of the end-effector frame, instead of
            end_effector_prim_name (Isaac 4.5's form).

    Isaac 5 (`isaacsim.robot.manipulators`) takes the end effector's full path as its second
    argument: a second argument starting with "/" is that path. `usd_path` is keyword-only
    (manip's addition: positions 3-9 are Isaac's `name`, `position`, ..., `gripper`).

    Raises:
        InvalidInputError: neither or both of end_effector_prim_name / end_effector_prim_path,
            or an end-effector path outside `prim_path`.
    """

    def __init__(self, prim_path: str, end_effector_prim_name: str | None = None, name: str = "single_manipulator",
                 position=None, translation=None, orientation=None, scale=None, visible=None,
                 gripper: Gripper | None = None, end_effector_prim_path: str | None = None, *,
                 usd_path: str | None = None):
        if isinstance(end_effector_prim_name, str) and end_effector_prim_name.startswith("/") \
                and end_effector_prim_path is None:  # Isaac 5's second argument: the full path
            end_effector_prim_name, end_effector_prim_path = None, end_effector_prim_name
        if (end_effector_prim_name is None) == (end_effector_prim_path is None):
            raise InvalidInputError("give end_effector_prim_name (e.g. 'panda_rightfinger') or end_effector_prim_path "
                                    "(e.g. '/World/Franka/panda_rightfinger'), exactly one")
        if end_effector_prim_path is None:
            end_effector_prim_path = f"{prim_path}/{end_effector_prim_name}"
        if not end_effector_prim_path.startswith(prim_path + "/"):
            raise InvalidInputError(f"end_effector_prim_path {end_effector_prim_path!r} must lie inside the robot's "
                                    f"prim {prim_path!r}")
        stage = get_current_stage()
        created = usd_path is not None and stage.find_reference(prim_path) is None
        if created:
            add_reference_to_stage(usd_path, prim_path)
        try:
            # The end effector and the gripper exist before the Robot registers itself: a model
            # compiled already binds the robot (and its gripper) at once.
            self._end_effector_prim_path = end_effector_prim_path
            self._end_effector = XFormPrim(end_effector_prim_path, name=f"{name}_end_effector")
            self._gripper = gripper
            super().__init__(prim_path, name, position=position, translation=translation, orientation=orientation,
                             scale=scale, visible=visible)
        except Exception:
            # A rejected call leaves the stage as it was: the model this constructor referenced
            # goes (with the end-effector frame below it), so the prim_path can be used again.
            if created:
                stage.remove_prim(prim_path)
            raise

    @property
    def end_effector(self) -> XFormPrim:
        """The end-effector frame (pose via `get_world_pose()`)."""
        return self._end_effector

    @property
    def gripper(self) -> Gripper | None:
        return self._gripper

    def bind_simulation(self, sim: SimHandle) -> None:
        super().bind_simulation(sim)
        if self._gripper is None or hasattr(self._gripper, "add_equalities_to_spec"):
            return  # a SurfaceGripper is bound as a wrapper of the stage (it drives no joints)
        self._gripper.initialize(self.apply_action, self.get_joint_positions, self.set_joint_positions,
                                 self._core.dof_names)
        indices = getattr(self._gripper, "joint_dof_indices", None)
        if indices is None:
            return
        # Isaac's tutorials open grippers past the finger limits (0.05 m on the Panda's 0.04):
        # as a target that is fine (the fingers stop on the limit); the reset teleport uses
        # the limit itself.
        default = self._core.onto_limits(self._gripper.get_default_state(), indices, "gripper default positions")
        self._gripper.set_default_state(default)
        if "positions" not in self._user_default_joints:
            self._default_joints.positions[indices] = default

    def post_reset(self) -> None:
        """Restore the robot's default state, then the gripper's (opened unless changed)."""
        super().post_reset()
        if self._gripper is not None:
            self._gripper.post_reset()
