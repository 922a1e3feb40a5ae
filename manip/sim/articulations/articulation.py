"""Articulations: `Articulation` / `Robot` (Isaac's `SingleArticulation` / `Robot`).

Drives (Isaac's implicit joint drives): every hinge/slide joint of a referenced model has
one MuJoCo actuator whose force is

    f = clip(kp * (q_target - q) + kd * (v_target - v), -max_effort, max_effort)

applied as `ctrl = kp q_target + kd v_target` with the bias `-kp q - kd v`; MuJoCo's
`implicitfast` integrator treats the damping term implicitly, so stiff gains are stable.

Joint limits hold, as in Isaac, where PhysX enforces the limits of every limited joint
(`PxArticulationMotion::eLIMITED`) whatever the drive target: a position target beyond a
limit drives the joint to that limit and no farther (the drive aims at the limit;
`get_applied_action()` still returns the target as given, as Isaac's does); MuJoCo's limit
constraints are made as stiff as it allows (time constant two substeps, impedance
0.95-0.99), and after every physics step a joint found beyond a limit (pushed by an
effort, or by its own speed within the step) is put back on it with its outward velocity
zeroed. `get_joint_positions()` therefore never reads past a limit after a step.

Commands are checked before they reach MuJoCo (InvalidInputError naming the argument and
the joint): NaN or infinite values (a NaN position/velocity *target* keeps that joint's
target, as in Isaac), magnitudes above 1e6 (`MAX_POSITION` [rad or m], `MAX_VELOCITY`
[rad/s or m/s], `MAX_EFFORT` [N m or N], in `manip.sim.articulations.articulation_core`), and drive
commands kp * target + kd * velocity target above 1e9. If MuJoCo still finds the
simulation unstable, `World.step()` raises `SimulationInstabilityError`.
The model's own actuators give the default gains: a `position` actuator gives kp and kv,
a `velocity` actuator gives kd (kp = 0), a `motor` gives kp = kd = 0; joints without an
actuator get one with kp = kd = 0 in an MJCF, and Isaac's URDF importer defaults in a URDF
(kp = 1e3, kd = 1e2, force limited to the URDF effort limit; `manip.sim.scenes.stage`). Efforts (effort mode) are added as joint forces, not
clipped. Actuators with a gear other than 1 are not supported (the gear is reset to 1).

Getters used before the first `World.reset()` return None and log a warning (Isaac's
behaviour); setters raise `SimulationError`.

The drives live in `ArticulationCore` (`manip.sim.articulations.articulation_core`, one per referenced
model, created by the World when it compiles), `ArticulationController` in
`manip.sim.controllers.articulation_controller`, `DOF_PROPERTIES_DTYPE` in `manip.sim.articulations.dof_properties`;
all are importable from here as well.
"""

from __future__ import annotations

import logging

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.sim.controllers.articulation_controller import CONTROL_MODES, ArticulationController  # noqa: F401 (CONTROL_MODES re-exported)
from manip.sim.articulations.articulation_core import MAX_EFFORT, MAX_POSITION, MAX_VELOCITY, ArticulationCore
from manip.sim.articulations.articulation_view import ArticulationView
from manip.sim.articulations.physx_settings import PhysxArticulationSettings
from manip.sim.articulations.dof_properties import DOF_PROPERTIES_DTYPE, dof_properties  # noqa: F401 (DTYPE re-exported)
from manip.sim.scenes.stage import (ReferencePrim, SimHandle, SimulationError, get_current_stage, get_prim_at_path,
                                    validate_prim_path)
from manip.sim.utils.types import DefaultPoseMixin, JointsState, XFormPrimState, position_or_translation
from manip.validation import unit_quat
from manip.sim.utils.bounds import bounded_vec
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.sim.prims import isaac5_views

logger = logging.getLogger(__name__)

class Articulation(DefaultPoseMixin, PhysxArticulationSettings):
    prim_path: str  # where the model is referenced

    """A model referenced on the stage, seen as an articulation (Isaac's `SingleArticulation`).

    Args:
        prim_path: where the model was referenced (`add_reference_to_stage(file, prim_path)`).
        name: unique scene name.
        position / translation: (3,) world position of the model's frame [m] (not both).
        orientation: (4,) (w, x, y, z).
        articulation_controller: a custom controller (default: a new ArticulationController).

    Raises:
        SimulationError: nothing is referenced at `prim_path`.
    """

    def __new__(cls, *args, **kwargs):
        # Isaac 5's `Articulation(prim_paths_expr=...)` is a view (4.x's ArticulationView).
        view = isaac5_views.view_call(cls, args, kwargs)
        return view if view is not None else super().__new__(cls)

    def __init__(
        self,
        prim_path: str,
        name: str = "articulation",
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
        articulation_controller: ArticulationController | None = None,
        enable_residual_reports: bool = False,
        reset_xform_properties: bool = True,
    ):
        validate_prim_path(prim_path)
        stage = get_current_stage()
        ref = stage.find_reference(prim_path)
        if ref is None:
            refs = [p for p in stage.prim_paths() if stage.find_reference(p) is not None]
            raise SimulationError(
                f"no model referenced at {prim_path!r}; call add_reference_to_stage(file, {prim_path!r}) first "
                f"(referenced prims: {refs})"
            )
        p = position_or_translation(position, translation)
        # Checked before the model's pose changes: a rejected call leaves the model as it was.
        p = bounded_vec(p, "position", "position") if p is not None else None
        q = unit_quat(orientation) if orientation is not None else None
        if scale is not None and not np.allclose(np.asarray(scale, dtype=float), 1.0):
            raise InvalidInputError("scaling an articulation is not supported (scale must be 1)")
        if p is not None:
            ref.position = p
        if q is not None:
            ref.orientation = q
        self.prim_path = prim_path
        self._name = name
        self._ref = ref
        self._core: ArticulationCore | None = None
        self._controller = articulation_controller if articulation_controller is not None else ArticulationController()
        self._articulation_view = ArticulationView(self)  # Isaac's batched view (count 1) of this articulation
        self._default_state = XFormPrimState(ref.position.copy(), ref.orientation.copy())
        self._default_joints: JointsState | None = None
        self._user_default_joints: dict = {}
        if self._ref.core is not None and p is not None:
            stage.mark_changed(prim_path)  # a compiled model: the new pose applies at reset
        stage.register_wrapper(self)

    # ------------------------------------------------------------------ binding
    def _bindable(self) -> bool:
        """Whether the model is compiled with this articulation in it."""
        return self._ref.core is not None

    def bind_simulation(self, sim: SimHandle) -> None:
        self._core = self._ref.core
        c = self._core
        self._controller.initialize(self)
        pos = self._user_default_joints.get("positions")
        vel = self._user_default_joints.get("velocities")
        eff = self._user_default_joints.get("efforts")
        for what, v in (("positions", pos), ("velocities", vel), ("efforts", eff)):
            if v is not None and v.size != c.n:
                self._core = None
                raise InvalidInputError(f"{self.prim_path}: default joint {what} have {v.size} entries, not {c.n}")
        all_joints = np.arange(c.n)
        self._default_joints = JointsState(
            c.onto_limits(pos, all_joints, "default joint positions") if pos is not None else c.home.copy(),
            vel.copy() if vel is not None else np.zeros(c.n),
            eff.copy() if eff is not None else np.zeros(c.n),
        )

    def unbind_simulation(self) -> None:
        self._core = None

    def initialize(self, physics_sim_view=None) -> None:
        """Bind to the compiled model if that was not done yet (the World binds articulations
        at every reset; Isaac scripts call this after a reset). Before the model holding
        this articulation is compiled, nothing happens: the next `World.reset()` binds it."""
        if self._core is None and self._bindable():
            self.bind_simulation(self._ref.core.sim)

    @property
    def core(self) -> ArticulationCore | None:
        """The compiled model's view of this articulation (joint indices, limits, drives);
        None before the World binds it at a reset."""
        return self._core

    @property
    def reference(self) -> ReferencePrim:
        """The referenced model (MJCF/URDF on the stage) this articulation wraps."""
        return self._ref

    @property
    def handles_initialized(self) -> bool:
        return self._core is not None

    def is_valid(self) -> bool:
        return self._core is not None

    def _removed(self, what: str) -> str | None:
        """Why this articulation has no model (its model is no longer on the stage), or None."""
        if get_current_stage().get_prim(self.prim_path) is self._ref:
            return None
        return (f"{self._name}.{what}: the model at {self.prim_path!r} is no longer on the stage (removed by "
                "scene.remove_object / scene.clear / world.clear, or made for an earlier World); wrap the model "
                "referenced now in a new Robot")

    def _c(self, what: str) -> ArticulationCore | None:
        if self._core is None:
            removed = self._removed(what)
            if removed:
                logger.warning("%s; returning None", removed)
                return None
            logger.warning("%s.%s used before the first World.reset(); returning None", self._name, what)
        return self._core

    def _cs(self, what: str) -> ArticulationCore:
        if self._core is None:
            removed = self._removed(what)
            if removed:
                raise SimulationError(removed)
            raise SimulationError(f"{self._name}.{what}: the world is not compiled yet; call world.reset() first")
        return self._core

    # ------------------------------------------------------------------ description
    @property
    def prim(self):
        """Isaac's Usd.Prim of the robot: the referenced model's prim on the stage (USD's reading
        methods `IsValid`, `GetPath`, `GetChildren` (its links), ...; None once removed)."""
        return get_prim_at_path(self.prim_path)

    @property
    def name(self) -> str:
        return self._name

    @property
    def num_dof(self) -> int | None:
        """Number of joints (hinge and slide) [None before the first reset]."""
        c = self._c("num_dof")
        return None if c is None else c.n

    @property
    def num_bodies(self) -> int | None:
        c = self._c("num_bodies")
        return None if c is None else len(c.body_ids)

    @property
    def dof_names(self) -> list[str] | None:
        """Joint names without the prim-path prefix, in model order [None before the first reset]."""
        c = self._c("dof_names")
        return None if c is None else list(c.dof_names)

    @property
    def body_names(self) -> list[str] | None:
        c = self._c("body_names")
        return None if c is None else list(c.body_names)

    def get_dof_index(self, dof_name: str) -> int:
        """Index of a joint by name.

        Raises:
            UnknownNameError: no such joint (the message lists them).
            SimulationError: before the first reset.
        """
        c = self._cs("get_dof_index")
        try:
            return c.dof_names.index(dof_name)
        except ValueError:
            raise UnknownNameError("joint", dof_name, c.dof_names) from None

    @property
    def dof_properties(self) -> np.ndarray | None:
        """(num_dof,) structured array with Isaac's fields (see DOF_PROPERTIES_DTYPE)."""
        c = self._c("dof_properties")
        return None if c is None else dof_properties(c)

    def get_dof_limits(self) -> np.ndarray | None:
        c = self._c("get_dof_limits")
        return None if c is None else np.stack([c.lower, c.upper], axis=1)

    # ------------------------------------------------------------------ joint state
    def get_joint_positions(self, joint_indices=None) -> np.ndarray | None:
        """Joint positions (K,) [rad or m] (all joints for None)."""
        c = self._c("get_joint_positions")
        return None if c is None else c.sim.data.qpos[c.qadr[c.indices(joint_indices)]].copy()

    def get_joint_velocities(self, joint_indices=None) -> np.ndarray | None:
        """Joint velocities (K,) [rad/s or m/s]."""
        c = self._c("get_joint_velocities")
        return None if c is None else c.sim.data.qvel[c.dadr[c.indices(joint_indices)]].copy()

    def set_joint_positions(self, positions, joint_indices=None) -> None:
        """Teleport joints to `positions` (K,) and set their drive position targets to them.

        Velocities are kept. A position at most 1e-3 outside its joint's limits is put on the
        limit; farther outside, it is set with a warning and the next physics step puts the
        joint back on its limit (as Isaac: PhysX pushes it back). Raises InvalidInputError on
        a wrong length, a non-finite value or a magnitude above MAX_POSITION; nothing changes
        then.
        """
        self._cs("set_joint_positions").teleport(positions, joint_indices)

    def set_joint_velocities(self, velocities, joint_indices=None) -> None:
        """Set joint velocities (K,) [rad/s or m/s] (drive targets unchanged)."""
        self._cs("set_joint_velocities").set_velocities(velocities, joint_indices)

    def set_joint_efforts(self, efforts, joint_indices=None) -> None:
        """Set the joint efforts (K,) [N m or N] added to the drives (persist until changed).

        Raises InvalidInputError on a wrong length, a non-finite value or an effort that would
        alone accelerate its joint beyond `manip.sim.utils.bounds.MAX_EFFORT_ACCELERATION` (1e4
        rad/s^2 on the joint's inertia: 1.1e3 N m on the Franka's joint 7); nothing changes then.
        """
        c = self._cs("set_joint_efforts")
        idx = c.indices(joint_indices)
        e = c.values(efforts, idx, "efforts", limit=MAX_EFFORT, kind="effort")
        c.check_physical(e, idx, "efforts", "effort")
        c.efforts = c.efforts.copy()
        c.efforts[idx] = e
        c.write_targets()

    def get_applied_joint_efforts(self, joint_indices=None) -> np.ndarray | None:
        """Drive force plus applied effort per joint (K,) [N m or N], last physics substep."""
        c = self._c("get_applied_joint_efforts")
        return None if c is None else c.joint_forces(joint_indices, constraint=False)

    def get_measured_joint_efforts(self, joint_indices=None) -> np.ndarray | None:
        """Total generalized force on each joint from drives, applied efforts and constraints
        (limits, contacts) (K,) [N m or N], last physics substep."""
        c = self._c("get_measured_joint_efforts")
        return None if c is None else c.joint_forces(joint_indices, constraint=True)

    def get_joints_state(self) -> JointsState | None:
        c = self._c("get_joints_state")
        if c is None:
            return None
        return JointsState(self.get_joint_positions(), self.get_joint_velocities(), self.get_applied_joint_efforts())

    def set_joints_default_state(self, positions=None, velocities=None, efforts=None) -> None:
        """Joint state restored by `post_reset()`, (num_dof,) each; None keeps a part."""
        for what, v, limit in (("positions", positions, MAX_POSITION), ("velocities", velocities, MAX_VELOCITY),
                               ("efforts", efforts, MAX_EFFORT)):
            if v is None:
                continue
            try:
                a = np.asarray(v, dtype=float).ravel()
            except (TypeError, ValueError) as exc:
                raise InvalidInputError(f"default joint {what} must be a sequence of numbers; got {v!r}") from exc
            if not np.all(np.isfinite(a)):
                raise InvalidInputError(f"default joint {what} must be finite; got {a}")
            if np.any(np.abs(a) > limit):
                raise InvalidInputError(f"default joint {what} must have magnitudes <= {limit:g}; got {a}")
            if self._core is not None and a.size != self._core.n:
                raise InvalidInputError(f"default joint {what} need {self._core.n} entries; got {a.size}")
            if self._core is not None and what != "positions":
                self._core.check_physical(a, np.arange(a.size), f"default joint {what}",
                                        {"velocities": "velocity", "efforts": "effort"}[what])
            self._user_default_joints[what] = a.copy()
            if self._default_joints is not None:
                if what == "positions":
                    a = self._core.onto_limits(a, np.arange(a.size), "default joint positions")
                setattr(self._default_joints, what, a.copy())

    def get_joints_default_state(self) -> JointsState | None:
        if self._default_joints is None:
            logger.warning("%s.get_joints_default_state used before the first World.reset()", self._name)
            return None
        s = self._default_joints
        return JointsState(s.positions.copy(), s.velocities.copy(), s.efforts.copy())

    # ------------------------------------------------------------------ root pose
    def get_world_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Pose of the model's frame: position (3,) [m], orientation (4,) (w, x, y, z).

        Before the first `World.reset()` (or after the prim changed), the pose authored on
        the stage: the one given at construction or by `set_world_pose` since (as Isaac
        reads the prim's transform at any time).
        """
        c = self._core
        if c is None:
            if get_current_stage().get_prim(self.prim_path) is not self._ref:
                logger.warning("%s: its model was removed from the stage; no pose (None)", self._name)
                return None  # type: ignore[return-value]
            return self._ref.position.copy(), self._ref.orientation.copy()
        b = c.root_ids[0]
        if c.free_qadr >= 0:
            p, q = c.sim.free_pose(c.free_qadr)
        else:
            p, q = c.sim.model.body_pos[b].copy(), c.sim.model.body_quat[b].copy()
        lp, lq = c.root_local[0]
        qw = quat.multiply(q, quat.conjugate(lq))
        return p - quat.to_matrix(qw) @ lp, qw

    def set_world_pose(self, position=None, orientation=None) -> None:
        """Move the model's frame (teleport; a fixed base is moved with it).

        Before the first `World.reset()` the pose is authored on the stage: the model is
        compiled there, and `get_world_pose()` returns it. As in Isaac, `World.reset()` then
        restores the default state (the pose at construction): to keep the new pose across
        resets, also call `set_default_state(position, orientation)` (as Isaac's "Adding
        Multiple Robots" tutorial does).
        """
        c = self._core
        cur_p, cur_q = self.get_world_pose()
        p = bounded_vec(position, "position", "position") if position is not None else cur_p
        q = unit_quat(orientation) if orientation is not None else cur_q
        if c is None:
            self._ref.position, self._ref.orientation = p.copy(), q.copy()
            get_current_stage().mark_changed(self.prim_path)
            return
        c.set_root_pose(p, q)

    def get_local_pose(self):
        return self.get_world_pose()

    def set_local_pose(self, translation=None, orientation=None) -> None:
        self.set_world_pose(translation, orientation)

    def get_linear_velocity(self) -> np.ndarray | None:
        """Linear velocity of a floating base (3,) [m/s], world frame (zeros for a fixed base)."""
        c = self._c("get_linear_velocity")
        if c is None:
            return None
        if c.free_dadr < 0:
            return np.zeros(3)
        return c.sim.data.qvel[c.free_dadr:c.free_dadr + 3].copy()

    def get_angular_velocity(self) -> np.ndarray | None:
        """Angular velocity of a floating base (3,) [rad/s], world frame."""
        c = self._c("get_angular_velocity")
        if c is None:
            return None
        if c.free_dadr < 0:
            return np.zeros(3)
        return c.sim.free_angular_velocity(c.free_qadr, c.free_dadr)

    def get_articulation_body_count(self) -> int | None:
        """Number of bodies (None before the first reset)."""
        return self.num_bodies

    def set_linear_velocity(self, velocity) -> None:
        """Set a floating base's linear velocity (3,) [m/s], world frame.

        Raises:
            SimulationError: a fixed base (it cannot move).
        """
        c = self._floating("set_linear_velocity")
        c.sim.data.qvel[c.free_dadr:c.free_dadr + 3] = bounded_vec(velocity, "linear", "linear velocity")
        c.sim.mark_stale()

    def set_angular_velocity(self, velocity) -> None:
        """Set a floating base's angular velocity (3,) [rad/s], world frame.

        Raises:
            SimulationError: a fixed base (it cannot move).
        """
        c = self._floating("set_angular_velocity")
        c.sim.set_free_angular_velocity(c.free_qadr, c.free_dadr, bounded_vec(velocity, "angular", "angular velocity"))
        c.sim.mark_stale()

    def get_world_velocity(self) -> np.ndarray | None:
        """Root velocity (6,): linear [m/s] then angular [rad/s], world frame (zeros for a fixed base)."""
        lin = self.get_linear_velocity()
        return None if lin is None else np.concatenate([lin, self.get_angular_velocity()])

    def set_world_velocity(self, velocity) -> None:
        """Set a floating base's root velocity (6,): linear [m/s] then angular [rad/s], world frame.

        Raises:
            InvalidInputError: not 6 values. SimulationError: a fixed base.
        """
        v = np.asarray(velocity, dtype=float).ravel() if not isinstance(velocity, str) else np.zeros(0)
        if v.size != 6:
            raise InvalidInputError(f"velocity must be 6 values (linear [m/s], angular [rad/s]); got {velocity!r}")
        self._floating("set_world_velocity")
        self.set_linear_velocity(v[:3])
        self.set_angular_velocity(v[3:])

    def _floating(self, what: str) -> ArticulationCore:
        c = self._cs(what)
        if c.free_dadr < 0:
            raise SimulationError(f"{self._name}.{what}: the articulation's base is fixed; it has no root velocity")
        return c

    def disable_gravity(self) -> None:
        """No gravity on the articulation's bodies (each body's weight is cancelled at its
        centre of mass during every physics step; `manip.sim.core.substeps`)."""
        c = self._cs("disable_gravity")
        c.sim.gravity_off.update(int(b) for b in c.body_ids)

    def enable_gravity(self) -> None:
        c = self._cs("enable_gravity")
        c.sim.gravity_off.difference_update(int(b) for b in c.body_ids)

    # ------------------------------------------------------------------ control
    def get_articulation_controller(self) -> ArticulationController:
        return self._controller

    def apply_action(self, control_actions: ArticulationAction) -> None:
        """Same as `get_articulation_controller().apply_action(...)`."""
        self._controller.apply_action(control_actions)

    def get_applied_action(self) -> ArticulationAction | None:
        if self._c("get_applied_action") is None:
            return None
        return self._controller.get_applied_action()

    def post_reset(self) -> None:
        """Restore the root pose, the default joint state (positions become the targets,
        velocity targets 0) and the default gains and effort limits."""
        c = self._cs("post_reset")
        s = self._default_state
        self.set_world_pose(s.position, s.orientation)
        j = self._default_joints
        c.kps, c.kds = c.default_kps.copy(), c.default_kds.copy()
        c.max_efforts = c.default_max_efforts.copy()
        c.sim.data.qpos[c.qadr] = j.positions
        c.sim.data.qvel[c.dadr] = j.velocities
        c.pos_target = j.positions.copy()
        c.vel_target = np.zeros(c.n)
        c.efforts = j.efforts.copy()
        c.write_gains()
        c.sim.mark_stale()

    def __repr__(self) -> str:
        return f"{type(self).__name__}(prim_path={self.prim_path!r}, name={self._name!r})"


class Robot(Articulation):
    """An articulation with sensors/grippers (Isaac's `Robot`); same API as `Articulation`."""

    def __init__(self, prim_path: str, name: str = "robot", position=None, translation=None, orientation=None,
                 scale=None, visible=None, articulation_controller=None, **kwargs):
        super().__init__(prim_path, name, position, translation, orientation, scale, visible,
                         articulation_controller, **kwargs)


SingleArticulation = Articulation
isaac5_views.register(Articulation, ArticulationView)


declare_not_supported(Articulation)
declare_not_supported(Robot)
