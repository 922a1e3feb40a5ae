"""Vectorised views over many prims: `XFormPrimView`, `RigidPrimView`.

A view matches prims as Isaac's `find_matching_prim_paths` does: `prim_paths_expr` is split
at "/" and each segment is a regular expression that must match the whole path segment
("/World/Cube_.*" matches "/World/Cube_0" but not its children; the glob "/World/Cube_*"
matches only "/World/Cube", "/World/Cube_", ...). Prims are MuJoCo bodies (name = prim
path), in model order. As in Isaac, an expression that matches no prim on the stage when the
view is created raises; the view resolves its prims when the World compiles, and methods
used before the first reset raise `SimulationError`.
"""

from __future__ import annotations

import logging
import re

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim.prims import body_forces, isaac5_views
from manip.sim.prims.rigid_prim import RigidPrim
from manip.sim.prims.sleep import RigidViewSleepThresholds
from manip.sim.prims.xform_prim import XFormPrim, model_frame_pose, relative_pose
from manip.sim.scenes.stage import SimHandle, SimulationError, get_current_stage, get_prim_at_path
from manip.sim.utils.bounds import check_bounded_rows
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.sim.utils.types import DynamicsViewState, XFormPrimViewState
from manip.validation import as_real_array, batch

logger = logging.getLogger(__name__)


def compile_path_expression(expr: str) -> list[re.Pattern]:
    """One compiled regular expression per segment of an absolute prim path expression."""
    if not isinstance(expr, str) or not expr.startswith("/") or expr.endswith("/"):
        raise InvalidInputError(f"prim_paths_expr must be an absolute path expression like '/World/Cube_.*'; "
                                f"got {expr!r}")
    try:
        return [re.compile(seg) for seg in expr[1:].split("/")]
    except re.error as exc:
        raise InvalidInputError(f"prim_paths_expr {expr!r} is not a valid regular expression: {exc}") from None


def path_matches(segments: list[re.Pattern], path: str) -> bool:
    """Whether each segment of `path` fully matches its expression (same number of segments)."""
    parts = path[1:].split("/") if path.startswith("/") else None
    return (parts is not None and len(parts) == len(segments)
            and all(r.fullmatch(p) for r, p in zip(segments, parts)))


#: Isaac's RigidPrimView options with the default values accepted here (the contact
#: options are honoured: see `RigidPrimView.get_contact_force_matrix`).
RIGID_VIEW_OPTIONS = {
    "masses": None, "densities": None, "linear_velocities": None, "angular_velocities": None,
    "disable_stablization": True,
}
CONTACT_OPTIONS = ("track_contact_forces", "prepare_contact_sensors", "contact_filter_prim_paths_expr",
                   "max_contact_count")


def _is_default(value, default) -> bool:
    if default is None:
        return value is None
    if isinstance(default, list):
        return value is None or (isinstance(value, (list, tuple)) and len(value) == 0)
    return value == default


class XFormPrimView:
    """Poses of every prim matching `prim_paths_expr`.

    Args:
        prim_paths_expr: regular expression on prim paths, e.g. "/World/Cube_[0-9]+".
        name: scene name.
        positions, orientations: (N, 3), (N, 4) poses applied at the first binding (optional).
    """

    def __init__(self, prim_paths_expr: str, name: str = "xform_prim_view", positions=None, translations=None,
                 orientations=None, scales=None, visibilities=None, reset_xform_properties: bool = True,
                 usd: bool = True):
        self._segments = compile_path_expression(prim_paths_expr)
        if scales is not None or visibilities is not None:
            raise InvalidInputError(
                f"{type(self).__name__}: scales and visibilities are not supported by views here; set them on each "
                "object (set_local_scale, set_visibility)")
        self.prim_paths_expr = prim_paths_expr
        self.prim_path = prim_paths_expr
        self._name = name
        if positions is not None and translations is not None:
            raise InvalidInputError("give either positions or translations, not both")
        self._initial = (positions if positions is not None else translations, orientations)
        self._sim: SimHandle | None = None
        self._bodies = np.zeros(0, dtype=int)
        self._paths: list[str] = []
        self._check_matches_something()
        get_current_stage().register_wrapper(self)

    def _matches(self, path: str) -> bool:
        return path_matches(self._segments, path)

    def _check_matches_something(self) -> None:
        """Raise (as Isaac) if no prim of the stage, nor of a referenced model, can match."""
        stage = get_current_stage()
        paths = stage.prim_paths()
        if stage.sim is not None:
            m = stage.sim.model
            paths += [m.body(b).name for b in range(1, m.nbody)]
        if any(self._matches(p) for p in paths):
            return
        # Bodies of a referenced model not compiled yet are unknown: accept an expression
        # that reaches inside a referenced prim.
        refs = [p for p in stage.prim_paths() if stage.find_reference(p) is not None]
        for r in refs:
            n = r.count("/")
            if len(self._segments) > n and path_matches(self._segments[:n], r):
                return
        raise InvalidInputError(
            f"prim_paths_expr {self.prim_paths_expr!r} matches no prim on the stage. Each path segment is a "
            "regular expression matching the whole segment (as in Isaac): '/World/Cube_.*' or "
            "'/World/Cube_[0-9]+', not the glob '/World/Cube_*'. Create the prims before the view; "
            f"prims on the stage: {sorted(stage.prim_paths())}"
        )

    @property
    def name(self) -> str:
        return self._name

    def bind_simulation(self, sim: SimHandle) -> None:
        m = sim.model
        ids = [b for b in range(1, m.nbody) if self._matches(m.body(b).name)]
        if not ids:
            logger.warning("view %r: no prim matches %r", self._name, self.prim_paths_expr)
        self._sim = sim
        self._bodies = np.array(ids, dtype=int)
        self._paths = [m.body(b).name for b in ids]
        jnt = m.body_jntadr[self._bodies]
        free = np.array([j >= 0 and int(m.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE) for j in jnt], dtype=bool)
        self._free = free
        jnt = np.maximum(jnt, 0) if m.njnt else np.zeros(0, dtype=int)  # a world of no joint has no addresses
        self._qadr = np.where(free, m.jnt_qposadr[jnt], -1) if m.njnt else np.full(len(ids), -1)
        self._dadr = np.where(free, m.jnt_dofadr[jnt], -1) if m.njnt else np.full(len(ids), -1)
        self._mocap = m.body_mocapid[self._bodies].copy()
        p, q = self._initial
        if p is not None or q is not None:
            # As Isaac's view: the given poses are the prims' poses and their default state
            # (the World's reset, which follows this binding, restores them).
            self.set_world_poses(p, q)
            if all(hasattr(get_current_stage().get_prim(path), "get_default_state") for path in self._paths):
                XFormPrimView.set_default_state(self, p, q)
            self._initial = (None, None)

    def unbind_simulation(self) -> None:
        self._sim = None

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do (bound when the World compiles)."""

    def post_reset(self) -> None:
        """Nothing to do: the prims restore their own default states."""

    def is_valid(self, indices=None) -> bool:
        """Whether the view is bound to the compiled World (`indices` accepted, as Isaac's)."""
        if indices is not None:
            self._idx(indices)
        return self._sim is not None

    def _need(self) -> SimHandle:
        if self._sim is None:
            raise SimulationError(f"view {self._name!r} is used before world.reset() compiled the world")
        if not self.count:
            raise SimulationError(f"view {self._name!r} matches no prim of the compiled world "
                                  f"({self.prim_paths_expr!r}; were its prims removed?)")
        return self._sim

    @property
    def count(self) -> int:
        """Number of matched prims (0 before the first reset)."""
        return len(self._bodies)

    @property
    def prim_paths(self) -> list[str]:
        return list(self._paths)

    @property
    def prims(self) -> list:
        """Isaac's Usd.Prims of the view: what `get_prim_at_path` returns for each of `prim_paths`
        (the objects, or the XFormPrims of robots' links; each answers USD's reading methods)."""
        return [get_prim_at_path(p) for p in self._paths]

    def _idx(self, indices) -> np.ndarray:
        if indices is None:
            return np.arange(self.count)
        idx = np.asarray(indices, dtype=int).ravel()
        if np.any(idx < 0) or np.any(idx >= self.count):
            raise InvalidInputError(f"indices {idx.tolist()} out of range for a view of {self.count} prims")
        return idx

    def get_world_poses(self, indices=None, clone: bool = True, usd: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Positions (K, 3) [m] and orientations (K, 4) (w, x, y, z) (copies; `clone` and `usd`
        are accepted for Isaac's signature: there is one copy of the state, MuJoCo's)."""
        sim = self._need()
        idx = self._idx(indices)
        sim.ensure_kinematics()
        b = self._bodies[idx]
        return sim.data.xpos[b].copy(), sim.data.xquat[b].copy()

    def set_world_poses(self, positions=None, orientations=None, indices=None, usd: bool = True) -> None:
        """Teleport free bodies and mocap prims (Visual/Fixed objects); articulation links raise."""
        sim = self._need()
        idx = self._idx(indices)
        p = batch(positions, idx.size, 3, "positions") if positions is not None else None
        if p is not None:
            check_bounded_rows(p, "position", "positions")
        q = quat.normalize(batch(orientations, idx.size, 4, "orientations")) if orientations is not None else None
        movable = self._free[idx] | (self._mocap[idx] >= 0)
        if not np.all(movable):
            bad = [self._paths[i] for i in idx[~movable]]
            raise SimulationError(f"cannot set the pose of {bad}: they are parts of articulations or fixed bodies")
        d = sim.data
        for k, i in enumerate(idx):
            if self._free[i]:
                a = self._qadr[i]
                if p is not None:
                    d.qpos[a:a + 3] = p[k]
                if q is not None:
                    d.qpos[a + 3:a + 7] = q[k]
            else:
                mid = self._mocap[i]
                if p is not None:
                    d.mocap_pos[mid] = p[k]
                if q is not None:
                    d.mocap_quat[mid] = q[k]
        sim.mark_stale()

    def _need_paths(self) -> list[str]:
        self._need()
        return list(self._paths)

    def _object(self, path: str):
        """The scene object at `path` (its default state lives there).

        Raises:
            SimulationError: `path` is a body of a referenced model (it has no default state).
        """
        prim = get_current_stage().get_prim(path)
        if prim is None or not hasattr(prim, "get_default_state"):
            raise SimulationError(f"{path!r} is a body of an articulation: its state follows the joints (set the "
                                  "articulation's default state instead)")
        return prim

    def get_default_state(self) -> XFormPrimViewState:
        """The default pose of each prim (what `World.reset()` restores)."""
        states = [self._object(p).get_default_state() for p in self._need_paths()]
        return XFormPrimViewState(np.array([s.position for s in states]), np.array([s.orientation for s in states]))

    def set_default_state(self, positions=None, orientations=None, indices=None) -> None:
        """Set the default poses (K, 3), (K, 4) of the prims `indices` (None keeps a part)."""
        self._need()
        idx = self._idx(indices)
        p = batch(positions, idx.size, 3, "positions") if positions is not None else None
        q = batch(orientations, idx.size, 4, "orientations") if orientations is not None else None
        for k, i in enumerate(idx):
            self._object(self._paths[i]).set_default_state(None if p is None else p[k], None if q is None else q[k])

    def get_local_scales(self, indices=None) -> np.ndarray:
        """(K, 3) scales of the matched prims (1 for bodies of referenced models)."""
        self._need()
        stage = get_current_stage()
        out = []
        for i in self._idx(indices):
            prim = stage.get_prim(self._paths[i])
            out.append(prim.get_local_scale() if hasattr(prim, "get_local_scale") else np.ones(3))
        return np.array(out, dtype=float).reshape(-1, 3)

    def get_world_scales(self, indices=None) -> np.ndarray:
        """Same as `get_local_scales` (no parent transforms)."""
        return self.get_local_scales(indices)

    def _shapes(self, indices, what: str) -> list:
        """The scene objects (shapes, XFormPrims) of `indices`; a robot's link raises naming `what`."""
        self._need()
        stage = get_current_stage()
        out = []
        for i in self._idx(indices):
            prim = stage.get_prim(self._paths[i])
            if prim is None:
                raise SimulationError(f"{what}: {self._paths[i]!r} is a link of a referenced robot, not an object of "
                                      "the scene (only objects have it here)")
            out.append(prim)
        return out

    def get_visibilities(self, indices=None) -> np.ndarray:
        """(K,) bool: whether each matched object is drawn."""
        return np.array([p.get_visibility() for p in self._shapes(indices, "get_visibilities")], dtype=bool)

    def set_visibilities(self, visibilities, indices=None) -> None:
        """Show or hide (K,) bool the matched objects (drawn only: collisions are unchanged, as Isaac's)."""
        prims = self._shapes(indices, "set_visibilities")
        v = np.asarray(visibilities).reshape(-1)
        if v.size != len(prims) or v.dtype.kind not in "bi" or not np.all((v == 0) | (v == 1)):
            raise InvalidInputError(f"visibilities must be {len(prims)} bools; got {visibilities!r}")
        for prim, visible in zip(prims, v):
            prim.set_visibility(bool(visible))

    def get_local_poses(self, indices=None):
        """Positions (K, 3) [m] and orientations (K, 4) in each prim's parent frame: a robot
        link's in its model's frame (as `XFormPrim.get_local_pose`), any other prim's in the
        world (no other parent transforms)."""
        positions, orientations = self.get_world_poses(indices)
        stage = get_current_stage()
        refs = [p for p in stage.prim_paths() if stage.find_reference(p) is not None]
        for k, i in enumerate(self._idx(indices)):
            ref = next((stage.find_reference(r) for r in refs if self._paths[i].startswith(r + "/")), None)
            if ref is not None:
                positions[k], orientations[k] = relative_pose(model_frame_pose(ref), (positions[k], orientations[k]))
        return positions, orientations

    def set_local_poses(self, translations=None, orientations=None, indices=None) -> None:
        self.set_world_poses(translations, orientations, indices)


class RigidPrimView(RigidViewSleepThresholds, XFormPrimView):
    """`XFormPrimView` plus velocities and masses of rigid bodies."""

    def __init__(self, prim_paths_expr: str, name: str = "rigid_prim_view", positions=None, translations=None,
                 orientations=None, scales=None, visibilities=None, reset_xform_properties: bool = True, **kwargs):
        """Args as `XFormPrimView`; Isaac's PhysX options are accepted at their defaults only
        (`RIGID_VIEW_OPTIONS`; masses, densities and velocities at construction are not
        available: `set_masses` / `set_velocities` after the reset).

        Raises:
            InvalidInputError: an unknown keyword, or an option other than its default.
        """
        self._links: dict[str, RigidPrim] = {}  # wrappers of robot links whose masses were set
        filters = kwargs.pop("contact_filter_prim_paths_expr", None) or []
        for key in CONTACT_OPTIONS[:2] + CONTACT_OPTIONS[3:]:
            kwargs.pop(key, None)  # contact forces are always available here
        if isinstance(filters, str) or not all(isinstance(f, str) for f in filters):
            raise InvalidInputError(f"contact_filter_prim_paths_expr must be a list of prim path expressions; "
                                    f"got {filters!r}")
        self._filter_segments = [compile_path_expression(f) for f in filters]
        self._filter_bodies = np.zeros(0, dtype=int)
        for key, value in kwargs.items():
            if key not in RIGID_VIEW_OPTIONS:
                raise InvalidInputError(f"RigidPrimView got an unknown argument {key!r}; Isaac's options accepted: "
                                        f"{sorted(RIGID_VIEW_OPTIONS) + list(CONTACT_OPTIONS)}")
            if not _is_default(value, RIGID_VIEW_OPTIONS[key]):
                raise InvalidInputError(
                    f"RigidPrimView({key}={value!r}) is not supported (manip has no PhysX contact sensors or per-view "
                    f"body settings); leave it at {RIGID_VIEW_OPTIONS[key]!r} and set masses and velocities on the "
                    "objects (set_mass, set_linear_velocity) or on the view after world.reset() (set_velocities)")
        super().__init__(prim_paths_expr, name, positions, translations, orientations, scales, visibilities,
                         reset_xform_properties)

    def get_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K, 6): linear [m/s] (of the centre of mass, as PhysX) then angular [rad/s]
        velocity of each body, world frame."""
        sim = self._need()
        idx = self._idx(indices)
        sim.ensure_kinematics()
        out = np.zeros((idx.size, 6))
        res = np.zeros(6)
        for k, i in enumerate(idx):
            mujoco.mj_objectVelocity(sim.model, sim.data, mujoco.mjtObj.mjOBJ_BODY, int(self._bodies[i]), res, 0)
            out[k, :3], out[k, 3:] = res[3:], res[:3]
        return out

    def get_linear_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        return self.get_velocities(indices)[:, :3]

    def get_angular_velocities(self, indices=None, clone: bool = True) -> np.ndarray:
        return self.get_velocities(indices)[:, 3:]

    def set_velocities(self, velocities, indices=None) -> None:
        """Set (K, 6) linear + angular world velocities of free bodies."""
        sim = self._need()
        idx = self._idx(indices)
        v = batch(velocities, idx.size, 6, "velocities")
        check_bounded_rows(v[:, :3], "linear", "velocities (linear part)")
        check_bounded_rows(v[:, 3:], "angular", "velocities (angular part)")
        if not np.all(self._free[idx]):
            raise SimulationError("only free rigid bodies (Dynamic objects) have settable velocities")
        for k, i in enumerate(idx):
            sim.data.qvel[self._dadr[i]:self._dadr[i] + 3] = v[k, :3]
            sim.set_free_angular_velocity(self._qadr[i], self._dadr[i], v[k, 3:])
        sim.mark_stale()

    def get_masses(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K,) [kg]."""
        sim = self._need()
        return sim.model.body_mass[self._bodies[self._idx(indices)]].copy()

    def set_masses(self, masses, indices=None) -> None:
        """Set (K,) masses [kg] (each inertia scaled with its mass), at once and kept when the World
        compiles again (domain randomisation of Isaac's views); a robot's link too."""
        idx = self._idx(indices)
        m = as_real_array(masses, "masses").reshape(-1)
        if m.shape != (idx.size,):
            raise InvalidInputError(f"masses must be {idx.size} values [kg] (one per prim); got shape {np.shape(masses)}")
        for k, i in enumerate(idx):
            self._rigid(i).set_mass(float(m[k]))

    def get_densities(self, indices=None) -> np.ndarray:
        """(K,) [kg/m^3]: each object's mass over its shape's volume (objects only)."""
        return np.array([p.get_density() for p in self._shapes(indices, "get_densities")], dtype=float)

    def _rigid(self, i: int):
        """The RigidPrim of matched prim `i`: the scene object, or a wrapper of a robot's link."""
        prim = get_current_stage().get_prim(self._paths[i])
        if prim is None or not hasattr(prim, "set_mass"):
            if self._paths[i] not in self._links:
                self._links[self._paths[i]] = RigidPrim(self._paths[i])
            prim = self._links[self._paths[i]]
        return prim

    def bind_simulation(self, sim: SimHandle) -> None:
        super().bind_simulation(sim)
        m = sim.model
        self._filter_bodies = np.array([b for seg in self._filter_segments for b in range(1, m.nbody)
                                        if path_matches(seg, m.body(b).name)], dtype=int)

    # ------------------------------------------------------------------ velocities, one part at a time
    def set_linear_velocities(self, velocities, indices=None) -> None:
        """Set (K, 3) linear world velocities [m/s] of free bodies; angular ones kept."""
        v = self.get_velocities(indices)
        v[:, :3] = batch(velocities, v.shape[0], 3, "velocities")
        self.set_velocities(v, indices)

    def set_angular_velocities(self, velocities, indices=None) -> None:
        """Set (K, 3) angular world velocities [rad/s] of free bodies; linear ones kept."""
        v = self.get_velocities(indices)
        v[:, 3:] = batch(velocities, v.shape[0], 3, "velocities")
        self.set_velocities(v, indices)

    # ------------------------------------------------------------------ forces
    def apply_forces(self, forces, indices=None, is_global: bool = True) -> None:
        """Push each body with a force (K, 3) [N] at its centre of mass during the next
        physics step (as PhysX: apply it before every step to keep pushing); world frame, or
        each body's frame with `is_global=False`."""
        self.apply_forces_and_torques_at_pos(forces, None, None, indices, is_global)

    def apply_forces_and_torques_at_pos(self, forces=None, torques=None, positions=None, indices=None,
                                        is_global: bool = True) -> None:
        """Forces (K, 3) [N] at `positions` (K, 3) [m] (the centres of mass for None) and
        torques (K, 3) [N m] on each body during the next physics step; world frame, or each
        body's frame (positions too) with `is_global=False`.

        Raises:
            InvalidInputError: a wrong shape or a non-finite value.
        """
        sim = self._need()
        idx = self._idx(indices)
        f = batch(forces, idx.size, 3, "forces") if forces is not None else None
        t = batch(torques, idx.size, 3, "torques") if torques is not None else None
        p = batch(positions, idx.size, 3, "positions") if positions is not None else None
        for what, a in (("forces", f), ("torques", t), ("positions", p)):
            if a is not None and not np.all(np.isfinite(a)):
                raise InvalidInputError(f"{what} must be finite; got {a}")
        body_forces.apply(sim, self._bodies[idx], f, t, p, bool(is_global))

    # ------------------------------------------------------------------ contacts
    def _impulse_scale(self, dt: float) -> float:
        """Isaac's contact getters return impulses / dt: force * physics_dt / dt."""
        if not (dt > 0):
            raise InvalidInputError(f"dt must be > 0 [s]; got {dt!r}")
        return (self._sim.physics_dt or self._sim.model.opt.timestep) / dt

    def get_net_contact_forces(self, indices=None, clone: bool = True, dt: float = 1.0) -> np.ndarray:
        """(K, 3) total contact impulse on each body over the last physics step divided by
        `dt` (Isaac's convention: pass dt = physics_dt for forces [N]), world frame."""
        sim = self._need()
        return body_forces.net_contact_forces(sim, self._bodies[self._idx(indices)]) * self._impulse_scale(dt)

    def get_contact_force_matrix(self, indices=None, clone: bool = True, dt: float = 1.0) -> np.ndarray:
        """(K, F, 3) contact impulse on each body from each prim matched by the view's
        `contact_filter_prim_paths_expr` (F of them), divided by `dt` (as
        get_net_contact_forces), world frame.

        Raises:
            SimulationError: the view was made without contact_filter_prim_paths_expr.
        """
        sim = self._need()
        if not self._filter_segments:
            raise SimulationError(f"view {self._name!r}: get_contact_force_matrix needs the view made with "
                                  "contact_filter_prim_paths_expr=[...] (the prims whose contacts are reported)")
        return (body_forces.contact_force_matrix(sim, self._bodies[self._idx(indices)], self._filter_bodies)
                * self._impulse_scale(dt))

    def get_coms(self, indices=None, clone: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Centres of mass in the body frames: positions (K, 3) [m], orientations (K, 4)."""
        sim = self._need()
        b = self._bodies[self._idx(indices)]
        return sim.model.body_ipos[b].copy(), sim.model.body_iquat[b].copy()

    def get_inertias(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K, 9) inertia tensors about the centres of mass, body frame, row-major [kg m^2]."""
        sim = self._need()
        out = []
        for b in self._bodies[self._idx(indices)]:
            R = quat.to_matrix(sim.model.body_iquat[b])
            out.append((R @ np.diag(sim.model.body_inertia[b]) @ R.T).ravel())
        return np.array(out).reshape(-1, 9)

    def get_inv_masses(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K,) 1 / mass [1/kg]."""
        return 1.0 / self.get_masses(indices)

    def get_inv_inertias(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K, 9) inverse inertia tensors (as get_inertias)."""
        return np.array([np.linalg.inv(i.reshape(3, 3)).ravel() for i in self.get_inertias(indices)]).reshape(-1, 9)

    def get_current_dynamic_state(self, indices=None) -> DynamicsViewState:
        """Poses and velocities now (world frame)."""
        p, q = self.get_world_poses(indices)
        v = self.get_velocities(indices)
        return DynamicsViewState(p, q, v[:, :3], v[:, 3:])

    @property
    def num_contact_filters(self) -> int:
        return len(self._filter_bodies)

    # ------------------------------------------------------------------ gravity
    def enable_gravities(self, indices=None) -> None:
        """Gravity acts on the bodies again."""
        sim = self._need()
        sim.gravity_off.difference_update(int(b) for b in self._bodies[self._idx(indices)])

    def disable_gravities(self, indices=None) -> None:
        """No gravity on the bodies (their weight is cancelled at their centre of mass)."""
        sim = self._need()
        sim.gravity_off.update(int(b) for b in self._bodies[self._idx(indices)])

    # ------------------------------------------------------------------ default states
    def get_default_state(self) -> DynamicsViewState:
        """The default state of each body (what `World.reset()` restores)."""
        states = [self._object(p).get_default_state() for p in self._need_paths()]
        return DynamicsViewState(np.array([s.position for s in states]), np.array([s.orientation for s in states]),
                                 np.array([getattr(s, "linear_velocity", np.zeros(3)) for s in states]),
                                 np.array([getattr(s, "angular_velocity", np.zeros(3)) for s in states]))

    def set_default_state(self, positions=None, orientations=None, linear_velocities=None, angular_velocities=None,
                          indices=None) -> None:
        """Set the default states (K rows each; None keeps a part) of the bodies `indices`."""
        self._need()
        idx = self._idx(indices)
        rows = {k: (batch(v, idx.size, n, k) if v is not None else None) for k, v, n in (
            ("positions", positions, 3), ("orientations", orientations, 4),
            ("linear_velocities", linear_velocities, 3), ("angular_velocities", angular_velocities, 3))}
        for k, i in enumerate(idx):
            obj = self._object(self._paths[i])
            obj.set_default_state(*(None if v is None else v[k] for v in rows.values()))


declare_not_supported(XFormPrimView)
declare_not_supported(RigidPrimView)


isaac5_views.register(XFormPrim, XFormPrimView)
isaac5_views.register(RigidPrim, RigidPrimView)
