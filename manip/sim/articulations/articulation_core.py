"""`ArticulationCore`: the drives, index arrays and state of one referenced model in the compiled World.

The World creates one core per `ReferencePrim` when it compiles the stage (and drops it on
the next compile); every `Articulation` wrapping that prim shares it. Internal: the public
API is `Articulation` and `ArticulationController`. The drive law and the joint limits are
documented in `manip.sim.articulations.articulation`.

Every command is checked here before it reaches MuJoCo: non-finite values and magnitudes
beyond `MAX_POSITION`, `MAX_VELOCITY`, `MAX_EFFORT` raise InvalidInputError naming the
argument, and so does a drive command (kp * target + kd * velocity target) beyond
`MAX_DRIVE_COMMAND`, which MuJoCo would treat as a numerical failure. Set velocities and
applied efforts are also held to the physical bounds of `manip.sim.utils.bounds` (joint speeds,
the acceleration an effort alone gives its joint).
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.robot_config import CONFIG_FILE, load_robot_config
from manip.sim.scenes.robot_overlaps import RobotsOverlapError, check_moved_robot
from manip.sim.scenes.stage import ReferencePrim, SimHandle, SimulationError
from manip.sim.utils import bounds

logger = logging.getLogger(__name__)

_HINGE = int(mujoco.mjtJoint.mjJNT_HINGE)
_SLIDE = int(mujoco.mjtJoint.mjJNT_SLIDE)

#: Largest accepted magnitude of a joint position or position target [rad or m]. A limited
#: joint's target beyond its limit is accepted (the joint stops at the limit); 1e300 is not.
MAX_POSITION = 1e6
#: Largest accepted magnitude of a joint velocity or velocity target [rad/s or m/s].
MAX_VELOCITY = 1e6
#: Largest accepted magnitude of an applied joint effort [N m or N] (the Franka's largest
#: drive torque is 87 N m).
MAX_EFFORT = 1e6
#: Largest accepted drive command kp * position target + kd * velocity target [N m or N]:
#: MuJoCo treats a control above 1e10 as a numerical failure and ignores every control.
MAX_DRIVE_COMMAND = 1e9
#: How far outside its limits `teleport` (set_joint_positions) accepts a position [rad or m]:
#: it is put on the limit.
LIMIT_TOLERANCE = 1e-3
#: Solver impedance of the joint limits (MuJoCo `solimp` dmin, dmax, width): harder than
#: MuJoCo's default (0.9, 0.95, 0.001). Their time constant is two integration substeps, the
#: stiffest MuJoCo allows.
LIMIT_SOLIMP = (0.95, 0.99, 0.001)

_UNITS = {"position": "rad or m", "velocity": "rad/s or m/s", "effort": "N m or N"}


def _urdf_velocity_limits(file_path: Path) -> dict[str, float]:
    """Joint velocity limits from the URDF of the robot whose model is `file_path`.

    MJCF has no velocity limits; if the model's folder holds a manip `robot.yaml`, its URDF
    gives them. Returns {} when none is found.
    """
    try:
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
        # Joint limits as hard as MuJoCo's soft constraints get (PhysX's are hard); what is
        # left of an excursion is removed after every physics step (`enforce_limits`).
        self._lim = np.flatnonzero(self.has_limits)
        self.stiffen_limits()
        self._lim_qadr = self.qadr[self._lim]
        self._lim_dadr = self.dadr[self._lim]
        self._lim_lower = self.lower[self._lim]
        self._lim_upper = self.upper[self._lim]
        self._qpos, self._qvel = d.qpos, d.qvel  # views into the MjData (its buffers never move)
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
        kp[affine] = 0.0 - m.actuator_biasprm[self.act[affine], 1]  # 0.0 - x: no negative zeros
        kd[affine] = 0.0 - m.actuator_biasprm[self.act[affine], 2]
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

    def stiffen_limits(self) -> None:
        """Joint limit constraints with a time constant of two integration substeps (the
        stiffest MuJoCo allows) and the impedance LIMIT_SOLIMP; call again when the step changes."""
        m = self.sim.model
        lim = self.joint_ids[self._lim]
        m.jnt_solref[lim] = [2.0 * m.opt.timestep, 1.0]
        m.jnt_solimp[lim, :3] = LIMIT_SOLIMP

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

    def drive_commands(self, kps: np.ndarray, kds: np.ndarray, pos_target: np.ndarray,
                       vel_target: np.ndarray) -> np.ndarray:
        """MuJoCo controls (n,) of the drives: kp * (position target clipped into the joint
        limits) + kd * velocity target. A target beyond a limit drives the joint to the limit,
        where it stops (as PhysX's hard limits stop it)."""
        return kps * np.clip(pos_target, self.lower, self.upper) + kds * vel_target

    def check_drive(self, kps: np.ndarray, kds: np.ndarray, pos_target: np.ndarray, vel_target: np.ndarray,
                    what: str) -> None:
        """Raise InvalidInputError naming `what` if a drive command would exceed MAX_DRIVE_COMMAND."""
        ctrl = self.drive_commands(kps, kds, pos_target, vel_target)
        bad = np.flatnonzero(~(np.abs(ctrl) <= MAX_DRIVE_COMMAND))
        if bad.size:
            i = int(bad[0])
            raise InvalidInputError(
                f"{what}: the drive command of joint {self.dof_names[i]!r}, kp * position target + kd * velocity "
                f"target = {kps[i]:.4g} * {pos_target[i]:.4g} + {kds[i]:.4g} * {vel_target[i]:.4g} = {ctrl[i]:.4g}, "
                f"exceeds {MAX_DRIVE_COMMAND:g} (MuJoCo would treat it as a numerical failure); use a smaller "
                "target or gain"
            )

    def write_targets(self) -> None:
        d = self.sim.data
        d.ctrl[self.act] = self.drive_commands(self.kps, self.kds, self.pos_target, self.vel_target)
        d.qfrc_applied[self.dadr] = self.efforts

    def enforce_limits(self) -> None:
        """Put every limited joint that lies beyond a limit back on it, and stop its motion
        outward (called after every physics step: the limits hold as in Isaac).

        MuJoCo's limits are soft constraints: a joint driven fast into a limit, or pressed
        against it by an effort, goes slightly past it within a step (with the stiff limits
        set here, < 1 mrad pressed by the Franka's full 87 N m).
        """
        if not self._lim.size:
            return
        qpos, qvel = self._qpos, self._qvel
        q = qpos[self._lim_qadr]
        low = q < self._lim_lower
        high = q > self._lim_upper
        if not (low.any() or high.any()):
            return
        np.maximum(q, self._lim_lower, out=q)
        np.minimum(q, self._lim_upper, out=q)
        qpos[self._lim_qadr] = q
        v = qvel[self._lim_dadr]
        v[(low & (v < 0.0)) | (high & (v > 0.0))] = 0.0
        qvel[self._lim_dadr] = v
        self.sim.mark_stale()

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

    def values(self, values, idx: np.ndarray, what: str, *, allow_nan: bool = False, limit: float | None = None,
               kind: str = "") -> np.ndarray:
        """`values` as (K,) floats, one per addressed joint `idx` (K,); finite (NaN allowed with
        allow_nan) and, with `limit`, of magnitude <= limit (`kind`: "position", "velocity" or
        "effort", for the unit in the message). Messages name the argument `what`."""
        try:
            a = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(f"{what} must be a sequence of numbers; got {values!r}") from exc
        if a.size != idx.size:
            raise InvalidInputError(
                f"{what} has {a.size} entries but {idx.size} joints are addressed "
                f"({[self.dof_names[i] for i in idx]})"
            )
        bad = ~np.isfinite(a) if not allow_nan else np.isinf(a)
        if np.any(bad):
            raise InvalidInputError(f"{what} must be finite; got {a}")
        if limit is not None:
            check_magnitude(a, limit, what, [self.dof_names[i] for i in idx], kind)
        return a

    def check_physical(self, a: np.ndarray, idx: np.ndarray, what: str, kind: str) -> None:
        """Raise InvalidInputError naming `what` and the joints if velocities (kind "velocity")
        or efforts ("effort") `a` (K,) of joints `idx` exceed `manip.sim.utils.bounds`."""
        names = [self.dof_names[i] for i in idx]
        revolute = self.types[idx] == 1
        if kind == "velocity":
            bounds.check_joint_speeds(a, revolute, names, what)
        else:
            m0 = self.sim.model.dof_M0[self.dadr[idx]]   # diagonal inertia at the reference configuration
            bounds.check_efforts(a, np.where(m0 > 0, m0, np.inf), revolute, names, what)

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
        names = [self.dof_names[i] for i in idx]
        for field, limit, kind in (("joint_positions", MAX_POSITION, "position"),
                                   ("joint_velocities", MAX_VELOCITY, "velocity"),
                                   ("joint_efforts", MAX_EFFORT, "effort")):
            values = getattr(action, field)
            if values is not None:
                check_magnitude(np.asarray(values, dtype=float), limit, f"ArticulationAction.{field}", names, kind)
        if action.joint_efforts is not None:
            self.check_physical(np.asarray(action.joint_efforts, dtype=float), idx, "ArticulationAction.joint_efforts",
                                "effort")
        pos = _merge_targets(self.pos_target, idx, action.joint_positions)
        vel = _merge_targets(self.vel_target, idx, action.joint_velocities)
        eff = self.efforts.copy()
        if action.joint_efforts is not None:
            eff[idx] = np.nan_to_num(action.joint_efforts, nan=0.0)
        self.check_drive(self.kps, self.kds, pos, vel, "ArticulationAction.joint_positions/joint_velocities")
        self.pos_target, self.vel_target, self.efforts = pos, vel, eff
        self.write_targets()

    def set_root_pose(self, position: np.ndarray, orientation: np.ndarray) -> None:
        """Teleport the model's frame to `position` (3,) [m], `orientation` (4,) (w, x, y, z)
        (validated by the caller); a fixed base moves with it. Into another robot, it raises
        `RobotsOverlapError` and the robot stays where it was (`scenes.robot_overlaps`)."""
        before = self._root_state()
        self._place_root(position, orientation)
        cores = list(self.sim.robot_cores)
        if len(cores) > 1:
            try:
                check_moved_robot(self, cores)
            except RobotsOverlapError:
                self._restore_root(before)
                raise

    def _root_state(self) -> tuple:
        m, d = self.sim.model, self.sim.data
        free = d.qpos[self.free_qadr:self.free_qadr + 7].copy() if self.free_qadr >= 0 else None
        return free, m.body_pos[self.root_ids].copy(), m.body_quat[self.root_ids].copy()

    def _restore_root(self, state: tuple) -> None:
        free, pos, rot = state
        if free is not None:
            self.sim.data.qpos[self.free_qadr:self.free_qadr + 7] = free
        self.sim.model.body_pos[self.root_ids], self.sim.model.body_quat[self.root_ids] = pos, rot
        self.sim.mark_stale()

    def _place_root(self, position: np.ndarray, orientation: np.ndarray) -> None:
        R = quat.to_matrix(orientation)
        m, d = self.sim.model, self.sim.data
        for k, b in enumerate(self.root_ids):
            lp, lq = self.root_local[k]
            bp, bq = position + R @ lp, quat.multiply(orientation, lq)
            if k == 0 and self.free_qadr >= 0:
                d.qpos[self.free_qadr:self.free_qadr + 3] = bp
                d.qpos[self.free_qadr + 3:self.free_qadr + 7] = bq
            else:
                m.body_pos[b] = bp
                m.body_quat[b] = bq
        self.sim.mark_stale()

    def onto_limits(self, positions: np.ndarray, idx: np.ndarray, what: str) -> np.ndarray:
        """`positions` (K,) of joints `idx` (K,) put inside the joint limits, with a warning
        naming the joints moved by more than LIMIT_TOLERANCE (for default states, which a
        reset teleports to: PhysX would push such joints back onto their limits)."""
        low, up = self.lower[idx], self.upper[idx]
        out = np.clip(positions, low, up)
        far = np.flatnonzero(np.abs(out - positions) > LIMIT_TOLERANCE)
        if far.size:
            logger.warning(
                "%s: %s outside the joint limits: %s; the joints start on their limits (as PhysX's limits hold "
                "them)", self.ref.prim_path, what,
                ", ".join(f"{self.dof_names[idx[k]]}={positions[k]:.4f} not in [{low[k]:.4f}, {up[k]:.4f}]"
                          for k in far))
        return out

    def teleport(self, positions, joint_indices=None) -> None:
        """Put joints `joint_indices` (all for None) at `positions` (K,) [rad or m] and make
        these their position targets (Isaac's `set_joint_positions`); velocities are kept.

        A position at most `LIMIT_TOLERANCE` outside its limits is put on the limit. A
        position farther outside is set as given, with a warning naming the joints, as Isaac
        sets it: the next physics step puts the joint back on its limit (as PhysX's limits
        push it back), and the drive aims at the limit.

        Raises:
            InvalidInputError: a wrong length, a non-finite value or a magnitude above
                MAX_POSITION; nothing changes then.
        """
        idx = self.indices(joint_indices)
        q = self.values(positions, idx, "positions", limit=MAX_POSITION, kind="position")
        low, up = self.lower[idx], self.upper[idx]
        far = (q < low - LIMIT_TOLERANCE) | (q > up + LIMIT_TOLERANCE)
        if far.any():
            logger.warning(
                "%s: set_joint_positions outside the joint limits: %s; set as given, the next physics step puts "
                "these joints back on their limits (as PhysX's limits do)", self.ref.prim_path,
                ", ".join(f"{self.dof_names[idx[k]]}={q[k]:.4f} not in [{low[k]:.4f}, {up[k]:.4f}]"
                          for k in np.flatnonzero(far)))
        q = np.where(far, q, np.clip(q, low, up))
        target = self.pos_target.copy()
        target[idx] = q
        self.check_drive(self.kps, self.kds, target, self.vel_target, "positions")
        self.sim.data.qpos[self.qadr[idx]] = q
        self.pos_target = target
        self.write_targets()
        self.sim.mark_stale()

    def set_velocities(self, velocities, joint_indices=None) -> None:
        """Set the velocities (K,) [rad/s or m/s] of joints `joint_indices` (all for None);
        drive targets unchanged.

        Raises:
            InvalidInputError: a wrong length, a non-finite value or a speed above
                `manip.sim.utils.bounds.MAX_JOINT_SPEED` (100 rad/s; prismatic: 10 m/s).
        """
        idx = self.indices(joint_indices)
        v = self.values(velocities, idx, "velocities", limit=MAX_VELOCITY, kind="velocity")
        self.check_physical(v, idx, "velocities", "velocity")
        self.sim.data.qvel[self.dadr[idx]] = v
        self.sim.mark_stale()

    def reset_drive_targets(self) -> None:
        """Position targets = current joint positions, velocity targets and efforts 0."""
        self.pos_target = self.sim.data.qpos[self.qadr].copy()
        self.vel_target = np.zeros(self.n)
        self.efforts = np.zeros(self.n)
        self.write_targets()

    def joint_forces(self, joint_indices, *, constraint: bool) -> np.ndarray:
        """Drive force plus applied effort (K,) [N m or N] on the addressed joints, last
        physics substep; with `constraint`, plus the constraint forces (limits, contacts)."""
        d = self.sim.data
        a = self.dadr[self.indices(joint_indices)]
        f = d.qfrc_actuator[a] + d.qfrc_applied[a]
        return f + d.qfrc_constraint[a] if constraint else f

    def drive_modes(self) -> np.ndarray:
        return np.where(self.kps > 0, 1, np.where(self.kds > 0, 2, 0)).astype(np.int32)


def check_magnitude(values: np.ndarray, limit: float, what: str, names: list[str], kind: str = "") -> None:
    """Raise InvalidInputError naming `what` (and the joint) if an entry of `values` (K,)
    (NaN entries ignored) has a magnitude above `limit`; `names` (K,) are the joints."""
    with np.errstate(invalid="ignore"):
        bad = np.flatnonzero(np.abs(values) > limit)
    if bad.size:
        k = int(bad[0])
        unit = f" [{_UNITS[kind]}]" if kind in _UNITS else ""
        raise InvalidInputError(
            f"{what}[{k}] = {values[k]:.4g} (joint {names[k]!r}) exceeds the largest accepted magnitude "
            f"{limit:g}{unit}"
        )


def _merge_targets(current: np.ndarray, idx: np.ndarray, values) -> np.ndarray:
    """A copy of `current` (n,) with `values` (K,) written at `idx` (K,), NaN entries skipped."""
    out = current.copy()
    if values is not None:
        keep = np.isnan(values)
        out[idx[~keep]] = values[~keep]
    return out
