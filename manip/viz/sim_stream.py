"""A MuJoCo simulation's bodies streamed to a viser scene.

`SimStream(server, model)` sends the model's visible geoms once: each moving body is a
frame node `<root>/<body>` with its geoms as children at their local poses (meshes from
`model.mesh_vert` / `mesh_face`, primitives as boxes, spheres, cylinders, capsules,
ellipsoids, planes as thin boxes), and the world body's geoms are placed once. `push(data)`
then moves the body frames that moved to `data.xpos` / `data.xquat` (one atomic update),
at most `max_rate` times per second of wall time: what a browser shows at 30 Hz costs a
few milliseconds per frame, however fast the physics steps.

The stream reads only the MuJoCo model and data; it does not import `manip.sim` (the
SimulationApp creates it when `{"viewer": "web"}` is asked for).
"""

from __future__ import annotations

import logging
import time
from typing import Any

import mujoco
import numpy as np
import trimesh

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)

#: Geom groups shown (MuJoCo's viewer shows groups 0-2 by default).
VISIBLE_GROUPS = (0, 1, 2)
#: Bodies that moved less than this since the last frame (position [m], quaternion
#: components) are not re-sent: invisible, and most of a scene is usually at rest.
#: The wall clock the rate limit reads [s] (tests replace it to pace the stream themselves).
clock = time.perf_counter
SEND_TOLERANCE = 1e-5
#: Side [m] of a plane drawn for an infinite MuJoCo plane (size 0).
INFINITE_PLANE_SIZE = 4.0


def _name(model: mujoco.MjModel, obj: mujoco.mjtObj, i: int, prefix: str) -> str:
    name = mujoco.mj_id2name(model, obj, i)
    return (name or f"{prefix}{i}").replace("/", "_")


def _color(model: mujoco.MjModel, g: int) -> tuple[tuple[int, int, int], float | None]:
    mat = int(model.geom_matid[g])
    rgba = model.mat_rgba[mat] if mat >= 0 else model.geom_rgba[g]
    rgb = tuple(int(round(255 * min(max(c, 0.0), 1.0))) for c in rgba[:3])   # above 1 (USD HDR) draws saturated
    alpha = float(rgba[3])
    return rgb, (None if alpha >= 1.0 else alpha)


def add_geom(scene: Any, name: str, model: mujoco.MjModel, g: int, position: np.ndarray,
             wxyz: np.ndarray) -> Any | None:
    """One MuJoCo geom `g` as a scene node at `position`, `wxyz` in its parent; None if not drawable."""
    color, opacity = _color(model, g)
    size = model.geom_size[g]
    kw = dict(color=color, opacity=opacity, position=position, wxyz=wxyz)
    t = int(model.geom_type[g])
    if t == mujoco.mjtGeom.mjGEOM_PLANE:
        sx = 2 * size[0] if size[0] > 0 else INFINITE_PLANE_SIZE
        sy = 2 * size[1] if size[1] > 0 else INFINITE_PLANE_SIZE
        return scene.add_box(name, dimensions=(sx, sy, 0.002), receive_shadow=True, **kw)
    if t == mujoco.mjtGeom.mjGEOM_SPHERE:
        return scene.add_icosphere(name, radius=float(size[0]), **kw)
    if t == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        return scene.add_icosphere(name, radius=1.0, scale=tuple(float(s) for s in size[:3]), **kw)
    if t == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return scene.add_cylinder(name, radius=float(size[0]), height=2 * float(size[1]), **kw)
    if t == mujoco.mjtGeom.mjGEOM_BOX:
        return scene.add_box(name, dimensions=2 * np.asarray(size[:3], dtype=float), **kw)
    if t == mujoco.mjtGeom.mjGEOM_CAPSULE:
        m = trimesh.creation.capsule(height=2 * float(size[1]), radius=float(size[0]))
        return scene.add_mesh_simple(name, m.vertices, m.faces, **kw)
    if t == mujoco.mjtGeom.mjGEOM_MESH:
        mid = int(model.geom_dataid[g])
        va, vn = int(model.mesh_vertadr[mid]), int(model.mesh_vertnum[mid])
        fa, fn = int(model.mesh_faceadr[mid]), int(model.mesh_facenum[mid])
        return scene.add_mesh_simple(name, model.mesh_vert[va:va + vn], model.mesh_face[fa:fa + fn], **kw)
    logger.warning("geom %s (type %s) is not drawn in the browser", name, mujoco.mjtGeom(t).name)
    return None


class SimStream:
    """Streams a MuJoCo model's body poses to a viser server.

    Args:
        server: the viser server.
        model: the compiled MuJoCo model.
        root: scene-tree prefix of the nodes.
        max_rate: largest number of pushes per second of wall time [Hz] (> 0).
        groups: geom groups drawn.
    """

    def __init__(self, server: Any, model: mujoco.MjModel, *, root: str = "/sim", max_rate: float = 30.0,
                 groups: tuple[int, ...] = VISIBLE_GROUPS):
        if not (isinstance(max_rate, (int, float)) and np.isfinite(max_rate) and max_rate > 0):
            raise InvalidInputError(f"max_rate must be a positive number [Hz]; got {max_rate!r}")
        self.server = server
        self.model = model
        self.root = root
        self.min_interval = 1.0 / float(max_rate)
        self.frames: dict[int, Any] = {}  # body id -> frame handle
        self.geoms: dict[str, Any] = {}  # node name -> geom handle
        self.pushes = 0
        self._last_push = -np.inf
        scene = server.scene
        body_names = {b: _name(model, mujoco.mjtObj.mjOBJ_BODY, b, "body") for b in range(model.nbody)}
        shown = [g for g in range(model.ngeom) if int(model.geom_group[g]) in groups and model.geom_rgba[g][3] > 0]
        with server.atomic():
            for g in shown:
                b = int(model.geom_bodyid[g])
                if b == 0 or (int(model.body_weldid[b]) == 0 and int(model.body_mocapid[b]) < 0):
                    continue  # static: drawn below at its world pose
                if b not in self.frames:
                    self.frames[b] = scene.add_frame(f"{root}/{body_names[b]}", show_axes=False)
            static_data = mujoco.MjData(model)
            mujoco.mj_kinematics(model, static_data)
            for g in shown:
                b = int(model.geom_bodyid[g])
                gname = _name(model, mujoco.mjtObj.mjOBJ_GEOM, g, "geom")
                if b in self.frames:
                    node = f"{root}/{body_names[b]}/{gname}"
                    h = add_geom(scene, node, model, g, model.geom_pos[g], model.geom_quat[g])
                else:
                    node = f"{root}/static/{gname}"
                    wxyz = np.empty(4)
                    mujoco.mju_mat2Quat(wxyz, static_data.geom_xmat[g])
                    h = add_geom(scene, node, model, g, static_data.geom_xpos[g].copy(), wxyz)
                if h is not None:
                    self.geoms[node] = h
        self._bodies = np.array(sorted(self.frames), dtype=int)
        self._handles = [self.frames[b] for b in self._bodies]
        self._sent = np.full((len(self._bodies), 7), np.inf)  # last sent position and quaternion

    @property
    def node_names(self) -> list[str]:
        """Names of the body frames and geom nodes sent."""
        return [h.name for h in self._handles] + list(self.geoms)

    def due(self) -> bool:
        """Whether 1 / max_rate s of wall time have passed since the last push."""
        return clock() - self._last_push >= self.min_interval

    def push(self, data: mujoco.MjData, *, force: bool = False) -> bool:
        """Send the bodies' poses in `data` (xpos, xquat must be current), rate-limited.

        Args:
            data: the simulation's data (of the stream's model).
            force: send even if the last push was less than 1 / max_rate s ago.

        Returns:
            Whether the poses were sent.
        """
        now = clock()
        if not force and now - self._last_push < self.min_interval:
            return False
        self._last_push = now
        pose = np.concatenate([data.xpos[self._bodies], data.xquat[self._bodies]], axis=1)
        moved = np.flatnonzero(np.max(np.abs(pose - self._sent), axis=1) > SEND_TOLERANCE)
        with self.server.atomic():
            for i in moved:
                h = self._handles[i]
                h.position = pose[i, :3]
                h.wxyz = pose[i, 3:]
        self._sent[moved] = pose[moved]
        self.pushes += 1
        return True

    def remove(self) -> None:
        """Remove every node the stream sent."""
        for name, h in self.geoms.items():
            if name.startswith(f"{self.root}/static/"):
                h.remove()  # body geoms go with their frame
        for h in self._handles:
            h.remove()
        self.geoms.clear()
        self._handles = []
        self.frames.clear()
