"""`XFormPrim`: a prim with a pose, new (a mocap body) or wrapping a body of a referenced model.

Prims have no parent transform: `/World` is the identity, so the local pose equals the
world pose, except for two kinds of prim: one fixed to a robot's link (its local pose is in
the link's frame) and one wrapping a link of a referenced model (its local pose is in the
model's frame, the parent prim of the links as in Isaac's robot USD files:
"/World/Franka/panda_hand" under "/World/Franka"). Quaternions are (w, x, y, z); positions in m.
"""

from __future__ import annotations

import logging

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.sim.scenes.stage import (ReferencePrim, SimHandle, SimulationError, Stage, UsdPrimMethods, get_current_stage,
                                    is_prim_path_valid, validate_prim_path)
from manip.sim.utils.types import DefaultPoseMixin, XFormPrimState, position_or_translation
from manip.validation import scale3, unit_quat
from manip.sim.utils.bounds import bounded_vec
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.sim.prims import isaac5_views

logger = logging.getLogger(__name__)

_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


class XFormPrim(DefaultPoseMixin, UsdPrimMethods):
    """A prim with a pose (Isaac's `SingleXFormPrim` / `XFormPrim`).

    Created at a free prim path, it is a new transform (a MuJoCo mocap body without
    geometry). Created at a path inside a referenced model (e.g. `/World/Franka/panda_hand`),
    it wraps that body (or site) of the model: its pose can be read, not set. Created at the
    path of an existing object (`XFormPrim`, `RigidPrim` or `GeometryPrim` over a cube made
    earlier, as Isaac wraps existing prims), it wraps that object's body: its pose (and a
    RigidPrim's velocities) can be read and set; the other arguments must be left None.

    Args:
        prim_path: where the prim lives, e.g. "/World/target".
        name: unique name in the scene (default: "xform_prim").
        position: (3,) world position [m]; `translation` is the same here (no parent
            transform); giving both raises.
        orientation: (4,) world orientation (w, x, y, z).
        scale: (3,) or scalar scale.
        visible: whether it is drawn.
        reset_xform_properties: Isaac's USD transform-op reset; accepted (no USD ops here).
    """

    _default_name = "xform_prim"
    prim_path: str  # where the prim lives on the stage
    _wraps_existing = True  # the shape classes and the ground plane always create their prim
    _mounts_on_links = True  # below a robot's link (no body or site of that name): a frame fixed to the link

    def __new__(cls, *args, **kwargs):
        # Isaac 5's `XFormPrim(prim_paths_expr=...)` (and RigidPrim's, GeometryPrim's) is a view.
        view = isaac5_views.view_call(cls, args, kwargs)
        return view if view is not None else super().__new__(cls)

    def __init__(
        self,
        prim_path: str,
        name: str | None = None,
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
        reset_xform_properties: bool = True,
    ):
        validate_prim_path(prim_path)
        self.prim_path = prim_path
        self._name = name if name is not None else self._default_name
        stage = get_current_stage()
        existing = stage.get_prim(prim_path) if self._wraps_existing else None
        if isinstance(existing, ReferencePrim):
            existing = None  # the model's root: use Articulation / Robot for it
        if existing is not None:
            given = [k for k, v in (("position", position), ("translation", translation),
                                    ("orientation", orientation), ("scale", scale), ("visible", visible)) if v is not None]
            if given:
                raise InvalidInputError(
                    f"{type(self).__name__} at {prim_path!r} wraps the existing {type(existing).__name__} there; "
                    f"{', '.join(given)} cannot be given (set them on the wrapped object)")
            position, orientation = existing.get_world_pose()
            scale = existing.get_local_scale()
        self._wrapped_object = existing
        p = position_or_translation(position, translation)
        self._pose = (
            bounded_vec(p, "position", "position") if p is not None else np.zeros(3),
            unit_quat(orientation) if orientation is not None else _IDENTITY.copy(),
        )
        self._scale = scale3(scale) if scale is not None else np.ones(3)
        self._visible = True if visible is None else bool(visible)
        self._default_state: XFormPrimState = self._make_default_state()
        self._sim: SimHandle | None = None
        self._body_id = -1
        self._site_id = -1
        self._mocap_id = -1
        self._qadr = -1
        self._dadr = -1
        self._wrapped_reference: ReferencePrim | None = None
        self._mount_link: str | None = None  # the link of a referenced model this prim is fixed to
        self._mount_ref: ReferencePrim | None = None
        self._link_id = -1
        for path in stage.prim_paths():
            if prim_path.startswith(path + "/") and stage.find_reference(path) is not None:
                self._wrapped_reference = stage.find_reference(path)
        if self._wrapped_reference is not None and self._mount(self._wrapped_reference):
            self._wrapped_reference = None  # a prim of its own, fixed to a link of the model
            stage.add_prim(self, inside_reference=True)
            if translation is None:  # a world pose (the robot at its authored pose): kept in the link's frame
                self._pose = relative_pose(self._link_pose(), self._pose)
                self._default_state = self._make_default_state()
        elif self._wrapped_reference is not None or self._wrapped_object is not None:
            ref = self._wrapped_reference
            if ref is not None and not ref.has_element(prim_path):  # else every world.reset() fails
                raise InvalidInputError(f"{type(self).__name__} {prim_path!r}: the model at {ref.prim_path!r} has no "
                                        f"body or site of that name (a {type(self).__name__} wraps one of its links)")
            stage.register_wrapper(self)
        else:
            stage.add_prim(self)

    def _mount(self, reference: ReferencePrim) -> bool:
        """Whether this prim, at a path inside `reference`'s model that is none of its bodies
        or sites, is a new prim fixed to the nearest link above it (a tool frame, a wrist
        camera), as Isaac makes an Xform there; else it wraps the model's body or site."""
        if not self._mounts_on_links or reference.has_element(self.prim_path):
            return False
        link = self.prim_path.rsplit("/", 1)[0]
        while link.startswith(reference.prefix) and not reference.has_body(link):
            link = link.rsplit("/", 1)[0]
        if not link.startswith(reference.prefix):
            raise InvalidInputError(f"{type(self).__name__} {self.prim_path!r} lies inside the model at "
                                    f"{reference.prim_path!r} but below none of its links: place it under one, e.g. "
                                    f"'{reference.prim_path}/<link>/{self.prim_path.rsplit('/', 1)[1]}'")
        self._mount_link, self._mount_ref = link, reference
        return True

    @property
    def mount_link(self) -> str | None:
        """The prim path of the robot link this prim is fixed to (None: not fixed to a link)."""
        return self._mount_link

    def _link_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """World pose of the link a mounted prim is fixed to (authored before the first reset)."""
        sim = self._sim
        if sim is None:
            return self._mount_ref.authored_pose(self._mount_link)
        sim.ensure_kinematics()
        return sim.data.xpos[self._link_id].copy(), sim.data.xquat[self._link_id].copy()

    def _set_local(self, position: np.ndarray, orientation: np.ndarray) -> None:
        """A mounted prim's pose in its link's frame, (3,) [m] and (4,) (w, x, y, z)."""
        self._pose = (position, orientation)
        if self._sim is not None:
            self._write_local(self._sim.model, position, orientation)

    def _write_local(self, model: mujoco.MjModel, position: np.ndarray, orientation: np.ndarray) -> None:
        """Into the compiled model: the mounted prim's site (a Camera: its camera)."""
        model.site_pos[self._site_id] = position
        model.site_quat[self._site_id] = orientation
        self._sim.mark_stale()

    def _add_mounted(self, body: mujoco.MjsBody) -> None:
        """The mounted prim's element on its link's body: an invisible site (a Camera: a camera)."""
        body.add_site(name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(),
                      size=[0.005, 0.005, 0.005], rgba=[0.0, 0.0, 0.0, 0.0], group=5)

    def _make_default_state(self) -> XFormPrimState:
        return XFormPrimState(self._pose[0].copy(), self._pose[1].copy())

    # ------------------------------------------------------------------ identity
    @property
    def name(self) -> str:
        """Unique name in the scene."""
        return self._name

    def is_valid(self) -> bool:
        """Whether a prim is at this prim's path on the stage (Isaac's method; it was a
        property here, and Isaac's call `is_valid()` raised TypeError)."""
        return is_prim_path_valid(self.prim_path)

    @property
    def simulated(self) -> bool:
        """Whether the prim is bound to the compiled World (after the `World.reset()` that
        compiled it)."""
        return self._sim is not None

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do: objects are bound when the World compiles (kept for Isaac scripts)."""

    # ------------------------------------------------------------------ building
    def add_to_spec(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        if self._mount_link is not None:
            link = spec.body(self._mount_link)
            if link is None:
                raise SimulationError(f"{self.prim_path!r}: its link {self._mount_link!r} is not in the model")
            self._add_mounted(link)
            return link
        body = spec.worldbody.add_body(
            name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(), mocap=True
        )
        return body

    def _bindable(self) -> bool:
        """Whether the compiled model holds this prim (a prim of a referenced model compiled
        already; a wrapped object compiled already)."""
        if self._wrapped_object is not None:
            return self._wrapped_object.simulated
        return self._wrapped_reference is None or self._wrapped_reference.core is not None

    def bind_simulation(self, sim: SimHandle) -> None:
        m = sim.model
        self._sim = sim
        if self._mount_link is not None:
            self._link_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, self._mount_link)
            self._site_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, self.prim_path)  # -1 for a camera
            return
        if self._wrapped_reference is not None:
            self._body_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, self.prim_path)
            self._site_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, self.prim_path)
            if self._body_id < 0 and self._site_id < 0:
                self._sim = None
                raise SimulationError(
                    f"XFormPrim {self.prim_path!r}: the referenced model has no body or site of that name"
                )
            if self._body_id >= 0:
                self._site_id = -1
            return
        self._body_id = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, self.prim_path)
        self._mocap_id = int(m.body_mocapid[self._body_id])
        jnt = m.body_jntadr[self._body_id]
        if jnt >= 0 and int(m.jnt_type[jnt]) == int(mujoco.mjtJoint.mjJNT_FREE):
            self._qadr = int(m.jnt_qposadr[jnt])
            self._dadr = int(m.jnt_dofadr[jnt])

    def unbind_simulation(self) -> None:
        self._sim = None

    def _removed_message(self, what: str) -> str | None:
        """Why this prim (not bound to a compiled world) has no state: it is no longer on the
        stage, so its stored values are stale (Isaac's deleted prim is invalid too); or None."""
        if self._wrapped_reference is not None or self._wrapped_object is not None \
                or get_current_stage().get_prim(self.prim_path) is self:
            return None
        return (f"{self.name}.{what}: {self.prim_path!r} is no longer on the stage (removed by scene.remove_object / "
                "scene.clear / world.clear, or made for an earlier World); add a new object")

    def _removed(self, what: str) -> bool:
        """Getters: True (after a warning, as for a robot's removed link) when the prim was removed."""
        message = self._removed_message(what)
        if message:
            logger.warning("%s; returning None", message)
        return message is not None

    def _require_on_stage(self, what: str) -> None:
        """Setters: raise SimulationError when the prim was removed (nothing to set)."""
        message = self._removed_message(what)
        if message:
            raise SimulationError(message)

    # ------------------------------------------------------------------ pose
    def get_world_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """World pose: position (3,) [m] and orientation (4,) (w, x, y, z).

        Before the first `World.reset()` it is the pose the prim was created with (or last
        set to); a body of a referenced model (a robot's link) is at the model's authored
        pose (its 'home' keyframe at the robot's pose on the stage).
        """
        if self._mount_link is not None:
            if self._sim is None and self._removed("get_world_pose"):
                return None  # type: ignore[return-value]
            return compose_poses(self._link_pose(), self._pose)
        sim = self._sim
        if sim is None:
            if self._wrapped_reference is not None:
                ref = self._wrapped_reference
                if get_current_stage().get_prim(ref.prim_path) is not ref:
                    logger.warning("%s: its model was removed from the stage; no pose (None)", self.prim_path)
                    return None  # type: ignore[return-value]
                pose = ref.authored_pose(self.prim_path)
                if pose is None:
                    raise SimulationError(f"XFormPrim {self.prim_path!r}: the referenced model "
                                          f"{self._wrapped_reference.prim_path!r} has no body or site of that name")
                return pose
            if self._wrapped_object is not None:
                return self._wrapped_object.get_world_pose()
            if self._removed("get_world_pose"):
                return None  # type: ignore[return-value]
            return self._pose[0].copy(), self._pose[1].copy()
        d = sim.data
        if self._qadr >= 0:
            return sim.free_pose(self._qadr)
        if self._mocap_id >= 0:
            return d.mocap_pos[self._mocap_id].copy(), d.mocap_quat[self._mocap_id].copy()
        sim.ensure_kinematics()
        if self._site_id >= 0:
            return d.site_xpos[self._site_id].copy(), quat.from_matrix(d.site_xmat[self._site_id].reshape(3, 3))
        return d.xpos[self._body_id].copy(), d.xquat[self._body_id].copy()

    def set_world_pose(self, position=None, orientation=None) -> None:
        """Teleport the prim. None keeps that part of the pose.

        Raises:
            InvalidInputError: non-finite position, or farther than `manip.sim.utils.bounds.MAX_WORLD_POSITION`
                (1e4 m) from the origin, or orientation not a unit quaternion.
            SimulationError: the prim is a body of a referenced model (move the robot instead).
        """
        p = bounded_vec(position, "position", "position") if position is not None else None
        q = unit_quat(orientation) if orientation is not None else None
        if self._mount_link is not None:  # stays fixed to its link, at the pose this gives in the link's frame
            self._require_on_stage("set_world_pose")
            now = compose_poses(self._link_pose(), self._pose)
            self._set_local(*relative_pose(self._link_pose(), (now[0] if p is None else p, now[1] if q is None else q)))
            return
        if self._wrapped_reference is not None:
            raise SimulationError(
                f"{self.prim_path!r} is part of the model at {self._wrapped_reference.prim_path!r}; "
                "its pose follows the joints (move the articulation instead)"
            )
        sim = self._sim
        if sim is None:
            if self._wrapped_object is not None:
                self._wrapped_object.set_world_pose(p, q)
                return
            self._require_on_stage("set_world_pose")
            self._pose = (p if p is not None else self._pose[0], q if q is not None else self._pose[1])
            return
        d = sim.data
        if self._qadr >= 0:
            if p is not None:
                d.qpos[self._qadr : self._qadr + 3] = p
            if q is not None:
                d.qpos[self._qadr + 3 : self._qadr + 7] = q
        else:
            if p is not None:
                d.mocap_pos[self._mocap_id] = p
            if q is not None:
                d.mocap_quat[self._mocap_id] = q
        sim.mark_stale()

    def get_local_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The pose in the parent prim's frame: the link's for a prim fixed to a robot's link,
        the model's (where its articulation is now) for a link of a referenced model, else the
        same as `get_world_pose` (no other parent transform here)."""
        if self._mount_link is not None:
            return self._pose[0].copy(), self._pose[1].copy()
        world = self.get_world_pose()
        if self._wrapped_reference is None or world is None:
            return world
        return relative_pose(self._model_frame(), world)

    def _model_frame(self) -> tuple[np.ndarray, np.ndarray]:
        return model_frame_pose(self._wrapped_reference)

    def set_local_pose(self, translation=None, orientation=None) -> None:
        """The pose in the link's frame for a prim fixed to a robot's link, else the same as
        `set_world_pose`."""
        if self._mount_link is None:
            self.set_world_pose(translation, orientation)
            return
        self._require_on_stage("set_local_pose")
        t = bounded_vec(translation, "position", "translation") if translation is not None else self._pose[0]
        self._set_local(t, unit_quat(orientation) if orientation is not None else self._pose[1])

    def get_local_scale(self) -> np.ndarray:
        """Scale (3,)."""
        return self._scale.copy()

    def get_world_scale(self) -> np.ndarray:
        return self._scale.copy()

    def set_local_scale(self, scale) -> None:
        """Change the scale; it takes effect at the next `World.reset()` (the model is recompiled)."""
        self._scale = scale3(scale)
        self._mark_changed()

    def _mark_changed(self) -> None:
        """A build parameter changed: the World recompiles at its next reset."""
        get_current_stage().mark_changed(self.prim_path)

    # ------------------------------------------------------------------ visibility
    def set_visibility(self, visible: bool) -> None:
        self._visible = bool(visible)
        self._apply_visibility()

    def get_visibility(self) -> bool:
        return self._visible

    def is_visible(self) -> bool:
        return self._visible

    def _apply_visibility(self) -> None:
        pass

    # ------------------------------------------------------------------ default state
    def post_reset(self) -> None:
        """Restore the default state (called by `World.reset()` for objects in the scene)."""
        if self._mount_link is not None:
            self._set_local(self._default_state.position.copy(), self._default_state.orientation.copy())
        elif self._wrapped_reference is None:
            self.set_world_pose(self._default_state.position, self._default_state.orientation)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(prim_path={self.prim_path!r}, name={self._name!r})"


declare_not_supported(XFormPrim)


def model_frame_pose(reference: ReferencePrim) -> tuple[np.ndarray, np.ndarray]:
    """World pose of a referenced model's frame (its links' parent prim): its articulation's
    pose if one wraps it (teleports included), else the pose authored on the stage."""
    for wrapper in get_current_stage().wrappers():
        if getattr(wrapper, "reference", None) is reference:
            pose = wrapper.get_world_pose()
            if pose is not None:
                return pose
    return reference.position.copy(), reference.orientation.copy()


def compose_poses(a, b) -> tuple[np.ndarray, np.ndarray]:
    """(position, wxyz) of frame b given in frame a, in a's parent frame (a @ b)."""
    c = Pose(*a) @ Pose(*b)
    return c.position.copy(), c.quaternion.copy()


def relative_pose(a, b) -> tuple[np.ndarray, np.ndarray]:
    """(position, wxyz) of frame b in frame a, both given in one parent frame (a^-1 @ b)."""
    inv = Pose(*a).inverse()
    return compose_poses((inv.position, inv.quaternion), b)


def link_prim(prim_path: str) -> XFormPrim:
    """The prim of a referenced model's body or site at `prim_path` (`get_prim_at_path` of a
    robot's link): an XFormPrim wrapping it, made once per path and reused."""
    for wrapper in get_current_stage().wrappers():
        if type(wrapper) is XFormPrim and wrapper.prim_path == prim_path:
            return wrapper
    return XFormPrim(prim_path, name=prim_path.rsplit("/", 1)[1])


Stage.link_prim_maker = staticmethod(link_prim)
