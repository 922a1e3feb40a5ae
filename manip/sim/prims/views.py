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
from manip.sim.scenes.stage import SimHandle, SimulationError, get_current_stage
from manip.sim.utils.bounds import check_bounded_rows
from manip.validation import batch

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


#: Isaac's RigidPrimView options with the default values accepted here.
RIGID_VIEW_OPTIONS = {
    "masses": None, "densities": None, "linear_velocities": None, "angular_velocities": None,
    "track_contact_forces": False, "prepare_contact_sensors": False, "disable_stablization": True,
    "contact_filter_prim_paths_expr": [], "max_contact_count": 0,
}


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
                 orientations=None, scales=None, visibilities=None, reset_xform_properties: bool = True):
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
        self._qadr = np.where(free, m.jnt_qposadr[np.maximum(jnt, 0)], -1)
        self._dadr = np.where(free, m.jnt_dofadr[np.maximum(jnt, 0)], -1)
        self._mocap = m.body_mocapid[self._bodies].copy()
        p, q = self._initial
        if p is not None or q is not None:
            self.set_world_poses(p, q)
            self._initial = (None, None)

    def unbind_simulation(self) -> None:
        self._sim = None

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do (bound when the World compiles)."""

    def post_reset(self) -> None:
        """Nothing to do: the prims restore their own default states."""

    def is_valid(self) -> bool:
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

    def _idx(self, indices) -> np.ndarray:
        if indices is None:
            return np.arange(self.count)
        idx = np.asarray(indices, dtype=int).ravel()
        if np.any(idx < 0) or np.any(idx >= self.count):
            raise InvalidInputError(f"indices {idx.tolist()} out of range for a view of {self.count} prims")
        return idx

    def get_world_poses(self, indices=None) -> tuple[np.ndarray, np.ndarray]:
        """Positions (K, 3) [m] and orientations (K, 4) (w, x, y, z)."""
        sim = self._need()
        idx = self._idx(indices)
        sim.ensure_kinematics()
        b = self._bodies[idx]
        return sim.data.xpos[b].copy(), sim.data.xquat[b].copy()

    def set_world_poses(self, positions=None, orientations=None, indices=None) -> None:
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

    def get_local_poses(self, indices=None):
        """Same as get_world_poses (no parent transforms)."""
        return self.get_world_poses(indices)

    def set_local_poses(self, translations=None, orientations=None, indices=None) -> None:
        self.set_world_poses(translations, orientations, indices)


class RigidPrimView(XFormPrimView):
    """`XFormPrimView` plus velocities and masses of rigid bodies."""

    def __init__(self, prim_paths_expr: str, name: str = "rigid_prim_view", positions=None, translations=None,
                 orientations=None, scales=None, visibilities=None, reset_xform_properties: bool = True, **kwargs):
        """Args as `XFormPrimView`; Isaac's PhysX options are accepted at their defaults only
        (`RIGID_VIEW_OPTIONS`; contact sensors, per-view masses and velocities are not
        available: set them on the objects).

        Raises:
            InvalidInputError: an unknown keyword, or an option other than its default.
        """
        for key, value in kwargs.items():
            if key not in RIGID_VIEW_OPTIONS:
                raise InvalidInputError(f"RigidPrimView got an unknown argument {key!r}; Isaac's options accepted: "
                                        f"{sorted(RIGID_VIEW_OPTIONS)}")
            if not _is_default(value, RIGID_VIEW_OPTIONS[key]):
                raise InvalidInputError(
                    f"RigidPrimView({key}={value!r}) is not supported (manip has no PhysX contact sensors or per-view "
                    f"body settings); leave it at {RIGID_VIEW_OPTIONS[key]!r} and set masses and velocities on the "
                    "objects (set_mass, set_linear_velocity) or on the view after world.reset() (set_velocities)")
        super().__init__(prim_paths_expr, name, positions, translations, orientations, scales, visibilities,
                         reset_xform_properties)

    def get_velocities(self, indices=None) -> np.ndarray:
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

    def get_linear_velocities(self, indices=None) -> np.ndarray:
        return self.get_velocities(indices)[:, :3]

    def get_angular_velocities(self, indices=None) -> np.ndarray:
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

    def get_masses(self, indices=None) -> np.ndarray:
        """(K,) [kg]."""
        sim = self._need()
        return sim.model.body_mass[self._bodies[self._idx(indices)]].copy()
