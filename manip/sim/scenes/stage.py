"""The stage: every prim (shape, transform, referenced model file) that the World compiles.

Isaac Sim keeps a USD stage; here the stage is a small registry of prims, each knowing how
to add itself to a `mujoco.MjSpec`. Creating an object puts its prim on the stage (as
creating a prim in Isaac does); `World.reset()` compiles the stage into a MuJoCo model.
MuJoCo names are prefixed by the prim path: the cube at `/World/cube` is the body
`/World/cube`, a Franka referenced at `/World/Franka` has joints `/World/Franka/panda_joint1`...
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from pathlib import Path
from collections.abc import Callable
from typing import Any, ClassVar, Protocol

import mujoco
import numpy as np

from manip import package_uri
from manip import quaternion as quat
from manip.sim.scenes.variants import VariantSet
from manip.errors import InvalidInputError, ManipError, RobotConfigError
from manip.sim.assets import MODEL_SUFFIXES, get_assets_root_path, resolve_asset_path
from manip.sim.core.callbacks import CallbackTable

logger = logging.getLogger(__name__)


class SimulationError(ManipError):
    """A misuse of the simulation API (wrong order of calls, a model that does not compile)."""


def validate_prim_path(prim_path: str) -> str:
    """Check that `prim_path` is an absolute USD prim path like `/World/cube_1`.

    Every segment is a prim name as USD's Sdf paths allow: a letter or `_`, then letters, digits
    or `_` (USD 24.03+ also takes Unicode letters: Python's `str.isidentifier`). Spaces, `-`,
    `.`, `:` and a leading digit are refused, as Isaac Sim's stage refuses them.
    """
    if not isinstance(prim_path, str) or not prim_path.startswith("/") or prim_path.endswith("/"):
        raise InvalidInputError(f"prim_path must be an absolute path like '/World/cube'; got {prim_path!r}")
    parts = prim_path[1:].split("/")
    if any(not p or p != p.strip() for p in parts):
        raise InvalidInputError(f"prim_path {prim_path!r} has an empty or blank segment")
    bad = [p for p in parts if not p.isidentifier()]
    if bad:
        raise InvalidInputError(
            f"prim_path {prim_path!r}: {bad[0]!r} is not a valid USD prim name; a prim name starts with a "
            f"letter or '_' and has only letters, digits and '_' (no spaces, '-', '.' or ':'), e.g. "
            f"{_valid_name(bad[0])!r}"
        )
    return prim_path


def _valid_name(name: str) -> str:
    """`name` made a valid prim name (other characters as '_', '_' before a leading digit), for messages."""
    out = "".join(c if (c == "_" or c.isalnum()) else "_" for c in name)
    return out if out.isidentifier() else "_" + out


class SimHandle:
    """The compiled model and its data, shared by every bound object.

    After physics steps the positions are current but the derived kinematics (body and
    geom poses, velocities) are stale; getters call `ensure_kinematics()`, which runs
    MuJoCo's position and velocity kinematics at most once per step.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData):
        self.model = model
        self.data = data
        self.kinematics_stale = True
        #: dof address (K,) of each free joint and its body's bounding radius [m] (K,), set
        #: by the compiler (`manip.sim.core.substeps` reads them).
        self.free_dofs = np.zeros(0, dtype=int)
        self.free_radii = np.zeros(0)
        #: Bodies whose external force (`xfrc_applied`) acts for the next physics step only.
        self.pulsed_bodies: set[int] = set()
        #: Bodies on which gravity does not act (`RigidPrimView.disable_gravities`).
        self.gravity_off: set[int] = set()
        #: The World's physics step [s] (set at each step by `manip.sim.core.substeps`).
        self.physics_dt: float | None = None
        #: Called after every physics step (a `SurfaceGripper` checks whether its grip broke).
        self.after_step: list = []
        #: The referenced robots' `ArticulationCore`s, held weakly (a teleported robot is checked
        #: against them; set by the World when it compiles).
        self.robot_cores = ()

    def ensure_kinematics(self) -> None:
        if self.kinematics_stale:
            mujoco.mj_kinematics(self.model, self.data)
            mujoco.mj_comPos(self.model, self.data)
            mujoco.mj_comVel(self.model, self.data)
            self.kinematics_stale = False

    def mark_stale(self) -> None:
        self.kinematics_stale = True

    # Free joints: qpos[qadr:qadr+7] = position (3,) [m], quaternion (4,) (w, x, y, z);
    # qvel[dadr:dadr+6] = linear velocity (world frame) [m/s], angular velocity (body frame) [rad/s].
    def free_pose(self, qadr: int) -> tuple[np.ndarray, np.ndarray]:
        """Position (3,) [m] and unit quaternion (4,) of the free joint at qpos address `qadr`."""
        q = self.data.qpos[qadr:qadr + 7]
        return q[:3].copy(), q[3:7] / np.linalg.norm(q[3:7])

    def free_rotation(self, qadr: int) -> np.ndarray:
        """Rotation matrix (3, 3) body -> world of the free joint at qpos address `qadr`."""
        q = self.data.qpos[qadr + 3:qadr + 7]
        return quat.to_matrix(q / np.linalg.norm(q))

    def free_angular_velocity(self, qadr: int, dadr: int) -> np.ndarray:
        """World-frame angular velocity (3,) [rad/s] of a free joint."""
        return self.free_rotation(qadr) @ self.data.qvel[dadr + 3:dadr + 6]

    def set_free_angular_velocity(self, qadr: int, dadr: int, w) -> None:
        """Set a free joint's angular velocity from world-frame `w` (3,) [rad/s]."""
        self.data.qvel[dadr + 3:dadr + 6] = self.free_rotation(qadr).T @ w


class StagePrim(Protocol):
    """What the World needs from a prim to compile and bind it (a `ReferencePrim` is bound
    by the World, which gives it an `ArticulationCore`)."""

    prim_path: str

    def add_to_spec(self, spec: mujoco.MjSpec) -> None: ...

    def bind_simulation(self, sim: SimHandle) -> None: ...


#: manip's shape classes -> the USD prim type Isaac creates for them (`UsdPrimMethods.GetTypeName`).
_USD_TYPES = (("Cuboid", "Cube"), ("Sphere", "Sphere"), ("Cylinder", "Cylinder"), ("Capsule", "Capsule"),
              ("Cone", "Cone"), ("Camera", "Camera"))


class UsdPrimMethods:
    """`Usd.Prim`'s reading methods (USD's CamelCase names) on manip's prims: Isaac's
    `get_prim_at_path` returns a `Usd.Prim`, manip's returns its object, which answers these.
    Paths are flat as in Isaac's robot USD files: a referenced model's links are its children
    ("/World/Franka/panda_hand"), a prim mounted below a link (a tool frame) the link's child."""

    prim_path: str

    def IsValid(self) -> bool:
        """Whether a prim is at this path on the stage (False once removed)."""
        return is_prim_path_valid(self.prim_path)

    def GetPath(self) -> str:
        """The prim path (a str; USD's Sdf.Path prints as the same string)."""
        return self.prim_path

    GetPrimPath = GetPath

    def GetName(self) -> str:
        """The last segment of the path ("panda_hand")."""
        return self.prim_path.rsplit("/", 1)[1]

    def GetTypeName(self) -> str:
        """The USD type Isaac gives it: "Cube", "Sphere", ... for shapes, "Camera", else "Xform"."""
        name = type(self).__name__
        return next((usd for cls, usd in _USD_TYPES if cls in name), "Xform")

    def GetChildren(self) -> list[Any]:
        """The prims one segment below this one (a model's links; a link's mounted prims)."""
        return [get_prim_at_path(p) for p in child_paths(self.prim_path)]

    def GetParent(self) -> Any | None:
        """The prim one segment above (None at "/World", which is no object here)."""
        return get_prim_at_path(self.prim_path.rsplit("/", 1)[0])

    def GetAttribute(self, name: str):
        """Refused: manip has no USD attributes (the object's getters and setters hold its state)."""
        raise NotImplementedError(f"{self.prim_path}.GetAttribute({name!r}): manip has no USD attributes; use the "
                                  f"object's getters and setters ({type(self).__name__})")

    @property
    def prim(self) -> Any:
        """Isaac's `Usd.Prim` of this object: here the object itself, which answers USD's reading
        methods (`IsValid`, `GetPath`, `GetName`, `GetTypeName`, `GetChildren`, `GetParent`) and is
        what the prim utilities take."""
        return self


class ReferencePrim(UsdPrimMethods):
    """A model file (MJCF or URDF) referenced on the stage under `prim_path`.

    Every MuJoCo name of the file is prefixed by `prim_path + "/"`. Before compiling, the
    prim's pose places the file's world frame; joints without an actuator get one, as every
    joint of an Isaac articulation has a drive: in an MJCF a drive with zero gains; in a URDF
    the drive Isaac's URDF importer makes (a position drive, kp = `URDF_DRIVE_STIFFNESS`,
    kd = `URDF_DRIVE_DAMPING`, force limited to the joint's `<limit effort>`).
    """

    def __init__(self, file_path: Path, prim_path: str):
        self.file_path = file_path
        self.prim_path = prim_path
        self.prefix = prim_path + "/"
        self.position = np.zeros(3)
        self.orientation = np.array([1.0, 0.0, 0.0, 0.0])
        self.home_qpos: dict[str, np.ndarray] = {}  # joint name (unprefixed) -> qpos of the 'home' key
        # The model's ArticulationCore, set by the World while a compiled model exists.
        self.core: Any = None
        self._probe: tuple[mujoco.MjModel, mujoco.MjData] | None = None  # the file alone, for authored poses
        self._names: tuple[frozenset, frozenset] | None = None  # the file's (body, site) names
        self._variants: dict[str, str] = {}  # USD variant selections, kept (`GetVariantSet`)
        #: PhysX's enabledSelfCollisions as set (`Articulation.set_enabled_self_collisions`): None keeps the
        #: model's own filter, False excludes every pair of its bodies from contact when compiled.
        self.self_collisions: bool | None = None

    def GetVariantSet(self, name: str) -> VariantSet:  # noqa: N802 (USD's name, as Isaac 5's examples call it)
        """The asset's variant set `name` (selections are kept and change nothing: `manip.sim.scenes.variants`)."""
        return VariantSet(self._variants, name, self.prim_path)

    def unbind_simulation(self) -> None:
        """Forget the compiled model's core (the prim was removed from the stage)."""
        self.core = None

    def authored_pose(self, prim_path: str) -> tuple[np.ndarray, np.ndarray] | None:
        """World pose of a body or site of this model as authored on the stage, before the
        World compiles it: the model at its 'home' keyframe (else its reference pose) placed
        at this prim's pose. Position (3,) [m], orientation (4,) (w, x, y, z); None if the
        model has no body or site at `prim_path`."""
        if self._probe is None:
            spec = self._load_spec()
            home = next((k for k in spec.keys if k.name == "home"), None)
            model = spec.compile()
            data = mujoco.MjData(model)
            if home is not None and np.asarray(home.qpos).size == model.nq:
                data.qpos[:] = home.qpos
            mujoco.mj_kinematics(model, data)
            self._probe = (model, data)
        model, data = self._probe
        name = prim_path[len(self.prefix):]
        b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
        s = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name) if b < 0 else -1
        if b < 0 and s < 0:
            return None
        p = data.xpos[b] if b >= 0 else data.site_xpos[s]
        q = data.xquat[b] if b >= 0 else quat.from_matrix(data.site_xmat[s].reshape(3, 3))
        R = quat.to_matrix(self.orientation)
        return self.position + R @ p, quat.multiply(self.orientation, q)

    def _element_names(self) -> tuple[frozenset, frozenset]:
        """The file's body and site names, read once from its parsed spec (nothing compiled or
        kept but the names)."""
        if self._names is None:
            spec = self._load_spec()
            self._names = (frozenset(b.name for b in spec.bodies), frozenset(x.name for x in spec.sites))
        return self._names

    def has_body(self, prim_path: str) -> bool:
        """Whether the model has a body (a link) at `prim_path` (its name after the prefix)."""
        return prim_path.startswith(self.prefix) and prim_path[len(self.prefix):] in self._element_names()[0]

    def has_element(self, prim_path: str) -> bool:
        """Whether the model has a body or a site at `prim_path`."""
        bodies, sites = self._element_names()
        return prim_path.startswith(self.prefix) and prim_path[len(self.prefix):] in bodies | sites

    def _load_spec(self) -> mujoco.MjSpec:
        try:
            if self.file_path.suffix.lower() == ".urdf":
                child = mujoco.MjSpec.from_string(_urdf_with_mesh_paths(self.file_path))
            else:
                child = mujoco.MjSpec.from_file(str(self.file_path))
        except Exception as exc:  # a mesh not found (RobotConfigError), bad XML, MuJoCo's ValueError
            raise SimulationError(f"cannot load {self.file_path} for prim {self.prim_path}: {exc}") from exc
        return child

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        child = self._load_spec()
        # Make asset paths absolute: after attaching, relative paths would resolve against
        # the parent's (non-existent) folder.
        base = Path(child.modelfiledir or self.file_path.parent)
        meshdir = base / (child.meshdir or "")
        texdir = base / (child.texturedir or "")
        for mesh in child.meshes:
            if mesh.file and not Path(mesh.file).is_absolute():
                mesh.file = str((meshdir / mesh.file).resolve())
        for tex in child.textures:
            if tex.file and not Path(tex.file).is_absolute():
                tex.file = str((texdir / tex.file).resolve())
        child.meshdir = ""
        child.texturedir = ""
        # Keyframes: remember 'home' (default joint state), drop all (their sizes would not
        # match the assembled model).
        self.home_qpos = {}
        keys = list(child.keys)
        home = next((k for k in keys if k.name == "home"), None)
        if home is not None:
            probe = child.copy().compile()
            qpos = np.asarray(home.qpos, dtype=float)
            if qpos.size == probe.nq:
                for j in range(probe.njnt):
                    if int(probe.jnt_type[j]) in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                        self.home_qpos[probe.joint(j).name] = qpos[probe.jnt_qposadr[j]].copy()
        for k in keys:
            child.delete(k)
        actuated = {a.target for a in child.actuators if a.trntype == mujoco.mjtTrn.mjTRN_JOINT}
        urdf = self.file_path.suffix.lower() == ".urdf"
        efforts = _urdf_effort_limits(self.file_path) if urdf else {}
        for joint in child.joints:
            if joint.type in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE) and joint.name not in actuated:
                if not joint.name:
                    continue
                act = child.add_actuator(name=joint.name, target=joint.name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
                if urdf:
                    _isaac_urdf_drive(act, efforts.get(joint.name))
        bodies = [b.name for b in child.bodies if b.name and b.name != "world"]
        frame = spec.worldbody.add_frame(pos=self.position.tolist(), quat=self.orientation.tolist())
        spec.attach(child, prefix=self.prefix, frame=frame)
        if self.self_collisions is False:  # no contact between any two of the model's bodies
            for i, a in enumerate(bodies):
                for b in bodies[i + 1:]:
                    spec.add_exclude(bodyname1=self.prefix + a, bodyname2=self.prefix + b)


def _urdf_with_mesh_paths(file_path: Path) -> str:
    """The URDF's text with each mesh file name made absolute as ROS tools resolve it
    (`package://`, `file://`, relative: `manip.package_uri`), which MuJoCo's URDF parser does
    not do. A collision mesh that resolves to no file raises RobotConfigError naming the URI
    and the folders searched; a visual one is left as written (MuJoCo discards URDF visuals
    unless the URDF's <mujoco><compiler discardvisual="false"/> asks for them)."""
    root = ET.parse(file_path).getroot()
    collision = {id(m) for m in package_uri.mesh_uris(root, collision_only=True)}
    for mesh in package_uri.mesh_uris(root):
        uri = mesh.get("filename", "")
        try:
            mesh.set("filename", str(package_uri.resolve(uri, file_path, "collision mesh")))
        except RobotConfigError:
            if id(mesh) in collision:
                raise
    # keep the absolute paths whole (MuJoCo's URDF compiler may strip the folders)
    ext = root.find("mujoco")
    if ext is None:
        ext = ET.SubElement(root, "mujoco")
    compiler = ext.find("compiler")
    if compiler is None:
        compiler = ET.SubElement(ext, "compiler")
    compiler.set("strippath", "false")
    return ET.tostring(root, encoding="unicode")


#: Drive gains Isaac's URDF importer gives every joint (its ImportConfig defaults: a position
#: drive of strength 1e3 and damping 1e2) [N m/rad, N m s/rad or N/m, N s/m].
URDF_DRIVE_STIFFNESS = 1e3
URDF_DRIVE_DAMPING = 1e2


def _urdf_effort_limits(file_path: Path) -> dict[str, float]:
    """{joint name: effort limit [N m or N]} of a URDF's `<limit effort>` (> 0 only)."""
    out = {}
    try:
        for joint in ET.parse(file_path).getroot().iter("joint"):
            limit = joint.find("limit")
            if limit is not None and float(limit.get("effort", 0.0)) > 0.0:
                out[joint.get("name")] = float(limit.get("effort"))
    except (ET.ParseError, ValueError, OSError) as exc:  # MuJoCo reports a malformed file itself
        logger.warning("%s: no URDF effort limits read (%s)", file_path, exc)
    return out


def _isaac_urdf_drive(act, effort: float | None) -> None:
    """Make `act` the drive Isaac's URDF importer creates: a position drive with its default
    gains, its force limited to the joint's URDF effort limit (unlimited without one)."""
    act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    bias = list(act.biasprm)
    bias[1], bias[2] = -URDF_DRIVE_STIFFNESS, -URDF_DRIVE_DAMPING
    act.biasprm = bias
    if effort is not None:
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-effort, effort]


class Stage:
    """The prims the World compiles, by prim path (insertion order is kept)."""

    #: Makes the prim of a referenced model's body or site (path -> prim or None): set by
    #: `manip.sim.prims.xform_prim` (an XFormPrim wrapping the link), read by `get_prim_at_path`.
    link_prim_maker: ClassVar[Callable[[str], Any] | None] = None

    def __init__(self) -> None:
        self._prims: dict[str, Any] = {}
        self._wrappers: list[Any] = []  # objects bound after each compile (Articulations)
        self.version = 0
        #: The stage-event callbacks (`World.add_stage_callback` adds to it).
        self.callbacks = CallbackTable("stage")
        self.sim: SimHandle | None = None  # set by the World while a compiled model exists
        #: Semantic labels by prim path ({type: label}; `manip.sim.utils.semantics`).
        self.semantics: dict[str, dict[str, str]] = {}

    def add_prim(self, prim: Any, inside_reference: bool = False) -> None:
        """Put `prim` on the stage; `inside_reference`: a prim fixed to a link of a referenced
        model (a wrist camera), below the model's path."""
        path = validate_prim_path(prim.prim_path)
        if path in self._prims:
            raise InvalidInputError(
                f"a prim already exists at {path!r} ({type(self._prims[path]).__name__}); use another prim_path "
                f"or remove it first"
            )
        for existing in self._prims:
            if path.startswith(existing + "/") and isinstance(self._prims[existing], ReferencePrim) \
                    and not inside_reference:
                raise InvalidInputError(
                    f"{path!r} lies inside the referenced model at {existing!r}; objects must be created outside it"
                )
        self._prims[path] = prim
        self.notify_changed("PRIM_ADDED", path)

    def remove_prim(self, prim_path: str) -> None:
        """Delete the prim at `prim_path` and, as USD deletes a prim's children, every prim
        and wrapper at or below it (e.g. a Franka's end-effector frame with the Franka).
        What is removed is unbound (articulation getters return None, as before a reset);
        the model changes at the next `World.reset()`."""
        if prim_path not in self._prims:
            return

        def below(path: object) -> bool:
            return isinstance(path, str) and (path == prim_path or path.startswith(prim_path + "/"))

        gone = [self._prims.pop(p) for p in list(self._prims) if below(p)]
        self.semantics = {p: labels for p, labels in self.semantics.items() if not below(p)}
        gone += [w for w in self._wrappers if below(getattr(w, "prim_path", None))]
        self._wrappers = [w for w in self._wrappers if w not in gone]
        for obj in gone:
            if hasattr(obj, "unbind_simulation"):
                obj.unbind_simulation()
        self.notify_changed("PRIM_REMOVED", prim_path)

    def get_prim(self, prim_path: str) -> Any | None:
        return self._prims.get(prim_path)

    def prims(self) -> list[Any]:
        return list(self._prims.values())

    def prim_paths(self) -> list[str]:
        return list(self._prims)

    def register_wrapper(self, wrapper: Any) -> None:
        """Remember `wrapper` to bind it after each compile; at once if the model is compiled
        and holds the wrapper's prims (`wrapper._bindable()`, default True). A wrapper of a
        prim added since the last compile is bound by the next `World.reset()`."""
        if wrapper not in self._wrappers:
            self._wrappers.append(wrapper)
            bindable = getattr(wrapper, "_bindable", None)
            if self.sim is not None and (bindable is None or bindable()):
                wrapper.bind_simulation(self.sim)

    def wrappers(self) -> list[Any]:
        return list(self._wrappers)

    def find_reference(self, prim_path: str) -> ReferencePrim | None:
        prim = self._prims.get(prim_path)
        return prim if isinstance(prim, ReferencePrim) else None

    def mark_changed(self, prim_path: str) -> None:
        """Note that the prim at `prim_path` changed: the World recompiles at its next reset."""
        self.notify_changed("PRIM_CHANGED", prim_path)

    def notify_changed(self, kind: str, path: str) -> None:
        self.version += 1
        self.callbacks.call(StageEvent(kind, path))

    def clear(self) -> None:
        self.sim = None
        self._prims.clear()
        self._wrappers.clear()
        self.semantics.clear()
        self.notify_changed("CLEARED", "/")


class StageEvent:
    """What a stage callback receives: `type` ("PRIM_ADDED", "PRIM_REMOVED", "CLEARED",
    "COMPILED") and the prim `path`."""

    def __init__(self, type: str, path: str):
        self.type = type
        self.path = path

    def __repr__(self) -> str:
        return f"StageEvent({self.type!r}, {self.path!r})"


_STAGE = Stage()


def get_current_stage(fabric: bool = False) -> Stage:
    """The stage that objects and references are created on (`fabric` accepted for Isaac's
    signature: there is one stage)."""
    return _STAGE


def create_new_stage() -> Stage:
    """Empty the stage (all prims and wrappers are forgotten). Returns it."""
    _STAGE.clear()
    return _STAGE


def is_prim_path_valid(prim_path: str, fabric: bool = False) -> bool:
    """Whether a prim exists at `prim_path` on the current stage: an object, a referenced
    model, or a body or site of a referenced model ("/World/Franka/panda_hand", as in Isaac,
    where a robot's links are prims below it)."""
    if prim_path in _STAGE._prims:
        return True
    for path, prim in _STAGE._prims.items():
        if isinstance(prim, ReferencePrim) and prim_path.startswith(path + "/"):
            return prim.has_element(prim_path) and prim_path != prim.prefix + "world"  # not MuJoCo's worldbody
    return False


def get_prim_at_path(prim_path: str, fabric: bool = False) -> Any | None:
    """The prim at `prim_path` (Isaac's `omni.isaac.core.utils.prims.get_prim_at_path`): the
    object or referenced model there, the `XFormPrim` of a robot's link or site (one per path,
    its pose read from MuJoCo), or None (`fabric` accepted for Isaac's signature). Each answers
    USD's `IsValid()`, `GetPath()`, `GetName()`, `GetTypeName()`, `GetChildren()`, `GetParent()`."""
    prim = _STAGE.get_prim(prim_path)
    if prim is None and Stage.link_prim_maker is not None and is_prim_path_valid(prim_path):
        prim = Stage.link_prim_maker(prim_path)
    return prim


def child_paths(prim_path: str) -> list[str]:
    """Paths one segment below `prim_path`: prims on the stage and the links (bodies and sites)
    of a referenced model at `prim_path`."""
    paths = set(_STAGE.prim_paths())
    ref = _STAGE.find_reference(prim_path)
    if ref is not None:
        bodies, sites = ref._element_names()
        paths |= {ref.prefix + n for n in bodies | sites if n and n != "world" and "/" not in n}
    return sorted(p for p in paths if p.rsplit("/", 1)[0] == prim_path)


def add_reference_to_stage(usd_path: str | Path, prim_path: str, prim_type: str = "Xform") -> ReferencePrim:
    """Load a model into the stage under `prim_path` (Isaac's `add_reference_to_stage`).

    `usd_path` is an Isaac asset path (`get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"`,
    see `manip.sim.assets.ISAAC_ASSETS`), which loads the bundled MuJoCo model, or an MJCF
    (.xml) or URDF (.urdf) file. Its names are prefixed by `prim_path + "/"` once compiled
    by `World.reset()`. Differs from Isaac: no USD files; a referenced model cannot be
    referenced twice at the same prim path.

    Raises:
        FileNotFoundError: no such asset (the message lists the available ones).
        InvalidInputError: the prim path is malformed or taken, or the file type is not
            .xml/.mjcf/.urdf.
    """
    path = resolve_asset_path(usd_path)
    if path.suffix.lower() not in MODEL_SUFFIXES:
        raise InvalidInputError(f"add_reference_to_stage: expected an MJCF (.xml) or URDF (.urdf) file; got {path}")
    validate_prim_path(prim_path)
    prim = ReferencePrim(path, prim_path)
    _STAGE.add_prim(prim)
    return prim


async def create_new_stage_async() -> Stage:
    """`create_new_stage()`, awaitable (Isaac's extension workflow)."""
    return create_new_stage()


def update_stage() -> None:
    """Nothing to do: the stage has no pending USD updates here (kept for Isaac scripts)."""


async def update_stage_async() -> None:
    """Nothing to do (Isaac waits for the next app update); awaitable."""
