"""The robot's visual meshes in a viser scene, posed at an arm configuration.

The URDF's visual geometry is read with Pinocchio (`pin.buildGeomFromUrdf`, VISUAL) and
each geometry object becomes one scene node `<root>/<geometry name>`; its mesh file is
loaded with trimesh (COLLADA via pycollada, keeping the file's materials) and sent once
as a GLB. `RobotMeshes.set_configuration(q)` places every node from Pinocchio's geometry
placements (`pin.updateGeometryPlacements`), so the scene matches the planner's
kinematics exactly (the gripper joints at their planning positions).
"""

from __future__ import annotations

import functools
import io
import logging
import threading
from typing import Any

import coal
import numpy as np
import pinocchio as pin
import trimesh

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics

logger = logging.getLogger(__name__)

#: Colour [0-255] of geometry that carries no material of its own (primitives).
ROBOT_COLOR = (230, 230, 235)


@functools.lru_cache(maxsize=64)
def mesh_glb(path: str) -> bytes:
    """The mesh file at `path` (.dae, .stl, .obj, ...) as GLB bytes, materials kept (cached).

    Raises:
        InvalidInputError: trimesh cannot read the file.
    """
    try:
        loaded = trimesh.load(path)
    except Exception as exc:  # trimesh raises many types (ValueError, KeyError, ImportError, ...)
        raise InvalidInputError(f"cannot read the mesh file {path}: {exc}") from exc
    with io.BytesIO() as buf:
        loaded.export(buf, file_type="glb")
        return buf.getvalue()


def _add_geometry(scene: Any, name: str, obj: pin.GeometryObject, visible: bool) -> Any:
    """One scene node for a Pinocchio geometry object (a mesh file or a coal primitive)."""
    geom = obj.geometry
    color = tuple(int(round(255 * c)) for c in obj.meshColor[:3]) if obj.overrideMaterial else ROBOT_COLOR
    if isinstance(geom, coal.BVHModelBase) and obj.meshPath:
        return scene.add_glb(name, mesh_glb(obj.meshPath), scale=tuple(float(s) for s in obj.meshScale),
                             visible=visible)
    if isinstance(geom, coal.Box):
        return scene.add_box(name, color=color, dimensions=2.0 * np.asarray(geom.halfSide), visible=visible)
    if isinstance(geom, coal.Sphere):
        return scene.add_icosphere(name, radius=float(geom.radius), color=color, visible=visible)
    if isinstance(geom, coal.Cylinder):
        return scene.add_cylinder(name, radius=float(geom.radius), height=2.0 * float(geom.halfLength),
                                  color=color, visible=visible)
    if isinstance(geom, coal.Capsule):
        m = trimesh.creation.capsule(height=2.0 * float(geom.halfLength), radius=float(geom.radius))
        return scene.add_mesh_simple(name, m.vertices, m.faces, color=color, visible=visible)
    raise InvalidInputError(
        f"visual geometry '{obj.name}' is a {type(geom).__name__}; the viewer shows meshes, boxes, spheres, "
        "cylinders and capsules"
    )


class RobotMeshes:
    """The robot's visual meshes as scene nodes under `root`, posed by `set_configuration`.

    Args:
        scene: a viser `SceneApi` (`server.scene`).
        kinematics: the planner's kinematics (its URDF, package folders, full model and
            locked gripper positions).
        root: scene-tree prefix of the nodes.
        visible: whether the nodes start visible.
    """

    def __init__(self, scene: Any, kinematics: Kinematics, root: str = "/robot", *, visible: bool = True):
        cfg = kinematics.config
        self._model = kinematics.full_model
        self._data = self._model.createData()
        self._geom = pin.buildGeomFromUrdf(self._model, str(cfg.urdf_path), pin.GeometryType.VISUAL,
                                           package_dirs=list(cfg.package_dirs))
        self._gdata = pin.GeometryData(self._geom)
        self._q_full = np.array(kinematics.locked_configuration, dtype=float)
        self._q_index = np.array([self._model.joints[self._model.getJointId(j)].idx_q for j in cfg.arm_joints])
        self._lock = threading.Lock()
        self.dof = len(cfg.arm_joints)
        self.root = root
        self.handles: dict[str, Any] = {}
        for obj in self._geom.geometryObjects:
            name = f"{root}/{obj.name}"
            self.handles[name] = _add_geometry(scene, name, obj, visible)
        self.configuration = np.asarray(cfg.default_joint_positions, dtype=float).copy()
        self.set_configuration(self.configuration)

    @property
    def node_names(self) -> list[str]:
        """Scene names of the robot's nodes (one per visual geometry object)."""
        return list(self.handles)

    def link_poses(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Poses of the visual geometry objects at arm configuration q (dof,) [rad].

        Returns:
            positions (G, 3) [m] and (w, x, y, z) quaternions (G, 4), base frame.
        """
        q = np.asarray(q, dtype=float)
        if q.shape != (self.dof,) or not np.all(np.isfinite(q)):
            raise InvalidInputError(f"q must be {self.dof} finite joint positions [rad]; got shape {q.shape}")
        with self._lock:
            self._q_full[self._q_index] = q
            pin.forwardKinematics(self._model, self._data, self._q_full)
            pin.updateGeometryPlacements(self._model, self._data, self._geom, self._gdata)
            R = np.array([M.rotation for M in self._gdata.oMg])
            p = np.array([M.translation for M in self._gdata.oMg])
        return p, quat.from_matrix(R)

    def set_configuration(self, q: np.ndarray) -> None:
        """Pose every node at arm configuration q (dof,) [rad]."""
        p, wxyz = self.link_poses(q)
        for h, pi, qi in zip(self.handles.values(), p, wxyz):
            h.position = pi
            h.wxyz = qi
        self.configuration = np.array(q, dtype=float)

    def set_visible(self, visible: bool) -> None:
        """Show or hide every node of the robot."""
        for h in self.handles.values():
            h.visible = bool(visible)
