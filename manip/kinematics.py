"""Forward kinematics and Jacobians of a robot's arm, single (Pinocchio) and batched (compiled).

`Kinematics` holds the Pinocchio model reduced to the arm joints (the gripper joints locked
at their planning positions). Single configurations go through Pinocchio's C++; batches of
configurations go through the same joint tree as constant tables evaluated by small numba
kernels (`chain_frames`, `frame_jacobian_into`), which the collision checker and the IK
solver also call from their own compiled loops. Tests hold both paths to Pinocchio's answers.

Threads: a `Kinematics` may be shared. Pinocchio's work space (`pin.Data`) is per thread
(`data`), the compiled kernels allocate their own outputs and release the GIL, and every
table is read-only after construction.
"""

from __future__ import annotations

import copy
import math
import threading
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from manip import curobo_names
from manip import quaternion as quat
from manip.errors import InvalidInputError, UnknownNameError
from manip.jit import kernel, kernel_array
from manip.limits import JointLimits
from manip.pose import Pose
from manip.robot_config import RobotConfig
from manip.urdf import build_model
from manip.validation import as_real_array

#: Batched evaluations run in chunks of this many configurations (temporaries stay in cache).
_CHUNK = 2048
#: `joint_transforms` of at least this many configurations runs `_joint_frames_lanes` (fewer: the
#: per-configuration kernel, cheaper there), `FK_LANES` configurations at a time.
FK_LANES_FROM = 16
FK_LANES = 64

_AXES = {"X": np.array([1.0, 0.0, 0.0]), "Y": np.array([0.0, 1.0, 0.0]), "Z": np.array([0.0, 0.0, 1.0])}


@dataclass(frozen=True)
class JointSpec:
    """One joint of the reduced model (the source of the compiled kernels' tables)."""

    parent: int          # index of the parent joint (0 = universe)
    R_placement: np.ndarray  # (3, 3) rotation of the joint frame in its parent joint frame
    p_placement: np.ndarray  # (3,)
    axis: np.ndarray     # (3,) unit axis in the joint frame
    revolute: bool
    q_index: int         # index into q


def _joint_spec(model: pin.Model, j: int) -> JointSpec:
    jm = model.joints[j]
    name = jm.shortname()
    if name.startswith("JointModelR") and name[-1] in _AXES:
        axis, revolute = _AXES[name[-1]], True
    elif name.startswith("JointModelP") and name[-1] in _AXES:
        axis, revolute = _AXES[name[-1]], False
    elif name == "JointModelRevoluteUnaligned":
        axis, revolute = np.asarray(jm.extract().axis, dtype=float), True
    elif name == "JointModelPrismaticUnaligned":
        axis, revolute = np.asarray(jm.extract().axis, dtype=float), False
    else:
        raise InvalidInputError(
            f"joint '{model.names[j]}' is of type {name}; manip supports revolute and prismatic joints"
        )
    M = model.jointPlacements[j]
    return JointSpec(int(model.parents[j]), M.rotation.copy(), M.translation.copy(), axis, revolute, jm.idx_q)


@kernel
def chain_frames(q, q_index, parent, table, R, p):
    """Joint frames of one configuration q (dof,) into R (J+1, 3, 3), p (J+1, 3).

    A joint's transform in its parent's frame is `A + cos(q) C + sin(q) S (+ q D)`, with the
    4x4 tables flattened in `table` (J, 3 or 4, 16) (`Kinematics.fk_tables`); frame 0 is the
    base (identity).
    """
    J = table.shape[0]
    prismatic = table.shape[1] > 3
    B = np.empty(16)
    for r in range(3):
        p[0, r] = 0.0
        for c in range(3):
            R[0, r, c] = 1.0 if r == c else 0.0
    for j in range(J):
        qj = q[q_index[j]]
        cq = math.cos(qj)
        sq = math.sin(qj)
        for e in range(16):
            B[e] = table[j, 0, e] + cq * table[j, 1, e] + sq * table[j, 2, e]
            if prismatic:
                B[e] += qj * table[j, 3, e]
        a = parent[j]
        for r in range(3):
            for c in range(3):
                R[j + 1, r, c] = R[a, r, 0] * B[c] + R[a, r, 1] * B[4 + c] + R[a, r, 2] * B[8 + c]
            p[j + 1, r] = R[a, r, 0] * B[3] + R[a, r, 1] * B[7] + R[a, r, 2] * B[11] + p[a, r]


@kernel
def _joint_frames(Q, q_index, parent, table):
    """Batched forward kinematics: joint frames R (N, J+1, 3, 3), p (N, J+1, 3) of Q (N, dof)."""
    N = Q.shape[0]
    J = table.shape[0]
    R = np.empty((N, J + 1, 3, 3))
    p = np.empty((N, J + 1, 3))
    for n in range(N):
        chain_frames(Q[n], q_index, parent, table, R[n], p[n])
    return R, p


@kernel
def _joint_frames_lanes(Q, q_index, parent, table, lanes):
    """`_joint_frames` (the same R, p bit for bit: the same operations on the same operands),
    computed `lanes` configurations at a time with the configuration index innermost (each
    joint's rotation and position as (9, lanes) and (3, lanes) arrays: loops the compiler
    vectorises), then laid out as (N, J+1, ...)."""
    N = Q.shape[0]
    J = table.shape[0]
    prismatic = table.shape[1] > 3
    R = np.empty((N, J + 1, 3, 3))
    p = np.empty((N, J + 1, 3))
    RS = np.empty((J + 1, 9, lanes))
    PS = np.empty((J + 1, 3, lanes))
    for e in range(9):
        RS[0, e, :] = 1.0 if e % 4 == 0 else 0.0
    PS[0] = 0.0
    cq = np.empty(lanes)
    sq = np.empty(lanes)
    B = np.empty((12, lanes))
    for s in range(0, N, lanes):
        L = min(lanes, N - s)
        for j in range(J):
            qi = q_index[j]
            for n in range(L):
                cq[n] = math.cos(Q[s + n, qi])
                sq[n] = math.sin(Q[s + n, qi])
            for e in range(12):   # the rows of the joint's 4x4 transform that are read
                t0, t1, t2 = table[j, 0, e], table[j, 1, e], table[j, 2, e]
                Be = B[e]
                for n in range(L):
                    Be[n] = t0 + cq[n] * t1 + sq[n] * t2
                if prismatic:
                    t3 = table[j, 3, e]
                    for n in range(L):
                        Be[n] += Q[s + n, qi] * t3
            a = parent[j]
            for r in range(3):
                A0, A1, A2 = RS[a, 3 * r], RS[a, 3 * r + 1], RS[a, 3 * r + 2]
                for c in range(3):
                    out = RS[j + 1, 3 * r + c]
                    Bc, B4, B8 = B[c], B[4 + c], B[8 + c]
                    for n in range(L):
                        out[n] = A0[n] * Bc[n] + A1[n] * B4[n] + A2[n] * B8[n]
                out = PS[j + 1, r]
                pa = PS[a, r]
                B3, B7, B11 = B[3], B[7], B[11]
                for n in range(L):
                    out[n] = A0[n] * B3[n] + A1[n] * B7[n] + A2[n] * B11[n] + pa[n]
        for n in range(L):
            for j in range(J + 1):
                for r in range(3):
                    for c in range(3):
                        R[s + n, j, r, c] = RS[j, 3 * r + c, n]
                    p[s + n, j, r] = PS[j, r, n]
    return R, p


@kernel
def frame_jacobian_into(R, p, chain, axes, revolute, q_index, f_joint, f_R, f_p, Rf, pf, Jac):
    """Pose Rf (3, 3), pf (3,) of a frame and its (6, dof) world-aligned Jacobian
    [linear; angular] into Jac, from the joint frames R, p of `chain_frames`.

    chain: the joints (1-based) supporting the frame; axes (J, 3), revolute (J,): each joint's
    axis in its own frame; f_joint, f_R (3, 3), f_p (3,): the frame's placement in its joint.
    """
    for r in range(3):
        for c in range(3):
            Rf[r, c] = R[f_joint, r, 0] * f_R[0, c] + R[f_joint, r, 1] * f_R[1, c] + R[f_joint, r, 2] * f_R[2, c]
        pf[r] = R[f_joint, r, 0] * f_p[0] + R[f_joint, r, 1] * f_p[1] + R[f_joint, r, 2] * f_p[2] + p[f_joint, r]
    Jac[:, :] = 0.0
    for j in chain:
        ax = axes[j - 1]
        a0 = R[j, 0, 0] * ax[0] + R[j, 0, 1] * ax[1] + R[j, 0, 2] * ax[2]
        a1 = R[j, 1, 0] * ax[0] + R[j, 1, 1] * ax[1] + R[j, 1, 2] * ax[2]
        a2 = R[j, 2, 0] * ax[0] + R[j, 2, 1] * ax[1] + R[j, 2, 2] * ax[2]
        c = q_index[j - 1]
        if revolute[j - 1]:
            d0 = pf[0] - p[j, 0]
            d1 = pf[1] - p[j, 1]
            d2 = pf[2] - p[j, 2]
            Jac[0, c] = a1 * d2 - a2 * d1
            Jac[1, c] = a2 * d0 - a0 * d2
            Jac[2, c] = a0 * d1 - a1 * d0
            Jac[3, c] = a0
            Jac[4, c] = a1
            Jac[5, c] = a2
        else:
            Jac[0, c] = a0
            Jac[1, c] = a1
            Jac[2, c] = a2


@kernel
def _frame_jacobians(Q, q_index, parent, table, chain, axes, revolute, f_joint, f_R, f_p):
    """Batched `frame_jacobian_into`: (R (N, 3, 3), p (N, 3), J (N, 6, dof)) of a frame."""
    N, dof = Q.shape
    J = table.shape[0]
    R = np.empty((J + 1, 3, 3))
    p = np.empty((J + 1, 3))
    Rf = np.empty((N, 3, 3))
    pf = np.empty((N, 3))
    Jac = np.empty((N, 6, dof))
    for n in range(N):
        chain_frames(Q[n], q_index, parent, table, R, p)
        frame_jacobian_into(R, p, chain, axes, revolute, q_index, f_joint, f_R, f_p, Rf[n], pf[n], Jac[n])
    return Rf, pf, Jac


class Kinematics:
    """Forward kinematics and frame Jacobians of a robot's arm joints.

    Args:
        config: the robot configuration; joints not in `config.arm_joints` are locked at
            the gripper's planning positions (or zero).
    """

    def __init__(self, config: RobotConfig):
        self.config = config
        full = build_model(config.urdf_path)
        missing = [j for j in config.arm_joints if not full.existJointName(j)]
        if missing:
            raise UnknownNameError("joint", missing[0], [n for n in full.names[1:]])
        q_lock = pin.neutral(full)
        locked = []
        for jid in range(1, full.njoints):
            name = full.names[jid]
            if name in config.arm_joints:
                continue
            locked.append(jid)
            if config.gripper is not None and name in config.gripper.joints:
                q_lock[full.joints[jid].idx_q] = config.gripper.planning_positions[config.gripper.joints.index(name)]
        self.full_model = full
        self.locked_configuration = q_lock
        self.model = pin.buildReducedModel(full, locked, q_lock) if locked else full
        self._local = threading.local()
        order = [self.model.getJointId(j) for j in config.arm_joints]
        # The reduced model keeps the URDF order; manip requires the config to list joints in
        # that same order so that q maps to the model without a permutation.
        q_idx = [self.model.joints[j].idx_q for j in order]
        if q_idx != list(range(len(order))):
            raise InvalidInputError(
                f"arm_joints must be listed in the URDF's tree order: {list(self.model.names[1:])}"
            )
        self.joint_names: tuple[str, ...] = tuple(config.arm_joints)
        self.dof = len(self.joint_names)
        #: The robot's `JointLimits` (`config.limits`); `lower` / `upper` are its (dof,) position limits [rad].
        self.limits = config.limits
        self.lower = self.limits.lower
        self.upper = self.limits.upper
        urdf_lo = self.model.lowerPositionLimit
        urdf_hi = self.model.upperPositionLimit
        if np.any(self.lower < urdf_lo - 1e-9) or np.any(self.upper > urdf_hi + 1e-9):
            raise InvalidInputError(f"{config.name}: configured joint limits exceed the URDF's")
        self._joints = [_joint_spec(self.model, j) for j in range(1, self.model.njoints)]
        self._joint_specs = tuple(self._joints)
        self._build_small_batch_tables()
        self.frame_names: tuple[str, ...] = tuple(f.name for f in self.model.frames)
        self._frame_ids = {f.name: i for i, f in enumerate(self.model.frames)}

    def pinned(self, q: np.ndarray, free: np.ndarray) -> Kinematics:
        """This kinematics with the joints not `free` held where `q` has them.

        The held joints' position limits become [q_i, q_i], so whatever reads `lower` /
        `upper` / `limits` (IK restarts and bounds, the path search's samples, the
        optimiser's bounds) keeps them there: the other arms of a multi-arm robot during
        one arm's plan. The model, tables and work spaces are shared (no copy).

        Args:
            q: (dof,) configuration [rad], clipped to the limits.
            free: (dof,) bool, True for the joints that may move.
        """
        free = np.asarray(free, dtype=bool)
        held = np.clip(np.asarray(q, dtype=float), self.lower, self.upper)
        out = copy.copy(self)
        lim = self.limits
        out.limits = JointLimits(velocity=lim.velocity, acceleration=lim.acceleration, jerk=lim.jerk,
                                 lower=np.where(free, lim.lower, held), upper=np.where(free, lim.upper, held),
                                 joint_names=lim.joint_names)
        out.lower, out.upper = out.limits.lower, out.limits.upper
        return out

    @property
    def data(self) -> pin.Data:
        """Pinocchio's work space of the calling thread (created on first use in each thread)."""
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = self.model.createData()
        return data

    # ------------------------------------------------------------------ validation
    def frame_id(self, link: str, what: str = "link") -> int:
        """Pinocchio frame index of `link` (argument name `what` in messages).

        Raises:
            InvalidInputError: `link` is not a string.
            UnknownNameError: no such frame (the message lists the frames).
        """
        if not isinstance(link, str):
            raise InvalidInputError(f"{what} must be a frame name (a str); got {link!r}")
        try:
            return self._frame_ids[link]
        except KeyError:
            raise UnknownNameError(f"{what}: frame", link, [n for n in self.frame_names if n != "universe"]) from None

    def check_q(self, q: np.ndarray, name: str = "q") -> np.ndarray:
        """`q` as a float array (dof,) or (N, dof); raises on wrong shape, a non-numeric
        dtype (complex, bool, strings, objects) or non-finite values."""
        q = as_real_array(q, name)
        if q.ndim not in (1, 2) or q.shape[-1] != self.dof:
            raise InvalidInputError(
                f"{name} must have shape ({self.dof},) or (N, {self.dof}) for joints {list(self.joint_names)}; got {q.shape}"
            )
        if not np.all(np.isfinite(q)):
            raise InvalidInputError(f"{name} has non-finite values: {q}")
        return q

    def within_limits(self, q: np.ndarray, tolerance: float = 0.0) -> np.ndarray:
        """True where every joint of `q` (..., dof) lies within the limits (+/- tolerance)."""
        return np.all((q >= self.lower - tolerance) & (q <= self.upper + tolerance), axis=-1)

    def limit_violations(self, q: np.ndarray, tolerance: float = 0.0) -> list[str]:
        """Human-readable list of the joints of a single `q` outside their limits."""
        out = []
        for name, v, lo, hi in zip(self.joint_names, q, self.lower, self.upper):
            if v < lo - tolerance or v > hi + tolerance:
                out.append(f"{name}={v:.6f} not in [{lo:.4f}, {hi:.4f}]")
        return out

    # ------------------------------------------------------------------ single
    def frame_transform(self, q: np.ndarray, frame_id: int) -> pin.SE3:
        """Pinocchio SE3 of one frame for one configuration (no validation: hot path)."""
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, frame_id)

    def frame_jacobian(self, q: np.ndarray, frame_id: int) -> np.ndarray:
        """(6, dof) Jacobian [linear; angular] in the world-aligned frame at the link origin.

        Call `frame_transform(q, frame_id)` first (it computes the kinematics).
        """
        pin.computeJointJacobians(self.model, self.data, q)
        return pin.getFrameJacobian(self.model, self.data, frame_id, pin.LOCAL_WORLD_ALIGNED)

    # ------------------------------------------------------------------ batched
    def joint_transforms(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (N, J+1, 3, 3) and positions (N, J+1, 3) of every joint frame.

        Index 0 is the universe (identity). Q: (N, dof).
        """
        Q = kernel_array(Q)
        if Q.shape[0] >= FK_LANES_FROM:   # the same frames, bit for bit, cheaper per configuration
            return _joint_frames_lanes(Q, self._sb_q, self._sb_parent_a, self._sb_table, FK_LANES)
        return _joint_frames(Q, self._sb_q, self._sb_parent_a, self._sb_table)

    @property
    def joint_specs(self) -> tuple[JointSpec, ...]:
        """The reduced model's J joints in tree order (joint frame j + 1 is joint_specs[j]):
        parent joint, placement in the parent [m], axis, revolute or prismatic, index in q."""
        return self._joint_specs

    @property
    def joint_axes(self) -> np.ndarray:
        """(J, 3) each joint's unit axis in its own frame (shared: do not modify)."""
        return self._axes

    @property
    def joint_revolute(self) -> np.ndarray:
        """(J,) bool: True for a revolute joint, False for a prismatic one (shared: do not modify)."""
        return self._revolute

    def fk_tables(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q_index (J,), parent (J,), table (J, 3|4, 16)): the inputs of `chain_frames`."""
        return self._sb_q, self._sb_parent_a, self._sb_table

    def jacobian_tables(self, frame_id: int) -> tuple:
        """Inputs of `frame_jacobian_into` for one frame (chain, axes, revolute, f_joint, f_R,
        f_p; q_index comes from `fk_tables`), cached."""
        tables = self._frame_tables.get(frame_id)
        if tables is None:
            f = self.model.frames[frame_id]
            chain = []
            j = f.parentJoint
            while j > 0:
                chain.append(j)
                j = self._joints[j - 1].parent
            tables = (np.array(chain, dtype=np.int64), self._axes, self._revolute, int(f.parentJoint),
                      np.ascontiguousarray(f.placement.rotation, dtype=np.float64),
                      np.ascontiguousarray(f.placement.translation, dtype=np.float64))
            self._frame_tables[frame_id] = tables
        return tables

    def _build_small_batch_tables(self) -> None:
        """Constant (J, 4, 4) tables such that a joint's transform in its parent joint frame is
        `A + cos(q) Cc + sin(q) Ss + q D` (placement times Rodrigues' rotation / translation)."""
        J = len(self._joints)
        self._sb_A = np.zeros((J, 4, 4))
        self._sb_C = np.zeros((J, 4, 4))
        self._sb_S = np.zeros((J, 4, 4))
        self._sb_D = np.zeros((J, 4, 4))
        for k, spec in enumerate(self._joints):
            Rp, pp = spec.R_placement, spec.p_placement
            self._sb_A[k, :3, 3] = pp
            self._sb_A[k, 3, 3] = 1.0
            if spec.revolute:
                x, y, z = spec.axis
                K = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
                K2 = K @ K
                self._sb_A[k, :3, :3] = Rp @ (np.eye(3) + K2)
                self._sb_C[k, :3, :3] = -(Rp @ K2)
                self._sb_S[k, :3, :3] = Rp @ K
            else:
                self._sb_A[k, :3, :3] = Rp
                self._sb_D[k, :3, 3] = Rp @ spec.axis
        self._sb_q = np.array([spec.q_index for spec in self._joints], dtype=np.int64)
        self._sb_prismatic = not all(spec.revolute for spec in self._joints)
        self._sb_parent = [spec.parent for spec in self._joints]
        self._sb_parent_a = np.array(self._sb_parent, dtype=np.int64)
        self._axes = np.array([spec.axis for spec in self._joints], dtype=np.float64).reshape(-1, 3)
        self._revolute = np.array([spec.revolute for spec in self._joints], dtype=np.bool_)
        self._frame_tables: dict[int, tuple] = {}
        tables = [self._sb_A, self._sb_C, self._sb_S] + ([self._sb_D] if self._sb_prismatic else [])
        self._sb_table = np.stack([t.reshape(J, 16) for t in tables], axis=1)  # (J, 3|4, 16)

    def frame_transforms(self, Q: np.ndarray, frame_ids: list[int]) -> tuple[np.ndarray, np.ndarray]:
        """World rotations (N, F, 3, 3) and positions (N, F, 3) of frames, for Q (N, dof)."""
        n = Q.shape[0]
        Rs = np.empty((len(frame_ids), n, 3, 3))
        ps = np.empty((len(frame_ids), n, 3))
        # chunks keep the per-joint temporaries in cache (8x faster at N = 100,000)
        for s in range(0, n, _CHUNK):
            R, p = self.joint_transforms(Q[s : s + _CHUNK])
            for i, fid in enumerate(frame_ids):
                Rs[i, s : s + _CHUNK], ps[i, s : s + _CHUNK] = self._frame_from_joint(R, p, fid)
        return Rs.transpose(1, 0, 2, 3), ps.transpose(1, 0, 2)

    def _frame_from_joint(self, R: np.ndarray, p: np.ndarray, frame_id: int) -> tuple[np.ndarray, np.ndarray]:
        """(R (N, 3, 3), p (N, 3)) of a frame from the joint transforms of `joint_transforms`."""
        f = self.model.frames[frame_id]
        n = R.shape[0]
        Rj = np.ascontiguousarray(R[:, f.parentJoint]).reshape(-1, 3)
        Rf = (Rj @ f.placement.rotation).reshape(n, 3, 3)
        pf = p[:, f.parentJoint] + (Rj @ f.placement.translation).reshape(n, 3)
        return Rf, pf

    def frame_jacobians(self, Q: np.ndarray, frame_id: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Batched frame pose and (N, 6, dof) world-aligned Jacobians [linear; angular].

        Returns:
            (R (N, 3, 3), p (N, 3), J (N, 6, dof)) of the frame.
        """
        return _frame_jacobians(kernel_array(Q), *self.fk_tables(),
                                *self.jacobian_tables(frame_id))

    def fk(self, q: np.ndarray, link: str | None = None) -> Pose:
        """Pose of `link` (default the config's `ee_link`, as `MotionGenerator.fk` and cuRobo's
        `get_state`) in the base frame for q (dof,) -> Pose or (N, dof) -> batched Pose."""
        q = self.check_q(q)
        fid = self.frame_id(self.config.ee_link if link is None else link, "link")
        if q.ndim == 1:
            M = self.frame_transform(q, fid)
            x, y, z, w = pin.Quaternion(M.rotation).coeffs()
            wxyz = np.array([w, x, y, z]) if w >= 0 else -np.array([w, x, y, z])
            return Pose._trusted(M.translation.copy(), wxyz / math.sqrt(float(wxyz @ wxyz)))
        R, p = self.frame_transforms(q, [fid])
        return Pose._trusted(np.ascontiguousarray(p[:, 0]), quat.from_matrix(R[:, 0]))

    def __getattr__(self, name: str):
        # only for missing names: cuRobo's CudaRobotModel names (get_state, ...) say where manip has them
        if name.startswith("__"):
            raise AttributeError(name)
        raise curobo_names.missing(type(self).__name__, curobo_names.KINEMATICS, name)
