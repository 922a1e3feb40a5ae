"""`ArticulationView`: Isaac's batched articulation API over one articulation (`robot._articulation_view`).

Isaac's `SingleArticulation` keeps an `ArticulationView` of count 1 as `_articulation_view`;
tutorials read gains, joint counts and limits through it. Here it is a thin view of the
articulation's drives (`ArticulationCore`): getters return arrays with a leading batch axis
of size 1, e.g. `get_gains()` -> (kps (1, num_dof), kds (1, num_dof)).

A script may also create one as Isaac's tutorials do, from a prim path expression
(`ArticulationView(prim_paths_expr="/World/Franka", name="franka_view")`, matched per path
segment as `XFormPrimView`), add it to the scene and use it after `world.reset()`.

Differences from Isaac: one articulation only (`indices` may be None or [0]; an expression
matching several referenced models raises, naming them: use one view per robot);
`num_joints` counts one joint per body below the articulation's root (fixed joints
included, as USD does), since MuJoCo merges no bodies but has no fixed-joint objects.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError, UnknownNameError
from manip.sim.articulations import articulation_dynamics as dyn
from manip.sim.articulations.articulation_core import MAX_EFFORT, MAX_POSITION, MAX_VELOCITY, ArticulationCore
from manip.sim.controllers.articulation_controller import ArticulationController
from manip.sim.utils.types import ArticulationViewActions, JointsState
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.sim.scenes.stage import ReferencePrim, SimulationError, get_current_stage
from manip.sim.prims.views import compile_path_expression, path_matches
from manip.sim.utils.bounds import bounded_vec
from manip.validation import unit_quat


class ViewedArticulation(Protocol):
    """What the view reads: the articulation's core (None before the World compiles)."""

    prim_path: str
    core: ArticulationCore | None


class _ReferencedModel:
    """A referenced model seen as a `ViewedArticulation` (its core, once compiled)."""

    def __init__(self, ref: ReferencePrim):
        self._ref = ref
        self.prim_path = ref.prim_path

    @property
    def core(self) -> ArticulationCore | None:
        return self._ref.core


def _find_articulation(prim_paths_expr: str) -> _ReferencedModel:
    """The one referenced model whose prim path matches `prim_paths_expr` (per segment).

    Raises:
        InvalidInputError: none or several match (the message lists the referenced models).
    """
    segments = compile_path_expression(prim_paths_expr)
    stage = get_current_stage()
    refs = [p for p in stage.prim_paths() if stage.find_reference(p) is not None]
    hits = [p for p in refs if path_matches(segments, p)]
    if len(hits) != 1:
        what = "no referenced model" if not hits else f"{len(hits)} referenced models {hits}"
        raise InvalidInputError(
            f"ArticulationView(prim_paths_expr={prim_paths_expr!r}) matches {what}; manip's view holds exactly "
            f"one articulation (one view per robot). Each path segment is a regular expression. Referenced models "
            f"on the stage: {refs}")
    return _ReferencedModel(stage.find_reference(hits[0]))


class ArticulationView:
    """Batched (count 1) access to one articulation's joints and drives.

    Args:
        prim_paths_expr: the `Articulation` viewed, or (Isaac's form) a prim path expression
            matching the prim path of exactly one referenced model, e.g. "/World/Franka".
        name: scene name (`world.scene.add(view)`).
        positions, translations, orientations, scales, visibilities,
            reset_xform_properties, enable_dof_force_sensors: accepted for Isaac scripts;
            given poses raise (move the articulation itself).

    Raises:
        InvalidInputError: the expression matches no or several referenced models, or a
            pose is given.
    """

    def __init__(self, prim_paths_expr: str | ViewedArticulation, name: str = "articulation_prim_view",
                 positions=None, translations=None, orientations=None, scales=None, visibilities=None,
                 reset_xform_properties: bool = True, enable_dof_force_sensors: bool = False):
        if any(v is not None for v in (positions, translations, orientations, scales)):
            raise InvalidInputError("ArticulationView: positions/translations/orientations/scales are not supported; "
                                    "set the pose with Articulation.set_world_pose")
        if isinstance(prim_paths_expr, str):
            self._articulation: ViewedArticulation = _find_articulation(prim_paths_expr)
        else:
            self._articulation = prim_paths_expr
        self._name = name
        self._default_joints: dict[str, np.ndarray] = {}  # set_joints_default_state's, applied by post_reset

    @property
    def name(self) -> str:
        return self._name

    @property
    def prim_path(self) -> str:
        return self._articulation.prim_path

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do: the view reads the articulation the World compiled (kept for Isaac scripts)."""

    def _c(self, what: str) -> ArticulationCore:
        c = self._articulation.core
        if c is None:
            raise SimulationError(f"articulation view {self.prim_paths[0]!r}: {what} before world.reset()")
        return c

    def _named_joints(self, joint_indices, joint_names):
        """`joint_indices`, or (Isaac 5) the indices of `joint_names`; not both.

        Raises:
            InvalidInputError: both given. UnknownNameError: an unknown joint name (the message lists them).
        """
        if joint_names is None:
            return joint_indices
        if joint_indices is not None:
            raise InvalidInputError("give joint_indices or joint_names, not both")
        names = self.dof_names
        missing = [n for n in ([joint_names] if isinstance(joint_names, str) else joint_names) if n not in names]
        if missing:
            raise UnknownNameError("joint", str(missing[0]), names)
        return [names.index(n) for n in ([joint_names] if isinstance(joint_names, str) else joint_names)]

    @staticmethod
    def _check_indices(indices) -> None:
        if indices is not None and np.asarray(indices).ravel().tolist() not in ([0], []):
            raise InvalidInputError(f"this view holds one articulation (index 0); got indices {indices!r}")

    # ------------------------------------------------------------------ description
    @property
    def prim_paths(self) -> list[str]:
        return [self._articulation.prim_path]

    @property
    def count(self) -> int:
        return 1

    @property
    def num_dof(self) -> int:
        return self._c("num_dof").n

    @property
    def num_bodies(self) -> int:
        return len(self._c("num_bodies").body_ids)

    @property
    def num_joints(self) -> int:
        """Joints of the articulation, fixed ones included: one per body below a root body."""
        c = self._c("num_joints")
        return len(c.body_ids) - len(c.root_ids)

    @property
    def dof_names(self) -> list[str]:
        return list(self._c("dof_names").dof_names)

    @property
    def body_names(self) -> list[str]:
        return list(self._c("body_names").body_names)

    def get_dof_index(self, dof_name: str) -> int:
        names = self.dof_names
        if dof_name not in names:
            raise InvalidInputError(f"no joint {dof_name!r}; joints: {names}")
        return names.index(dof_name)

    def post_reset(self) -> None:
        """Apply the view's joint default state (`set_joints_default_state`), if it has one, over
        the articulation's own (the World's reset calls it after the single objects', as Isaac's
        scene does, when the view is in the scene); else nothing: the articulation restores its
        own default state."""
        if not self._default_joints or self._articulation.core is None:
            return
        c = self._articulation.core
        pos = self._default_joints.get("positions")
        if pos is not None:
            c.teleport(pos)
        if "velocities" in self._default_joints:
            c.set_velocities(self._default_joints["velocities"])
        if "efforts" in self._default_joints:
            self.set_joint_efforts(self._default_joints["efforts"])

    def set_joints_default_state(self, positions=None, velocities=None, efforts=None) -> None:
        """The joint state (1, num_dof) or (num_dof,) each (None keeps a part) the view's
        `post_reset` restores at every `World.reset()` (as Isaac's view: add the view to the
        scene). Positions [rad or m] become the drive targets; velocities [rad/s or m/s];
        efforts [N m or N] applied until changed.

        Raises:
            InvalidInputError: a wrong length, NaN, or magnitudes beyond physical bounds.
        """
        c = self._c("set_joints_default_state")
        idx = np.arange(c.n)
        for what, v, limit in (("positions", positions, MAX_POSITION), ("velocities", velocities, MAX_VELOCITY),
                               ("efforts", efforts, MAX_EFFORT)):
            if v is not None:
                self._default_joints[what] = c.values(self._row(v, what), idx, what, limit=limit).copy()

    def get_joints_default_state(self) -> JointsState:
        """The view's joint default state, (1, num_dof) each; the articulation's own where the view
        sets none (what `World.reset()` restores)."""
        c = self._c("get_joints_default_state")
        own = {"positions": c.home, "velocities": np.zeros(c.n), "efforts": np.zeros(c.n)}
        wrapper = next((w for w in get_current_stage().wrappers()
                        if getattr(w, "core", None) is c and hasattr(w, "get_joints_default_state")), None)
        if wrapper is not None and wrapper.get_joints_default_state() is not None:
            s = wrapper.get_joints_default_state()
            own = {"positions": s.positions, "velocities": s.velocities, "efforts": s.efforts}
        rows = {k: np.array(self._default_joints.get(k, v), dtype=float)[None, :] for k, v in own.items()}
        return JointsState(rows["positions"], rows["velocities"], rows["efforts"])

    def is_physics_handle_valid(self) -> bool:
        return self._articulation.core is not None

    # ------------------------------------------------------------------ drives
    def get_gains(self, indices=None, joint_indices=None, joint_names=None,
                  clone: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Drive stiffness and damping: (kps (1, K), kds (1, K)) for the joints `joint_indices` (all for None)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("get_gains")
        idx = c.indices(joint_indices)
        return c.kps[idx][None, :].copy(), c.kds[idx][None, :].copy()

    def set_gains(self, kps=None, kds=None, indices=None, joint_indices=None, joint_names=None,
                  save_to_usd: bool = False) -> None:
        """Set drive stiffness `kps` and damping `kds`, (1, K) or (K,) each, of `joint_indices` (all for None).

        Raises:
            InvalidInputError: wrong shape, a negative or non-finite gain.
        """
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("set_gains")
        idx = c.indices(joint_indices)
        new_kp, new_kd = c.kps.copy(), c.kds.copy()
        if kps is not None:
            new_kp[idx] = c.values(kps, idx, "kps")
        if kds is not None:
            new_kd[idx] = c.values(kds, idx, "kds")
        if np.any(new_kp < 0) or np.any(new_kd < 0):
            raise InvalidInputError("gains must be >= 0")
        c.check_drive(new_kp, new_kd, c.pos_target, c.vel_target, "kps/kds")
        c.kps, c.kds = new_kp, new_kd
        c.write_gains()

    def set_max_efforts(self, values, indices=None, joint_indices=None, joint_names=None) -> None:
        """Drive force limits (1, K) or (K,) [N m or N] (> 0; inf = unlimited) of `joint_indices`
        (all for None), as `ArticulationController.set_max_efforts`."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._controller("set_max_efforts").set_max_efforts(self._row(values, "values"), joint_indices)

    def get_max_efforts(self, indices=None, joint_indices=None, joint_names=None, clone: bool = True) -> np.ndarray:
        """Drive force limits (1, K) [N m or N] (inf = unlimited)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("get_max_efforts")
        return c.max_efforts[c.indices(joint_indices)][None, :].copy()

    def get_dof_limits(self) -> np.ndarray:
        """(1, num_dof, 2) lower and upper joint limits [rad or m]."""
        c = self._c("get_dof_limits")
        return np.stack([c.lower, c.upper], axis=1)[None, :, :]

    def get_joint_max_velocities(self, indices=None, joint_indices=None, joint_names=None,
                                 clone: bool = True) -> np.ndarray:
        """(1, K) joint velocity limits [rad/s or m/s] (inf where the model gives none)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("get_joint_max_velocities")
        return c.max_velocities[c.indices(joint_indices)][None, :].copy()

    # ------------------------------------------------------------------ state
    def get_joint_positions(self, indices=None, joint_indices=None, joint_names=None, clone: bool = True) -> np.ndarray:
        """(1, K) joint positions [rad or m]."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("get_joint_positions")
        return c.sim.data.qpos[c.qadr[c.indices(joint_indices)]][None, :].copy()

    def get_joint_velocities(self, indices=None, joint_indices=None, joint_names=None,
                             clone: bool = True) -> np.ndarray:
        """(1, K) joint velocities [rad/s or m/s]."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("get_joint_velocities")
        return c.sim.data.qvel[c.dadr[c.indices(joint_indices)]][None, :].copy()

    # ------------------------------------------------------------------ commands
    @staticmethod
    def _row(values, what: str):
        """(1, K) or (K,) values as (K,) (the batch axis of a count-1 view)."""
        if values is None:
            return None
        a = np.asarray(values, dtype=float)
        if a.ndim == 2:
            if a.shape[0] != 1:
                raise InvalidInputError(f"{what} must have shape (1, K) or (K,) for a view of one articulation; "
                                        f"got {a.shape}")
            a = a[0]
        return a

    def set_joint_positions(self, positions, indices=None, joint_indices=None, joint_names=None) -> None:
        """Teleport the joints to `positions` (1, K) [rad or m] and make them their drive targets."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._c("set_joint_positions").teleport(self._row(positions, "positions"), joint_indices)

    def set_joint_velocities(self, velocities, indices=None, joint_indices=None, joint_names=None) -> None:
        """Set joint velocities (1, K) [rad/s or m/s] (drive targets unchanged)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._c("set_joint_velocities").set_velocities(self._row(velocities, "velocities"), joint_indices)

    def set_joint_position_targets(self, positions, indices=None, joint_indices=None, joint_names=None) -> None:
        """Drive position targets (1, K) [rad or m] (NaN keeps a joint's target)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._c("set_joint_position_targets").apply_action(
            ArticulationAction(joint_positions=self._row(positions, "positions"), joint_indices=joint_indices))

    def set_joint_velocity_targets(self, velocities, indices=None, joint_indices=None, joint_names=None) -> None:
        """Drive velocity targets (1, K) [rad/s or m/s] (NaN keeps a joint's target)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._c("set_joint_velocity_targets").apply_action(
            ArticulationAction(joint_velocities=self._row(velocities, "velocities"), joint_indices=joint_indices))

    def set_joint_efforts(self, efforts, indices=None, joint_indices=None, joint_names=None) -> None:
        """Joint efforts (1, K) [N m or N] added to the drives (persist until changed)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        c = self._c("set_joint_efforts")
        idx = c.indices(joint_indices)
        e = c.values(self._row(efforts, "efforts"), idx, "efforts", limit=MAX_EFFORT, kind="effort")
        c.check_physical(e, idx, "efforts", "effort")
        c.efforts = c.efforts.copy()
        c.efforts[idx] = e
        c.write_targets()

    def get_applied_joint_efforts(self, indices=None, joint_indices=None, joint_names=None,
                                  clone: bool = True) -> np.ndarray:
        """(1, K) drive force plus applied effort per joint [N m or N], last physics substep."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        return self._c("get_applied_joint_efforts").joint_forces(joint_indices, constraint=False)[None, :]

    def get_measured_joint_efforts(self, indices=None, joint_indices=None, joint_names=None,
                                   clone: bool = True) -> np.ndarray:
        """(1, K) total generalized force per joint, constraints (limits, contacts) included."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        return self._c("get_measured_joint_efforts").joint_forces(joint_indices, constraint=True)[None, :]

    def get_joints_state(self, indices=None, clone: bool = True) -> JointsState:
        """Positions, velocities and applied efforts, (1, num_dof) each."""
        self._check_indices(indices)
        return JointsState(self.get_joint_positions(), self.get_joint_velocities(), self.get_applied_joint_efforts())

    def _controller(self, what: str) -> ArticulationController:
        """A controller of the viewed articulation's drives (the view holds no state of its own)."""
        self._c(what)
        controller = ArticulationController()
        controller.initialize(self._articulation)
        return controller

    def switch_control_mode(self, mode: str, indices=None, joint_indices=None, joint_names=None) -> None:
        """Drives to "position", "velocity" or "effort" (as `ArticulationController.switch_control_mode`)."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        self._controller("switch_control_mode").switch_control_mode(mode, joint_indices)

    def switch_dof_control_mode(self, mode: str, dof_index: int, indices=None) -> None:
        """One joint's drive to "position", "velocity" or "effort"."""
        self._check_indices(indices)
        self._controller("switch_dof_control_mode").switch_control_mode(mode, [dof_index])

    def get_applied_actions(self, clone: bool = True) -> ArticulationViewActions:
        """The drive targets: position, velocity and effort, (1, num_dof) each."""
        a = self._controller("get_applied_actions").get_applied_action()
        return ArticulationViewActions(a.joint_positions[None, :], a.joint_velocities[None, :],
                                       a.joint_efforts[None, :])

    # ------------------------------------------------------------------ root and dynamics
    def get_world_poses(self, indices=None, clone: bool = True, usd: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Root poses: positions (1, 3) [m], orientations (1, 4) (w, x, y, z)."""
        self._check_indices(indices)
        c = self._c("get_world_poses")
        c.sim.ensure_kinematics()
        b = c.root_ids[0]
        return c.sim.data.xpos[b][None, :].copy(), c.sim.data.xquat[b][None, :].copy()

    def set_world_poses(self, positions=None, orientations=None, indices=None, usd: bool = True) -> None:
        """Teleport the root: positions (1, 3) or (3,) [m], orientations (1, 4) or (4,) (w, x, y, z)
        (None keeps a part); a fixed base moves with it. As Isaac's, a `World.reset()` restores the
        articulation's default pose (`set_default_state` on the articulation keeps the new one)."""
        self._check_indices(indices)
        cur_p, cur_q = self.get_world_poses()
        p = cur_p[0] if positions is None else bounded_vec(self._row(positions, "positions"), "position", "positions")
        q = cur_q[0] if orientations is None else unit_quat(self._row(orientations, "orientations"))
        self._c("set_world_poses").set_root_pose(p, q)

    def get_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        """(1, 6) root linear [m/s] and angular [rad/s] velocity, world frame (zeros for a fixed base)."""
        self._check_indices(indices)
        c = self._c("get_velocities")
        out = np.zeros((1, 6))
        if c.free_dadr >= 0:
            out[0, :3] = c.sim.data.qvel[c.free_dadr:c.free_dadr + 3]
            out[0, 3:] = c.sim.free_angular_velocity(c.free_qadr, c.free_dadr)
        return out

    def get_linear_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        """(1, 3) root linear velocity [m/s]."""
        return self.get_velocities(indices)[:, :3]

    def get_angular_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        """(1, 3) root angular velocity [rad/s]."""
        return self.get_velocities(indices)[:, 3:]

    def get_local_poses(self, indices=None) -> tuple[np.ndarray, np.ndarray]:
        """Same as get_world_poses (no parent transforms here)."""
        return self.get_world_poses(indices)

    def get_dof_types(self, dof_names=None) -> list[str]:
        """"Rotation" or "Translation" per joint."""
        c = self._c("get_dof_types")
        return ["Rotation" if t == 1 else "Translation" for t in c.types]

    def get_body_masses(self, indices=None, body_indices=None, clone: bool = True) -> np.ndarray:
        """(1, B) body masses [kg]."""
        self._check_indices(indices)
        c = self._c("get_body_masses")
        m = c.sim.model.body_mass[c.body_ids]
        return (m if body_indices is None else m[np.asarray(body_indices, dtype=int)])[None, :].copy()

    def get_enabled_self_collisions(self, indices=None) -> np.ndarray:
        """(1,) bool: whether the robot's links collide with each other (its
        `Articulation.set_enabled_self_collisions` flag; True until set: the model's own filter)."""
        self._check_indices(indices)
        ref = get_current_stage().find_reference(self._articulation.prim_path)
        flag = None if ref is None else ref.self_collisions
        return np.array([True if flag is None else bool(flag)])

    def get_body_index(self, body_name: str) -> int:
        names = self.body_names
        if body_name not in names:
            raise InvalidInputError(f"no body {body_name!r}; bodies: {names}")
        return names.index(body_name)

    def get_jacobians(self, indices=None, clone: bool = True) -> np.ndarray:
        """(1, B, 6, n) body Jacobians in Isaac's layout (`manip.sim.articulations.articulation_dynamics`)."""
        self._check_indices(indices)
        return dyn.jacobians(self._c("get_jacobians"))[None]

    def get_jacobian_shape(self) -> tuple[int, int, int]:
        """(B, 6, n) of one articulation's Jacobians."""
        return dyn.jacobians(self._c("get_jacobian_shape")).shape

    def get_mass_matrices(self, indices=None, clone: bool = True) -> np.ndarray:
        """(1, n, n) joint-space inertia matrix."""
        self._check_indices(indices)
        return dyn.mass_matrix(self._c("get_mass_matrices"))[None]

    def get_mass_matrix_shape(self) -> tuple[int, int]:
        return dyn.mass_matrix(self._c("get_mass_matrix_shape")).shape

    def get_generalized_gravity_forces(self, indices=None, joint_indices=None, joint_names=None,
                                       clone: bool = True) -> np.ndarray:
        """(1, n) generalized forces holding the articulation against gravity [N m or N]."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        return dyn.gravity_forces(self._c("get_generalized_gravity_forces"))[None]

    def get_coriolis_and_centrifugal_forces(self, indices=None, joint_indices=None, joint_names=None,
                                            clone: bool = True) -> np.ndarray:
        """(1, n) Coriolis and centrifugal generalized forces [N m or N]."""
        joint_indices = self._named_joints(joint_indices, joint_names)
        self._check_indices(indices)
        return dyn.coriolis_and_centrifugal_forces(self._c("get_coriolis_and_centrifugal_forces"))[None]

    def apply_action(self, control_actions: ArticulationAction, indices=None) -> None:
        """Set drive targets from an action with (K,) or (1, K) fields (Isaac's semantics)."""
        self._check_indices(indices)
        if not isinstance(control_actions, ArticulationAction):
            raise InvalidInputError(f"expected an ArticulationAction; got {type(control_actions).__name__}")
        self._c("apply_action").apply_action(control_actions)

    def __repr__(self) -> str:
        return f"ArticulationView(prim_paths={self.prim_paths})"


declare_not_supported(ArticulationView)
