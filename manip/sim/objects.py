"""Prims with a pose: transforms, Visual/Fixed/Dynamic shapes and the ground plane.

Families, as in Isaac Sim:
- `Visual*`: drawn, no collision, moved only by `set_world_pose` (a MuJoCo mocap body).
- `Fixed*`: collides, never moves by physics (a mocap body: static for the solver).
- `Dynamic*`: a rigid body with a free joint, mass (default 0.02 kg) or density.

Objects have no parent transform: `/World` is the identity, so the local pose equals the
world pose. Physics materials: MuJoCo has one sliding friction per geom, so a material's
dynamic friction is used (static friction only if dynamic is missing); MuJoCo combines the
two geoms of a contact by taking the larger friction. Restitution is not modelled (MuJoCo
contacts are soft and inelastic); it is kept for reference only.
"""

from __future__ import annotations

import logging

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.errors import InvalidInputError
from manip.sim import _validate as V
from manip.sim.stage import ReferencePrim, SimHandle, SimulationError, get_current_stage, validate_prim_path
from manip.sim.types import DefaultPoseMixin, DynamicState, XFormPrimState

logger = logging.getLogger(__name__)

_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


class PhysicsMaterial:
    """Friction/restitution of a surface (Isaac's `PhysicsMaterial`).

    Args:
        prim_path: path of the material (informative only).
        name: its name.
        static_friction: static friction coefficient (used if dynamic is None).
        dynamic_friction: sliding friction coefficient (what MuJoCo uses).
        restitution: kept for reference, not simulated.
    """

    def __init__(
        self,
        prim_path: str = "/World/Physics_Materials/material",
        name: str = "physics_material",
        static_friction: float | None = None,
        dynamic_friction: float | None = None,
        restitution: float | None = None,
    ):
        self.prim_path = prim_path
        self.name = name
        self._static = static_friction
        self._dynamic = dynamic_friction
        self._restitution = restitution
        for what, v in (("static_friction", static_friction), ("dynamic_friction", dynamic_friction)):
            if v is not None and (not np.isfinite(v) or v < 0):
                raise InvalidInputError(f"{what} must be a finite number >= 0; got {v}")

    def get_static_friction(self) -> float | None:
        return self._static

    def get_dynamic_friction(self) -> float | None:
        return self._dynamic

    def get_restitution(self) -> float | None:
        return self._restitution

    def mujoco_friction(self) -> float | None:
        """The sliding friction MuJoCo uses: dynamic friction, else static, else None."""
        return self._dynamic if self._dynamic is not None else self._static


class XFormPrim(DefaultPoseMixin):
    """A prim with a pose (Isaac's `SingleXFormPrim` / `XFormPrim`).

    Created at a free prim path, it is a new transform (a MuJoCo mocap body without
    geometry). Created at a path inside a referenced model (e.g. `/World/Franka/panda_hand`),
    it wraps that body (or site) of the model: its pose can be read, not set.

    Args:
        prim_path: where the prim lives, e.g. "/World/target".
        name: unique name in the scene (default: "xform_prim").
        position: (3,) world position [m]; `translation` is the same here (no parent
            transform); giving both raises.
        orientation: (4,) world orientation (w, x, y, z).
        scale: (3,) or scalar scale.
        visible: whether it is drawn.
    """

    _default_name = "xform_prim"

    def __init__(
        self,
        prim_path: str,
        name: str | None = None,
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
    ):
        validate_prim_path(prim_path)
        self.prim_path = prim_path
        self._name = name if name is not None else self._default_name
        if position is not None and translation is not None:
            raise InvalidInputError("give either position (world) or translation (local), not both")
        p = position if position is not None else translation
        self._pose = (
            V.vec(p, 3, "position") if p is not None else np.zeros(3),
            V.unit_quat(orientation) if orientation is not None else _IDENTITY.copy(),
        )
        self._scale = V.scale3(scale) if scale is not None else np.ones(3)
        self._visible = True if visible is None else bool(visible)
        self._default_state: XFormPrimState = self._make_default_state()
        self._sim: SimHandle | None = None
        self._body_id = -1
        self._site_id = -1
        self._mocap_id = -1
        self._qadr = -1
        self._dadr = -1
        self._wrapped_reference: ReferencePrim | None = None
        stage = get_current_stage()
        for path in stage.prim_paths():
            if prim_path.startswith(path + "/") and stage.find_reference(path) is not None:
                self._wrapped_reference = stage.find_reference(path)
        if self._wrapped_reference is not None:
            stage.register_wrapper(self)
        else:
            stage.add_prim(self)

    def _make_default_state(self) -> XFormPrimState:
        return XFormPrimState(self._pose[0].copy(), self._pose[1].copy())

    # ------------------------------------------------------------------ identity
    @property
    def name(self) -> str:
        """Unique name in the scene."""
        return self._name

    @property
    def is_valid(self) -> bool:
        return self._sim is not None

    def initialize(self, physics_sim_view=None) -> None:
        """Nothing to do: objects are bound when the World compiles (kept for Isaac scripts)."""

    # ------------------------------------------------------------------ building
    def _build(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        body = spec.worldbody.add_body(
            name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(), mocap=True
        )
        return body

    def _bind(self, sim: SimHandle) -> None:
        m = sim.model
        self._sim = sim
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

    def _unbind(self) -> None:
        self._sim = None

    # ------------------------------------------------------------------ pose
    def get_world_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """World pose: position (3,) [m] and orientation (4,) (w, x, y, z).

        Before the first `World.reset()` it is the pose the prim was created with (or last
        set to).
        """
        sim = self._sim
        if sim is None:
            if self._wrapped_reference is not None:
                logger.warning("%s: pose unknown before the first World.reset(); returning None", self.prim_path)
                return None  # type: ignore[return-value]
            return self._pose[0].copy(), self._pose[1].copy()
        d = sim.data
        if self._qadr >= 0:
            q = d.qpos[self._qadr : self._qadr + 7]
            return q[:3].copy(), q[3:7] / np.linalg.norm(q[3:7])
        if self._mocap_id >= 0:
            return d.mocap_pos[self._mocap_id].copy(), d.mocap_quat[self._mocap_id].copy()
        sim.ensure_kinematics()
        if self._site_id >= 0:
            return d.site_xpos[self._site_id].copy(), quat.from_matrix(d.site_xmat[self._site_id].reshape(3, 3))
        return d.xpos[self._body_id].copy(), d.xquat[self._body_id].copy()

    def set_world_pose(self, position=None, orientation=None) -> None:
        """Teleport the prim. None keeps that part of the pose.

        Raises:
            InvalidInputError: non-finite position, or orientation not a unit quaternion.
            SimulationError: the prim is a body of a referenced model (move the robot instead).
        """
        p = V.vec(position, 3, "position") if position is not None else None
        q = V.unit_quat(orientation) if orientation is not None else None
        if self._wrapped_reference is not None:
            raise SimulationError(
                f"{self.prim_path!r} is part of the model at {self._wrapped_reference.prim_path!r}; "
                "its pose follows the joints (move the articulation instead)"
            )
        sim = self._sim
        if sim is None:
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
        """Same as `get_world_pose` (prims have no parent transform here)."""
        return self.get_world_pose()

    def set_local_pose(self, translation=None, orientation=None) -> None:
        """Same as `set_world_pose` (prims have no parent transform here)."""
        self.set_world_pose(translation, orientation)

    def get_local_scale(self) -> np.ndarray:
        """Scale (3,)."""
        return self._scale.copy()

    def get_world_scale(self) -> np.ndarray:
        return self._scale.copy()

    def set_local_scale(self, scale) -> None:
        """Change the scale; it takes effect at the next `World.reset()` (the model is recompiled)."""
        self._scale = V.scale3(scale)
        get_current_stage()._changed("PRIM_CHANGED", self.prim_path)

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
        if self._wrapped_reference is None:
            self.set_world_pose(self._default_state.position, self._default_state.orientation)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(prim_path={self.prim_path!r}, name={self._name!r})"


# ---------------------------------------------------------------------------- shapes
_FAMILY_COLLIDES = {"visual": False, "fixed": True, "dynamic": True, "ground": True}


class GeometryPrim(XFormPrim):
    """A prim with one geometry (base of the shape classes)."""

    _family = "visual"
    _shape = "cuboid"

    def __init__(
        self,
        prim_path: str,
        name: str | None = None,
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
        color=None,
        physics_material: PhysicsMaterial | None = None,
        visual_material=None,
    ):
        self._color = V.vec(color, 3, "color") if color is not None else np.array([0.5, 0.5, 0.5])
        if np.any(self._color < 0) or np.any(self._color > 1):
            raise InvalidInputError(f"color must be RGB in [0, 1]; got {self._color}")
        self._physics_material = physics_material
        self._geom_id = -1
        super().__init__(prim_path, name, position, translation, orientation, scale, visible)

    # shape parameters: overridden
    def _geom_type_size(self) -> tuple[int, list[float]]:
        raise NotImplementedError

    def _build(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        dynamic = self._family == "dynamic"
        body = spec.worldbody.add_body(
            name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(), mocap=not dynamic
        )
        if dynamic:
            body.add_freejoint(name=self.prim_path + "/root_joint")
        gtype, size = self._geom_type_size()
        collides = _FAMILY_COLLIDES[self._family]
        kwargs = dict(
            name=self.prim_path + "/geom",
            type=gtype,
            size=size,
            rgba=[*self._color.tolist(), 1.0 if self._visible else 0.0],
            contype=1 if collides else 0,
            conaffinity=1 if collides else 0,
            group=0 if collides else 2,
        )
        if gtype == mujoco.mjtGeom.mjGEOM_MESH:
            kwargs["meshname"] = self._build_mesh(spec)
        if self._physics_material is not None and self._physics_material.mujoco_friction() is not None:
            kwargs["friction"] = [self._physics_material.mujoco_friction(), 0.005, 0.0001]
        geom = body.add_geom(**kwargs)
        if dynamic:
            self._set_mass_props(geom)
        elif not collides:
            geom.mass = 0.0
        return body

    def _build_mesh(self, spec: mujoco.MjSpec) -> str:
        raise NotImplementedError

    def _set_mass_props(self, geom) -> None:
        pass

    def _bind(self, sim: SimHandle) -> None:
        super()._bind(sim)
        self._geom_id = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, self.prim_path + "/geom")

    def _apply_visibility(self) -> None:
        if self._sim is not None and self._geom_id >= 0:
            self._sim.model.geom_rgba[self._geom_id, 3] = 1.0 if self._visible else 0.0

    def get_color(self) -> np.ndarray:
        return self._color.copy()

    def set_color(self, color) -> None:
        c = V.vec(color, 3, "color")
        self._color = c
        if self._sim is not None:
            self._sim.model.geom_rgba[self._geom_id, :3] = c

    def get_applied_physics_material(self) -> PhysicsMaterial | None:
        return self._physics_material

    def apply_physics_material(self, physics_material: PhysicsMaterial) -> None:
        """Use this material's friction (immediately if compiled)."""
        self._physics_material = physics_material
        f = physics_material.mujoco_friction()
        if self._sim is not None and f is not None:
            self._sim.model.geom_friction[self._geom_id, 0] = f

    def set_collision_enabled(self, enabled: bool) -> None:
        """Enable/disable contacts of the geometry (immediately if compiled)."""
        if self._sim is not None:
            v = 1 if enabled else 0
            self._sim.model.geom_contype[self._geom_id] = v
            self._sim.model.geom_conaffinity[self._geom_id] = v

    @property
    def geom_id(self) -> int:
        """Index of the MuJoCo geom (-1 before the World compiles)."""
        return self._geom_id

    def _shape_dimensions(self) -> np.ndarray:
        """Dimensions in the `CollisionObject` convention (see Scene.get_collision_objects)."""
        raise NotImplementedError


class _Cuboid:
    _shape = "cuboid"

    def _init_shape(self, size):
        self._size = V.positive(size if size is not None else 1.0, "size")

    def get_size(self) -> float:
        """Edge length before scaling [m] (real edge lengths = size * scale)."""
        return self._size

    def set_size(self, size: float) -> None:
        """Change the edge length; takes effect at the next `World.reset()`."""
        self._size = V.positive(size, "size")
        get_current_stage()._changed("PRIM_CHANGED", self.prim_path)

    def _geom_type_size(self):
        return mujoco.mjtGeom.mjGEOM_BOX, (0.5 * self._size * self._scale).tolist()

    def _shape_dimensions(self) -> np.ndarray:
        return self._size * self._scale


class _Sphere:
    _shape = "sphere"

    def _init_shape(self, radius):
        self._radius = V.positive(radius if radius is not None else 1.0, "radius")

    def get_radius(self) -> float:
        return self._radius

    def set_radius(self, radius: float) -> None:
        """Change the radius; takes effect at the next `World.reset()`."""
        self._radius = V.positive(radius, "radius")
        get_current_stage()._changed("PRIM_CHANGED", self.prim_path)

    def _geom_type_size(self):
        r = self._radius * self._scale
        if np.allclose(r, r[0]):
            return mujoco.mjtGeom.mjGEOM_SPHERE, [float(r[0]), 0.0, 0.0]
        return mujoco.mjtGeom.mjGEOM_ELLIPSOID, r.tolist()

    def _shape_dimensions(self) -> np.ndarray:
        r = self._radius * self._scale
        return np.array([r[0]]) if np.allclose(r, r[0]) else r


class _RadiusHeight:
    def _init_shape(self, radius, height):
        self._radius = V.positive(radius if radius is not None else 1.0, "radius")
        self._height = V.positive(height if height is not None else 1.0, "height")
        if not np.isclose(self._scale[0], self._scale[1]):
            logger.warning("%s: x and y scales differ; the radius uses the x scale", self.prim_path)

    def get_radius(self) -> float:
        return self._radius

    def get_height(self) -> float:
        return self._height

    def set_radius(self, radius: float) -> None:
        """Change the radius; takes effect at the next `World.reset()`."""
        self._radius = V.positive(radius, "radius")
        get_current_stage()._changed("PRIM_CHANGED", self.prim_path)

    def set_height(self, height: float) -> None:
        """Change the height; takes effect at the next `World.reset()`."""
        self._height = V.positive(height, "height")
        get_current_stage()._changed("PRIM_CHANGED", self.prim_path)

    def _rh(self) -> tuple[float, float]:
        return self._radius * self._scale[0], self._height * self._scale[2]

    def _shape_dimensions(self) -> np.ndarray:
        return np.array(self._rh())


class _Cylinder(_RadiusHeight):
    _shape = "cylinder"

    def _geom_type_size(self):
        r, h = self._rh()
        return mujoco.mjtGeom.mjGEOM_CYLINDER, [r, 0.5 * h, 0.0]


class _Capsule(_RadiusHeight):
    """Height is the length of the cylindrical part (as in USD); the total length is height + 2 radius."""

    _shape = "capsule"

    def _geom_type_size(self):
        r, h = self._rh()
        return mujoco.mjtGeom.mjGEOM_CAPSULE, [r, 0.5 * h, 0.0]


class _Cone(_RadiusHeight):
    """A cone along z, centred on its prim: base disc at -height/2, apex at +height/2
    (USD's convention). MuJoCo has no cone primitive: it is a 48-sided convex mesh."""

    _shape = "cone"
    _EDGES = 48

    def _geom_type_size(self):
        return mujoco.mjtGeom.mjGEOM_MESH, [0.0, 0.0, 0.0]

    def _build_mesh(self, spec: mujoco.MjSpec) -> str:
        r, h = self._rh()
        a = np.linspace(0.0, 2 * np.pi, self._EDGES, endpoint=False)
        verts = np.vstack([[0.0, 0.0, 0.5 * h], np.c_[r * np.cos(a), r * np.sin(a), np.full(a.size, -0.5 * h)]])
        name = self.prim_path + "/mesh"
        spec.add_mesh(name=name, uservert=verts.ravel().tolist())
        return name


class _DynamicMixin:
    def _init_dynamic(self, mass, density, linear_velocity, angular_velocity):
        if mass is not None and density is not None:
            raise InvalidInputError("give either mass or density, not both")
        self._mass = V.positive(mass, "mass") if mass is not None else None
        self._density = V.positive(density, "density") if density is not None else None
        if self._mass is None and self._density is None:
            self._mass = 0.02
        lin = V.vec(linear_velocity, 3, "linear_velocity") if linear_velocity is not None else np.zeros(3)
        ang = V.vec(angular_velocity, 3, "angular_velocity") if angular_velocity is not None else np.zeros(3)
        s = self._default_state
        self._default_state = DynamicState(s.position, s.orientation, lin, ang)

    def _set_mass_props(self, geom) -> None:
        if self._mass is not None:
            geom.mass = self._mass
        else:
            geom.density = self._density


class RigidPrim(XFormPrim):
    """Velocity/mass API of a rigid body (mixed into the Dynamic* shapes)."""

    def _require_dynamic(self) -> None:
        if self._sim is not None and self._qadr < 0:
            raise SimulationError(f"{self.prim_path!r} is not a free rigid body")

    def get_linear_velocity(self) -> np.ndarray:
        """Linear velocity of the body origin (3,) [m/s], world frame."""
        if self._sim is None:
            return self._default_state.linear_velocity.copy()
        self._require_dynamic()
        return self._sim.data.qvel[self._dadr : self._dadr + 3].copy()

    def get_angular_velocity(self) -> np.ndarray:
        """Angular velocity (3,) [rad/s], world frame."""
        if self._sim is None:
            return self._default_state.angular_velocity.copy()
        self._require_dynamic()
        d = self._sim.data
        q = d.qpos[self._qadr + 3 : self._qadr + 7]
        return quat.to_matrix(q / np.linalg.norm(q)) @ d.qvel[self._dadr + 3 : self._dadr + 6]

    def set_linear_velocity(self, velocity) -> None:
        v = V.vec(velocity, 3, "linear velocity")
        if self._sim is None:
            self._default_state.linear_velocity = v
            return
        self._require_dynamic()
        self._sim.data.qvel[self._dadr : self._dadr + 3] = v
        self._sim.mark_stale()

    def set_angular_velocity(self, velocity) -> None:
        """Set the angular velocity (3,) [rad/s], world frame."""
        w = V.vec(velocity, 3, "angular velocity")
        if self._sim is None:
            self._default_state.angular_velocity = w
            return
        self._require_dynamic()
        d = self._sim.data
        q = d.qpos[self._qadr + 3 : self._qadr + 7]
        d.qvel[self._dadr + 3 : self._dadr + 6] = quat.to_matrix(q / np.linalg.norm(q)).T @ w
        self._sim.mark_stale()

    def get_velocities(self) -> np.ndarray:
        """(6,) linear then angular velocity, world frame."""
        return np.concatenate([self.get_linear_velocity(), self.get_angular_velocity()])

    def get_mass(self) -> float:
        """Mass [kg]."""
        if self._sim is not None:
            return float(self._sim.model.body_mass[self._body_id])
        if getattr(self, "_mass", None) is not None:
            return float(self._mass)
        return float(self._density * self._volume())

    def set_mass(self, mass: float) -> None:
        """Change the mass [kg]; the inertia is scaled with it. Immediate if compiled."""
        m = V.positive(mass, "mass")
        if self._sim is not None:
            model = self._sim.model
            old = model.body_mass[self._body_id]
            model.body_inertia[self._body_id] *= m / old
            model.body_mass[self._body_id] = m
            mujoco.mj_setConst(model, self._sim.data)
        self._mass, self._density = m, None

    def _volume(self) -> float:
        d = self._shape_dimensions()
        if self._shape == "cuboid":
            return float(np.prod(d))
        if self._shape == "sphere":
            return float(4.0 / 3.0 * np.pi * np.prod(d) if d.size == 3 else 4.0 / 3.0 * np.pi * d[0] ** 3)
        r, h = d
        base = np.pi * r * r * h
        if self._shape == "capsule":
            return float(base + 4.0 / 3.0 * np.pi * r**3)
        return float(base / 3.0 if self._shape == "cone" else base)

    def set_default_state(self, position=None, orientation=None, linear_velocity=None, angular_velocity=None) -> None:
        """State restored by `post_reset()`; None keeps a part."""
        super().set_default_state(position, orientation)
        if linear_velocity is not None:
            self._default_state.linear_velocity = V.vec(linear_velocity, 3, "linear_velocity")
        if angular_velocity is not None:
            self._default_state.angular_velocity = V.vec(angular_velocity, 3, "angular_velocity")

    def get_default_state(self) -> DynamicState:
        s = self._default_state
        return DynamicState(
            s.position.copy(), s.orientation.copy(), s.linear_velocity.copy(), s.angular_velocity.copy()
        )

    def post_reset(self) -> None:
        super().post_reset()
        self.set_linear_velocity(self._default_state.linear_velocity)
        self.set_angular_velocity(self._default_state.angular_velocity)


def _make_shape_classes():
    """Create the 15 Visual/Fixed/Dynamic x Cuboid/Sphere/Cylinder/Capsule/Cone classes."""
    out = {}
    shapes = {"Cuboid": (_Cuboid, "cube"), "Sphere": (_Sphere, "sphere"), "Cylinder": (_Cylinder, "cylinder"),
              "Capsule": (_Capsule, "capsule"), "Cone": (_Cone, "cone")}
    for family in ("Visual", "Fixed", "Dynamic"):
        for shape_name, (mixin, short) in shapes.items():
            out[family + shape_name] = _shape_class(family, shape_name, mixin, short)
    return out


def _shape_class(family: str, shape_name: str, mixin, short: str):
    dynamic = family == "Dynamic"
    bases = (mixin, _DynamicMixin, RigidPrim, GeometryPrim) if dynamic else (mixin, GeometryPrim)
    shape_args = "size" if shape_name == "Cuboid" else ("radius" if shape_name == "Sphere" else "radius, height")

    def __init__(
        self,
        prim_path: str,
        name: str | None = None,
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
        color=None,
        size: float | None = None,
        radius: float | None = None,
        height: float | None = None,
        visual_material=None,
        physics_material: PhysicsMaterial | None = None,
        mass: float | None = None,
        density: float | None = None,
        linear_velocity=None,
        angular_velocity=None,
    ):
        if name is None:
            name = f"{family.lower()}_{short}"
        given = {"size": size, "radius": radius, "height": height}
        allowed = {"Cuboid": {"size"}, "Sphere": {"radius"}}.get(shape_name, {"radius", "height"})
        extra = [k for k, v in given.items() if v is not None and k not in allowed]
        if extra:
            raise InvalidInputError(f"{family}{shape_name} takes {shape_args}, not {', '.join(extra)}")
        if not dynamic and any(v is not None for v in (mass, density, linear_velocity, angular_velocity)):
            raise InvalidInputError(f"{family}{shape_name} is not a rigid body: mass, density and velocities "
                                    f"belong to Dynamic{shape_name}")
        if family == "Visual" and physics_material is not None:
            raise InvalidInputError(f"Visual{shape_name} has no collision; a physics material needs Fixed/Dynamic")
        self._scale = V.scale3(scale) if scale is not None else np.ones(3)
        self.prim_path = prim_path
        if shape_name == "Cuboid":
            self._init_shape(size)
        elif shape_name == "Sphere":
            self._init_shape(radius)
        else:
            self._init_shape(radius, height)
        GeometryPrim.__init__(self, prim_path, name, position, translation, orientation, scale, visible, color,
                              physics_material, visual_material)
        if dynamic:
            self._init_dynamic(mass, density, linear_velocity, angular_velocity)

    doc = {
        "Visual": "drawn only (no collision); moved by set_world_pose",
        "Fixed": "a static collider; moved by set_world_pose, never by physics",
        "Dynamic": "a rigid body (free joint); mass defaults to 0.02 kg unless mass or density is given",
    }[family]
    __init__.__doc__ = (
        f"""A {shape_name.lower()}: {doc}.

        Args:
            prim_path: e.g. "/World/{short}".
            name: unique scene name (default "{family.lower()}_{short}").
            position / translation: (3,) [m] (the same here; not both).
            orientation: (4,) (w, x, y, z).
            scale: (3,) or scalar.
            visible: drawn or not.
            color: RGB in [0, 1].
            {shape_args}: [m] (default 1.0){'; real edge lengths are size * scale' if shape_name == 'Cuboid' else ''}.
            physics_material: friction (Fixed/Dynamic).
            mass, density: Dynamic only [kg], [kg/m^3].
            linear_velocity, angular_velocity: Dynamic only, initial and default [m/s], [rad/s].
        """
    )
    cls = type(f"{family}{shape_name}", bases, {"__init__": __init__, "_family": family.lower(),
                                                "__doc__": __init__.__doc__, "__module__": __name__})
    return cls


_classes = _make_shape_classes()
VisualCuboid = _classes["VisualCuboid"]
VisualSphere = _classes["VisualSphere"]
VisualCylinder = _classes["VisualCylinder"]
VisualCapsule = _classes["VisualCapsule"]
VisualCone = _classes["VisualCone"]
FixedCuboid = _classes["FixedCuboid"]
FixedSphere = _classes["FixedSphere"]
FixedCylinder = _classes["FixedCylinder"]
FixedCapsule = _classes["FixedCapsule"]
FixedCone = _classes["FixedCone"]
DynamicCuboid = _classes["DynamicCuboid"]
DynamicSphere = _classes["DynamicSphere"]
DynamicCylinder = _classes["DynamicCylinder"]
DynamicCapsule = _classes["DynamicCapsule"]
DynamicCone = _classes["DynamicCone"]


class GroundPlane(GeometryPrim):
    """An infinite collision plane, its normal along +z (Isaac's `GroundPlane`).

    Args:
        prim_path: e.g. "/World/groundPlane".
        name: scene name (default "ground_plane").
        size: half-extent of the drawn checkerboard [m] (collision is infinite).
        z_position: height of the plane [m].
        color: RGB of the checkerboard's dark squares.
        physics_material / static_friction / dynamic_friction / restitution: surface
            (friction as explained in the module docstring; restitution not simulated).
    """

    _family = "ground"
    _shape = "plane"

    def __init__(
        self,
        prim_path: str,
        name: str = "ground_plane",
        size: float | None = None,
        z_position: float = 0.0,
        scale=None,
        visible: bool = True,
        color=None,
        physics_material: PhysicsMaterial | None = None,
        static_friction: float = 0.5,
        dynamic_friction: float = 0.5,
        restitution: float = 0.8,
    ):
        self._size = V.positive(size if size is not None else 5.0, "size")
        if physics_material is None:
            physics_material = PhysicsMaterial(
                prim_path + "/physicsMaterial", name + "_material", static_friction, dynamic_friction, restitution
            )
        z = float(z_position)
        if not np.isfinite(z):
            raise InvalidInputError(f"z_position must be finite; got {z_position}")
        super().__init__(prim_path, name, [0.0, 0.0, z], None, None, scale, visible,
                         color if color is not None else [0.2, 0.3, 0.4], physics_material)

    def _geom_type_size(self):
        return mujoco.mjtGeom.mjGEOM_PLANE, [self._size, self._size, 0.05]

    def _build(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        tex_name = self.prim_path + "/texture"
        c = self._color
        spec.add_texture(name=tex_name, type=mujoco.mjtTexture.mjTEXTURE_2D, builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
                         rgb1=c.tolist(), rgb2=np.clip(c + 0.1, 0, 1).tolist(), width=300, height=300)
        mat = spec.add_material(name=self.prim_path + "/material", texrepeat=[5, 5], texuniform=True, reflectance=0.1)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex_name
        body = super()._build(spec)
        geom = body.first_geom()
        geom.material = self.prim_path + "/material"
        geom.rgba = [1.0, 1.0, 1.0, 1.0 if self._visible else 0.0]
        return body

    def _shape_dimensions(self) -> np.ndarray:
        return np.zeros(0)
