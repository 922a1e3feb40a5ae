"""Articulations: `Articulation`/`Robot`, their implicit PD drives and `ArticulationController`.

Drives (Isaac's implicit joint drives): every hinge/slide joint of a referenced model has
one MuJoCo actuator whose force is

    f = clip(kp * (q_target - q) + kd * (v_target - v), -max_effort, max_effort)

applied as `ctrl = kp q_target + kd v_target` with the bias `-kp q - kd v`; MuJoCo's
`implicitfast` integrator treats the damping term implicitly, so stiff gains are stable.
The model's own actuators give the default gains: a `position` actuator gives kp and kv,
a `velocity` actuator gives kd (kp = 0), a `motor` gives kp = kd = 0; joints without an
actuator get one with kp = kd = 0. Efforts (effort mode) are added as joint forces, not
clipped. Actuators with a gear other than 1 are not supported (the gear is reset to 1).

Getters used before the first `World.reset()` return None and log a warning (Isaac's
behaviour); setters raise `SimulationError`.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import _validate as V
from manip.sim.stage import ReferencePrim, SimHandle, SimulationError, get_current_stage, validate_prim_path
from manip.sim.types import DefaultPoseMixin, JointsState, XFormPrimState

logger = logging.getLogger(__name__)

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

CONTROL_MODES = ("position", "velocity", "effort")
_HINGE = int(mujoco.mjtJoint.mjJNT_HINGE)
_SLIDE = int(mujoco.mjtJoint.mjJNT_SLIDE)
_LIMIT_TOLERANCE = 1e-3  # [rad or m] how far set_joint_positions may lie outside the limits


def _urdf_velocity_limits(file_path: Path) -> dict[str, float]:
    """Joint velocity limits from the URDF of the robot whose model is `file_path`.

    MJCF has no velocity limits; if the model's folder holds a manip `robot.yaml`, its URDF
    gives them. Returns {} when none is found.
    """
    try:
        from manip.robot_config import CONFIG_FILE, load_robot_config

        if file_path.suffix.lower() == ".urdf":
            urdf = file_path
        elif (file_path.parent / CONFIG_FILE).is_file():
            urdf = load_robot_config(file_path.parent).urdf_path
        else:
            return {}
        out = {}
        for joint in ET.parse(urdf).getroot().iter("joint"):
            limit = joint.find("limit")
            if limit is not None and limit.get("velocity") is not None:
                out[joint.get("name")] = float(limit.get("velocity"))
        return out
    except Exception as exc:  # the limits are informative; never fail the World over them
        logger.debug("no URDF velocity limits for %s: %s", file_path, exc)
        return {}


class ArticulationCore:
    """Index arrays, gains and drive targets of one referenced model in the compiled World.

    One per referenced prim, shared by every wrapper of that prim. Internal.
    """

    def __init__(self, ref: ReferencePrim, sim: SimHandle):
        m, d = sim.model, sim.data
        self.ref = ref
        self.sim = sim
        prefix = ref.prefix
        names = [m.joint(j).name for j in range(m.njnt)]
        jids = [
            j for j in range(m.njnt)
            if names[j].startswith(prefix) and int(m.jnt_type[j]) in (_HINGE, _SLIDE)
        ]
        self.joint_ids = np.array(jids, dtype=int)
        self.dof_names = [names[j][len(prefix):] for j in jids]
        self.n = len(jids)
        self.qadr = m.jnt_qposadr[self.joint_ids].astype(int)
        self.dadr = m.jnt_dofadr[self.joint_ids].astype(int)
        self.types = np.where(m.jnt_type[self.joint_ids] == _HINGE, 1, 2).astype(np.int32)
        self.has_limits = m.jnt_limited[self.joint_ids].astype(bool)
        rng = m.jnt_range[self.joint_ids]
        self.lower = np.where(self.has_limits, rng[:, 0], -np.inf)
        self.upper = np.where(self.has_limits, rng[:, 1], np.inf)
        # Bodies and roots.
        self.body_ids = np.array([b for b in range(m.nbody) if m.body(b).name.startswith(prefix)], dtype=int)
        self.body_names = [m.body(b).name[len(prefix):] for b in self.body_ids]
        self.root_ids = np.array([b for b in self.body_ids if m.body_parentid[b] == 0], dtype=int)
        self.free_qadr = -1
        self.free_dadr = -1
        if self.root_ids.size == 1:
            j = m.body_jntadr[self.root_ids[0]]
            if j >= 0 and int(m.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE):
                self.free_qadr = int(m.jnt_qposadr[j])
                self.free_dadr = int(m.jnt_dofadr[j])
        # Pose of each root body relative to the prim frame (fixed at compile time).
        T_world_prim_pos, T_world_prim_quat = ref.position.copy(), ref.orientation.copy()
        self.root_local = []
        for b in self.root_ids:
            if b == self.root_ids[0] and self.free_qadr >= 0:
                p, q = m.qpos0[self.free_qadr:self.free_qadr + 3], m.qpos0[self.free_qadr + 3:self.free_qadr + 7]
            else:
                p, q = m.body_pos[b], m.body_quat[b]
            qi = quat.conjugate(T_world_prim_quat)
            self.root_local.append((quat.to_matrix(qi) @ (p - T_world_prim_pos), quat.multiply(qi, q)))
        # Actuators, one per DoF.
        act_of_joint = {}
        for a in range(m.nu):
            if int(m.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT):
                act_of_joint.setdefault(int(m.actuator_trnid[a, 0]), a)
        missing = [self.dof_names[i] for i, j in enumerate(jids) if j not in act_of_joint]
        if missing:
            raise SimulationError(f"{ref.prim_path}: joints without an actuator: {missing}")
        self.act = np.array([act_of_joint[j] for j in jids], dtype=int)
        kp = np.zeros(self.n)
        kd = np.zeros(self.n)
        affine = m.actuator_biastype[self.act] == int(mujoco.mjtBias.mjBIAS_AFFINE)
        kp[affine] = -m.actuator_biasprm[self.act[affine], 1]
        kd[affine] = -m.actuator_biasprm[self.act[affine], 2]
        gear = m.actuator_gear[self.act, 0]
        if np.any(gear != 1.0):
            logger.warning("%s: actuator gears other than 1 are reset to 1", ref.prim_path)
        m.actuator_gear[self.act, 0] = 1.0
        m.actuator_gaintype[self.act] = mujoco.mjtGain.mjGAIN_FIXED
        m.actuator_gainprm[self.act, :] = 0.0
        m.actuator_gainprm[self.act, 0] = 1.0
        m.actuator_biastype[self.act] = mujoco.mjtBias.mjBIAS_AFFINE
        m.actuator_biasprm[self.act, :] = 0.0
        m.actuator_dyntype[self.act] = mujoco.mjtDyn.mjDYN_NONE
        m.actuator_ctrllimited[self.act] = 0
        self.default_kps = kp
        self.default_kds = kd
        self.default_max_efforts = np.where(
            m.actuator_forcelimited[self.act].astype(bool), np.abs(m.actuator_forcerange[self.act]).max(axis=1), np.inf
        )
        vlim = _urdf_velocity_limits(ref.file_path)
        self.max_velocities = np.array([vlim.get(n, np.inf) for n in self.dof_names])
        self.home = np.array([ref.home_qpos.get(n, m.qpos0[a]) for n, a in zip(self.dof_names, self.qadr)])
        # Drive state.
        self.kps = kp.copy()
        self.kds = kd.copy()
        self.max_efforts = self.default_max_efforts.copy()
        self.pos_target = d.qpos[self.qadr].copy()
        self.vel_target = np.zeros(self.n)
        self.efforts = np.zeros(self.n)
        self.write_gains()

    # ------------------------------------------------------------------ drive writes
    def write_gains(self) -> None:
        m = self.sim.model
        m.actuator_biasprm[self.act, 1] = -self.kps
        m.actuator_biasprm[self.act, 2] = -self.kds
        finite = np.isfinite(self.max_efforts)
        m.actuator_forcelimited[self.act] = finite.astype(np.uint8)
        m.actuator_forcerange[self.act, 0] = np.where(finite, -self.max_efforts, 0.0)
        m.actuator_forcerange[self.act, 1] = np.where(finite, self.max_efforts, 0.0)
        self.write_targets()

    def write_targets(self) -> None:
        d = self.sim.data
        d.ctrl[self.act] = self.kps * self.pos_target + self.kds * self.vel_target
        d.qfrc_applied[self.dadr] = self.efforts

    def indices(self, joint_indices) -> np.ndarray:
        """Validated joint indices (K,) (all joints for None)."""
        if joint_indices is None:
            return np.arange(self.n)
        idx = np.asarray(joint_indices).ravel()
        if idx.size and not np.issubdtype(idx.dtype, np.integer):
            raise InvalidInputError(f"joint_indices must be integers; got {joint_indices!r}")
        idx = idx.astype(int)
        if np.any(idx < 0) or np.any(idx >= self.n):
            raise InvalidInputError(
                f"joint_indices {idx.tolist()} out of range: this articulation has {self.n} DoF (0..{self.n - 1}): "
                f"{self.dof_names}"
            )
        if len(set(idx.tolist())) != idx.size:
            raise InvalidInputError(f"joint_indices has repeated entries: {idx.tolist()}")
        return idx

    def values(self, values, idx: np.ndarray, what: str, allow_nan: bool = False) -> np.ndarray:
        a = np.asarray(values, dtype=float).ravel()
        if a.size != idx.size:
            raise InvalidInputError(
                f"{what} has {a.size} entries but {idx.size} joints are addressed "
                f"({[self.dof_names[i] for i in idx]})"
            )
        bad = ~np.isfinite(a) if not allow_nan else np.isinf(a)
        if np.any(bad):
            raise InvalidInputError(f"{what} must be finite; got {a}")
        return a

    def apply_action(self, action: ArticulationAction) -> None:
        """Set drive targets from an action (Isaac's semantics); nothing changes on error."""
        if not isinstance(action, ArticulationAction):
            raise InvalidInputError(f"expected an ArticulationAction; got {type(action).__name__}")
        k = action.get_length()
        if k is None:
            return
        if action.joint_indices is None:
            if k != self.n:
                raise InvalidInputError(
                    f"the action has {k} entries but the articulation at {self.ref.prim_path} has {self.n} DoF "
                    f"{self.dof_names}; give joint_indices to address a subset"
                )
            idx = np.arange(self.n)
        else:
            idx = self.indices(action.joint_indices)
        pos, vel, eff = self.pos_target.copy(), self.vel_target.copy(), self.efforts.copy()
        if action.joint_positions is not None:
            p = action.joint_positions
            keep = np.isnan(p)
            pos[idx[~keep]] = p[~keep]
        if action.joint_velocities is not None:
            v = action.joint_velocities
            keep = np.isnan(v)
            vel[idx[~keep]] = v[~keep]
        if action.joint_efforts is not None:
            eff[idx] = np.nan_to_num(action.joint_efforts, nan=0.0)
        self.pos_target, self.vel_target, self.efforts = pos, vel, eff
        self.write_targets()

    def drive_modes(self) -> np.ndarray:
        return np.where(self.kps > 0, 1, np.where(self.kds > 0, 2, 0)).astype(np.int32)


class ArticulationController:
    """The implicit PD drives of an articulation (Isaac's `ArticulationController`)."""

    def __init__(self) -> None:
        self._articulation: Articulation | None = None

    def initialize(self, articulation: Articulation) -> None:
        """Attach to an articulation (done by `Articulation` when the World compiles)."""
        self._articulation = articulation

    def _core(self) -> ArticulationCore:
        if self._articulation is None or self._articulation._core is None:
            raise SimulationError("the articulation controller is used before World.reset() compiled the world")
        return self._articulation._core

    def apply_action(self, control_actions: ArticulationAction) -> None:
        """Set drive targets; they take effect from the next physics step and persist.

        A None field is untouched; a NaN (None) entry of positions/velocities keeps that
        joint's target; a NaN effort is 0.

        Raises:
            InvalidInputError: not an ArticulationAction, a length that differs from the
                number of DoF (without joint_indices) or from joint_indices, indices out
                of range. Targets are unchanged then.
        """
        self._core().apply_action(control_actions)

    def get_applied_action(self) -> ArticulationAction:
        """The current targets: positions, velocities and efforts, (num_dof,) each."""
        c = self._core()
        return ArticulationAction(c.pos_target.copy(), c.vel_target.copy(), c.efforts.copy())

    def set_gains(self, kps=None, kds=None, save_to_usd: bool = False) -> None:
        """Set the drive stiffness kps [N m/rad or N/m] and damping kds [N m s/rad or N s/m], (num_dof,)."""
        c = self._core()
        idx = np.arange(c.n)
        new_kp = c.values(kps, idx, "kps") if kps is not None else c.kps
        new_kd = c.values(kds, idx, "kds") if kds is not None else c.kds
        if np.any(new_kp < 0) or np.any(new_kd < 0):
            raise InvalidInputError("gains must be >= 0")
        c.kps, c.kds = new_kp.copy(), new_kd.copy()
        c.write_gains()

    def get_gains(self) -> tuple[np.ndarray, np.ndarray]:
        """(kps, kds), (num_dof,) each."""
        c = self._core()
        return c.kps.copy(), c.kds.copy()

    def switch_control_mode(self, mode: str, joint_indices=None) -> None:
        """Switch drives to "position" (default gains), "velocity" (kp = 0, default kd; if
        the default kd is 0, kd = 10 * default kp or 1e3) or "effort" (kp = kd = 0)."""
        if mode not in CONTROL_MODES:
            raise InvalidInputError(f"unknown control mode {mode!r}; valid: {list(CONTROL_MODES)}")
        c = self._core()
        idx = c.indices(joint_indices)
        kp, kd = c.kps.copy(), c.kds.copy()
        if mode == "position":
            kp[idx], kd[idx] = c.default_kps[idx], c.default_kds[idx]
        elif mode == "velocity":
            dkd = c.default_kds[idx]
            kp[idx] = 0.0
            kd[idx] = np.where(dkd > 0, dkd, np.where(c.default_kps[idx] > 0, 10 * c.default_kps[idx], 1e3))
        else:
            kp[idx], kd[idx] = 0.0, 0.0
        c.kps, c.kds = kp, kd
        c.write_gains()

    def switch_dof_control_mode(self, dof_index: int, mode: str) -> None:
        """`switch_control_mode` for one DoF."""
        self.switch_control_mode(mode, [dof_index])

    def set_max_efforts(self, values, joint_indices=None) -> None:
        """Clip of each drive's force [N m or N] (> 0; inf = unlimited)."""
        c = self._core()
        idx = c.indices(joint_indices)
        v = np.asarray(values, dtype=float).ravel()
        if v.size != idx.size or np.any(np.isnan(v)) or np.any(v <= 0):
            raise InvalidInputError(f"max efforts must be {idx.size} positive values; got {values!r}")
        c.max_efforts = c.max_efforts.copy()
        c.max_efforts[idx] = v
        c.write_gains()

    def get_max_efforts(self) -> np.ndarray:
        return self._core().max_efforts.copy()

    def get_joint_limits(self) -> np.ndarray:
        """(num_dof, 2) lower and upper position limits (-inf/inf if unlimited)."""
        c = self._core()
        return np.stack([c.lower, c.upper], axis=1)


class Articulation(DefaultPoseMixin):
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
        if position is not None and translation is not None:
            raise InvalidInputError("give either position (world) or translation (local), not both")
        p = position if position is not None else translation
        if p is not None:
            ref.position = V.vec(p, 3, "position")
        if orientation is not None:
            ref.orientation = V.unit_quat(orientation)
        if scale is not None and not np.allclose(np.asarray(scale, dtype=float), 1.0):
            raise InvalidInputError("scaling an articulation is not supported (scale must be 1)")
        self.prim_path = prim_path
        self._name = name
        self._ref = ref
        self._core: ArticulationCore | None = None
        self._controller = articulation_controller if articulation_controller is not None else ArticulationController()
        self._default_state = XFormPrimState(ref.position.copy(), ref.orientation.copy())
        self._default_joints: JointsState | None = None
        self._user_default_joints: dict = {}
        if self._ref.core is not None and p is not None:
            stage._changed("PRIM_CHANGED", prim_path)  # a compiled model: the new pose applies at reset
        stage.register_wrapper(self)

    # ------------------------------------------------------------------ binding
    def _bind(self, sim: SimHandle) -> None:
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
        self._default_joints = JointsState(
            pos.copy() if pos is not None else c.home.copy(),
            vel.copy() if vel is not None else np.zeros(c.n),
            eff.copy() if eff is not None else np.zeros(c.n),
        )

    def _unbind(self) -> None:
        self._core = None

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do: the World binds articulations when it compiles (kept for Isaac scripts)."""

    @property
    def handles_initialized(self) -> bool:
        return self._core is not None

    def is_valid(self) -> bool:
        return self._core is not None

    def _c(self, what: str) -> ArticulationCore | None:
        if self._core is None:
            logger.warning("%s.%s used before the first World.reset(); returning None", self._name, what)
        return self._core

    def _cs(self, what: str) -> ArticulationCore:
        if self._core is None:
            raise SimulationError(f"{self._name}.{what}: the world is not compiled yet; call world.reset() first")
        return self._core

    # ------------------------------------------------------------------ description
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
        if c is None:
            return None
        out = np.zeros(c.n, dtype=DOF_PROPERTIES_DTYPE)
        out["type"] = c.types
        out["hasLimits"] = c.has_limits
        out["lower"] = c.lower
        out["upper"] = c.upper
        out["driveMode"] = c.drive_modes()
        out["maxVelocity"] = c.max_velocities
        out["maxEffort"] = c.max_efforts
        out["stiffness"] = c.kps
        out["damping"] = c.kds
        return out

    def get_dof_limits(self) -> np.ndarray | None:
        c = self._c("get_dof_limits")
        return None if c is None else np.stack([c.lower, c.upper], axis=1)

    # ------------------------------------------------------------------ joint state
    def get_joint_positions(self, joint_indices=None) -> np.ndarray | None:
        """Joint positions (K,) [rad or m] (all joints for None)."""
        c = self._c("get_joint_positions")
        if c is None:
            return None
        return c.sim.data.qpos[c.qadr[c.indices(joint_indices)]].copy()

    def get_joint_velocities(self, joint_indices=None) -> np.ndarray | None:
        """Joint velocities (K,) [rad/s or m/s]."""
        c = self._c("get_joint_velocities")
        if c is None:
            return None
        return c.sim.data.qvel[c.dadr[c.indices(joint_indices)]].copy()

    def set_joint_positions(self, positions, joint_indices=None) -> None:
        """Teleport joints to `positions` (K,) and set their drive position targets to them.

        Velocities are kept. Raises InvalidInputError on a wrong length, a non-finite value or
        a position outside the joint limits (by more than 1e-3); nothing changes then.
        """
        c = self._cs("set_joint_positions")
        idx = c.indices(joint_indices)
        q = c.values(positions, idx, "positions")
        low, up = c.lower[idx], c.upper[idx]
        bad = (q < low - _LIMIT_TOLERANCE) | (q > up + _LIMIT_TOLERANCE)
        if np.any(bad):
            i = np.flatnonzero(bad)
            raise InvalidInputError(
                "positions outside the joint limits: "
                + ", ".join(f"{c.dof_names[idx[k]]}={q[k]:.4f} not in [{low[k]:.4f}, {up[k]:.4f}]" for k in i)
            )
        c.sim.data.qpos[c.qadr[idx]] = q
        c.pos_target = c.pos_target.copy()
        c.pos_target[idx] = q
        c.write_targets()
        c.sim.mark_stale()

    def set_joint_velocities(self, velocities, joint_indices=None) -> None:
        """Set joint velocities (K,) [rad/s or m/s] (drive targets unchanged)."""
        c = self._cs("set_joint_velocities")
        idx = c.indices(joint_indices)
        v = c.values(velocities, idx, "velocities")
        c.sim.data.qvel[c.dadr[idx]] = v
        c.sim.mark_stale()

    def set_joint_efforts(self, efforts, joint_indices=None) -> None:
        """Set the joint efforts (K,) [N m or N] added to the drives (persist until changed)."""
        c = self._cs("set_joint_efforts")
        idx = c.indices(joint_indices)
        e = c.values(efforts, idx, "efforts")
        c.efforts = c.efforts.copy()
        c.efforts[idx] = e
        c.write_targets()

    def get_applied_joint_efforts(self, joint_indices=None) -> np.ndarray | None:
        """Drive force plus applied effort per joint (K,) [N m or N], last physics substep."""
        c = self._c("get_applied_joint_efforts")
        if c is None:
            return None
        idx = c.indices(joint_indices)
        d = c.sim.data
        return d.qfrc_actuator[c.dadr[idx]] + d.qfrc_applied[c.dadr[idx]]

    def get_measured_joint_efforts(self, joint_indices=None) -> np.ndarray | None:
        """Total generalized force on each joint from drives, applied efforts and constraints
        (limits, contacts) (K,) [N m or N], last physics substep."""
        c = self._c("get_measured_joint_efforts")
        if c is None:
            return None
        idx = c.indices(joint_indices)
        d = c.sim.data
        a = c.dadr[idx]
        return d.qfrc_actuator[a] + d.qfrc_applied[a] + d.qfrc_constraint[a]

    def get_joints_state(self) -> JointsState | None:
        c = self._c("get_joints_state")
        if c is None:
            return None
        return JointsState(self.get_joint_positions(), self.get_joint_velocities(), self.get_applied_joint_efforts())

    def set_joints_default_state(self, positions=None, velocities=None, efforts=None) -> None:
        """Joint state restored by `post_reset()`, (num_dof,) each; None keeps a part."""
        for what, v in (("positions", positions), ("velocities", velocities), ("efforts", efforts)):
            if v is None:
                continue
            a = np.asarray(v, dtype=float).ravel()
            if not np.all(np.isfinite(a)):
                raise InvalidInputError(f"default joint {what} must be finite")
            if self._core is not None and a.size != self._core.n:
                raise InvalidInputError(f"default joint {what} need {self._core.n} entries; got {a.size}")
            self._user_default_joints[what] = a.copy()
            if self._default_joints is not None:
                setattr(self._default_joints, what, a.copy())

    def get_joints_default_state(self) -> JointsState | None:
        if self._default_joints is None:
            logger.warning("%s.get_joints_default_state used before the first World.reset()", self._name)
            return None
        s = self._default_joints
        return JointsState(s.positions.copy(), s.velocities.copy(), s.efforts.copy())

    # ------------------------------------------------------------------ root pose
    def get_world_pose(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Pose of the model's frame: position (3,) [m], orientation (4,) (w, x, y, z)."""
        c = self._c("get_world_pose")
        if c is None:
            return None
        d = c.sim.data
        b = c.root_ids[0]
        if c.free_qadr >= 0:
            p, q = d.qpos[c.free_qadr:c.free_qadr + 3].copy(), d.qpos[c.free_qadr + 3:c.free_qadr + 7].copy()
            q = q / np.linalg.norm(q)
        else:
            p, q = c.sim.model.body_pos[b].copy(), c.sim.model.body_quat[b].copy()
        lp, lq = c.root_local[0]
        qw = quat.multiply(q, quat.conjugate(lq))
        return p - quat.to_matrix(qw) @ lp, qw

    def set_world_pose(self, position=None, orientation=None) -> None:
        """Move the model's frame (teleport; a fixed base is moved with it)."""
        c = self._cs("set_world_pose")
        cur_p, cur_q = self.get_world_pose()
        p = V.vec(position, 3, "position") if position is not None else cur_p
        q = V.unit_quat(orientation) if orientation is not None else cur_q
        R = quat.to_matrix(q)
        m, d = c.sim.model, c.sim.data
        for k, b in enumerate(c.root_ids):
            lp, lq = c.root_local[k]
            bp, bq = p + R @ lp, quat.multiply(q, lq)
            if k == 0 and c.free_qadr >= 0:
                d.qpos[c.free_qadr:c.free_qadr + 3] = bp
                d.qpos[c.free_qadr + 3:c.free_qadr + 7] = bq
            else:
                m.body_pos[b] = bp
                m.body_quat[b] = bq
        c.sim.mark_stale()

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
        d = c.sim.data
        q = d.qpos[c.free_qadr + 3:c.free_qadr + 7]
        return quat.to_matrix(q / np.linalg.norm(q)) @ d.qvel[c.free_dadr + 3:c.free_dadr + 6]

    def disable_gravity(self) -> None:
        """Compensate gravity on every body of the articulation (MuJoCo `gravcomp`)."""
        c = self._cs("disable_gravity")
        c.sim.model.body_gravcomp[c.body_ids] = 1.0

    def enable_gravity(self) -> None:
        c = self._cs("enable_gravity")
        c.sim.model.body_gravcomp[c.body_ids] = 0.0

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
