"""The shape objects: {Visual, Fixed, Dynamic} x {Cuboid, Sphere, Cylinder, Capsule, Cone}.

Families, as in Isaac Sim:
- `Visual*`: drawn, no collision, moved only by `set_world_pose` (a MuJoCo mocap body).
- `Fixed*`: collides, never moves by physics (a mocap body: static for the solver).
- `Dynamic*`: a rigid body with a free joint, mass (default 0.02 kg) or density.

A concrete class combines a shape mixin (`_Cuboid`, ...: dimensions, MuJoCo geom, volume)
with a family base (`_VisualShape`, `_FixedShape`, `_DynamicShape`); all share the
constructor of `_ShapePrim`.
"""

from __future__ import annotations

import logging

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.prims.geometry_prim import GeometryPrim, PhysicsMaterial
from manip.sim.prims.rigid_prim import RigidPrim
from manip.sim.utils.types import DynamicState
from manip.validation import positive, scale3
from manip.sim.utils.bounds import bounded_vec, check_object_size

logger = logging.getLogger(__name__)


def _length(value, what: str) -> float:
    """A shape dimension [m]: positive; 1.0 when None."""
    return positive(value if value is not None else 1.0, what, "m")


# ---------------------------------------------------------------------------- shape mixins
class _Cuboid:
    """Edge `size` [m] before scaling: the edges are size * scale (3,)."""

    shape_kind = "cuboid"  # the geometry type, as the planner names it
    _shape_params = ("size",)

    def _init_shape(self, size, radius, height) -> None:
        self._size = _length(size, "size")

    def get_size(self) -> float:
        """Edge length before scaling [m] (real edge lengths = size * scale)."""
        return self._size

    def set_size(self, size: float) -> None:
        """Change the edge length [m]; takes effect at the next `World.reset()`."""
        self._set_dimension("_size", positive(size, "size", "m"))

    def _geom_type_size(self):
        return mujoco.mjtGeom.mjGEOM_BOX, (0.5 * self._size * self._scale).tolist()

    def shape_dimensions(self) -> np.ndarray:
        return self._size * self._scale

    def _volume(self) -> float:
        return float(np.prod(self.shape_dimensions()))


class _Radius:
    """The `radius` [m] of round shapes."""

    def get_radius(self) -> float:
        return self._radius

    def set_radius(self, radius: float) -> None:
        """Change the radius [m]; takes effect at the next `World.reset()`."""
        self._set_dimension("_radius", positive(radius, "radius", "m"))


class _Sphere(_Radius):
    """Radius times scale: a sphere, or an ellipsoid if the scale is not uniform."""

    shape_kind = "sphere"  # the geometry type, as the planner names it
    _shape_params = ("radius",)

    def _init_shape(self, size, radius, height) -> None:
        self._radius = _length(radius, "radius")

    def _geom_type_size(self):
        r = self._radius * self._scale
        if np.allclose(r, r[0]):
            return mujoco.mjtGeom.mjGEOM_SPHERE, [float(r[0]), 0.0, 0.0]
        return mujoco.mjtGeom.mjGEOM_ELLIPSOID, r.tolist()

    def shape_dimensions(self) -> np.ndarray:
        r = self._radius * self._scale
        return np.array([r[0]]) if np.allclose(r, r[0]) else r

    def _volume(self) -> float:
        d = self.shape_dimensions()
        return float(4.0 / 3.0 * np.pi * np.prod(d) if d.size == 3 else 4.0 / 3.0 * np.pi * d[0] ** 3)


class _RadiusHeight(_Radius):
    """`radius` [m] (times the x scale) and `height` [m] (times the z scale), axis along z."""

    _shape_params = ("radius", "height")

    def _init_shape(self, size, radius, height) -> None:
        self._radius = _length(radius, "radius")
        self._height = _length(height, "height")
        if not np.isclose(self._scale[0], self._scale[1]):
            logger.warning("%s: x and y scales differ; the radius uses the x scale", self.prim_path)

    def get_height(self) -> float:
        return self._height

    def set_height(self, height: float) -> None:
        """Change the height [m]; takes effect at the next `World.reset()`."""
        self._set_dimension("_height", positive(height, "height", "m"))

    def _rh(self) -> tuple[float, float]:
        return self._radius * self._scale[0], self._height * self._scale[2]

    def shape_dimensions(self) -> np.ndarray:
        return np.array(self._rh())

    def _cylinder_volume(self) -> float:
        r, h = self.shape_dimensions()
        return np.pi * r * r * h


class _Cylinder(_RadiusHeight):
    shape_kind = "cylinder"  # the geometry type, as the planner names it

    def _geom_type_size(self):
        r, h = self._rh()
        return mujoco.mjtGeom.mjGEOM_CYLINDER, [r, 0.5 * h, 0.0]

    def _volume(self) -> float:
        return float(self._cylinder_volume())


class _Capsule(_RadiusHeight):
    """Height is the length of the cylindrical part (as in USD); the total length is height + 2 radius."""

    shape_kind = "capsule"  # the geometry type, as the planner names it

    def _geom_type_size(self):
        r, h = self._rh()
        return mujoco.mjtGeom.mjGEOM_CAPSULE, [r, 0.5 * h, 0.0]

    def _volume(self) -> float:
        r = self.shape_dimensions()[0]
        return float(self._cylinder_volume() + 4.0 / 3.0 * np.pi * r**3)


class _Cone(_RadiusHeight):
    """A cone along z, centred on its prim: base disc at -height/2, apex at +height/2
    (USD's convention). MuJoCo has no cone primitive: it is a 48-sided convex mesh."""

    shape_kind = "cone"  # the geometry type, as the planner names it
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

    def _volume(self) -> float:
        return float(self._cylinder_volume() / 3.0)


# ---------------------------------------------------------------------------- families
class _ShapePrim(GeometryPrim):
    """Constructor shared by the shape classes (Isaac's argument names and order)."""

    _wraps_existing = False

    _shape_params: tuple[str, ...] = ()

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
        """Create the shape and put its prim on the stage.

        Args:
            prim_path: e.g. "/World/cube".
            name: unique scene name (default e.g. "dynamic_cube", "fixed_sphere").
            position / translation: (3,) [m] (the same here; not both).
            orientation: (4,) (w, x, y, z).
            scale: (3,) or scalar.
            visible: drawn or not.
            color: RGB in [0, 1].
            size: Cuboid edge [m] (default 1.0); real edge lengths are size * scale.
            radius, height: Sphere radius; Cylinder/Capsule/Cone radius and height [m]
                (default 1.0).
            physics_material: friction (Fixed/Dynamic).
            mass, density: Dynamic only [kg], [kg/m^3].
            linear_velocity, angular_velocity: Dynamic only, initial and default [m/s], [rad/s].

        Raises:
            InvalidInputError: a dimension of another shape, an argument of another
                family, or an invalid value.
        """
        given = {"size": size, "radius": radius, "height": height}
        extra = [k for k, v in given.items() if v is not None and k not in self._shape_params]
        if extra:
            raise InvalidInputError(f"{self._title()} takes {', '.join(self._shape_params)}, not {', '.join(extra)}")
        # Every argument is checked before the prim is put on the stage: a rejected call leaves
        # nothing behind (the same prim_path can be used again).
        self._check_family_args(physics_material, (mass, density, linear_velocity, angular_velocity))
        self._scale = scale3(scale) if scale is not None else np.ones(3)
        self.prim_path = prim_path
        self._init_shape(size, radius, height)
        self._check_size()
        body = self._check_body(mass, density, linear_velocity, angular_velocity)
        super().__init__(prim_path, name, position, translation, orientation, scale, visible, color=color,
                         physics_material=physics_material, visual_material=visual_material)
        self._init_body(*body)

    def _check_size(self) -> None:
        """Raise InvalidInputError when a dimension (scale included) exceeds MAX_OBJECT_SIZE."""
        check_object_size(self.shape_dimensions(), self._shape_params, f"{self._title()} '{self.prim_path}'")

    def _set_dimension(self, attr: str, value: float) -> None:
        """Set a dimension (`_size`, `_radius`, `_height`) [m] if the shape stays within bounds."""
        old = getattr(self, attr)
        setattr(self, attr, value)
        try:
            self._check_size()
        except InvalidInputError:
            setattr(self, attr, old)
            raise
        self._mark_changed()

    def set_local_scale(self, scale) -> None:
        """Change the scale; it takes effect at the next `World.reset()` (the model is recompiled)."""
        old = self._scale
        self._scale = scale3(scale)
        try:
            self._check_size()
        except InvalidInputError:
            self._scale = old
            raise
        self._mark_changed()

    def _title(self, family: str | None = None) -> str:
        """E.g. "DynamicCuboid" (of this shape in `family`, default its own)."""
        return (family or self._family).capitalize() + self.shape_kind.capitalize()

    def _check_family_args(self, physics_material, body_args: tuple) -> None:
        if any(v is not None for v in body_args):
            raise InvalidInputError(f"{self._title()} is not a rigid body: mass, density and velocities "
                                    f"belong to {self._title('dynamic')}")

    def _check_body(self, mass, density, linear_velocity, angular_velocity) -> tuple:
        """The rigid-body arguments, validated (Dynamic family only; checked by
        `_check_family_args` for the others)."""
        return ()

    def _init_body(self, *body) -> None:
        """Rigid-body state (Dynamic family only), from `_check_body`'s values."""


class _VisualShape(_ShapePrim):
    _family = "visual"

    def _check_family_args(self, physics_material, body_args: tuple) -> None:
        super()._check_family_args(physics_material, body_args)
        if physics_material is not None:
            raise InvalidInputError(f"{self._title()} has no collision; a physics material needs Fixed/Dynamic")


class _FixedShape(_ShapePrim):
    _family = "fixed"


class _DynamicShape(RigidPrim, _ShapePrim):
    _family = "dynamic"

    __init__ = _ShapePrim.__init__  # the shapes' constructor, not RigidPrim's (a wrapper's)

    def _check_family_args(self, physics_material, body_args: tuple) -> None:
        pass

    def _check_body(self, mass, density, linear_velocity, angular_velocity) -> tuple:
        if mass is not None and density is not None:
            raise InvalidInputError("give either mass or density, not both")
        mass = positive(mass, "mass", "kg") if mass is not None else None
        density = positive(density, "density", "kg/m^3") if density is not None else None
        if mass is None and density is None:
            mass = 0.02
        lin = bounded_vec(linear_velocity, "linear", "linear_velocity") if linear_velocity is not None else np.zeros(3)
        ang = bounded_vec(angular_velocity, "angular", "angular_velocity") if angular_velocity is not None \
            else np.zeros(3)
        return mass, density, lin, ang

    def _init_body(self, mass, density, lin, ang) -> None:
        self._mass, self._density = mass, density
        s = self._default_state
        self._default_state = DynamicState(s.position, s.orientation, lin, ang)

    def _set_mass_props(self, geom) -> None:
        if self._mass is not None:
            geom.mass = self._mass
        else:
            geom.density = self._density


# ---------------------------------------------------------------------------- the 15 classes
class VisualCuboid(_Cuboid, _VisualShape):
    """A box drawn only (no collision), moved by set_world_pose; edge `size` [m] times scale."""

    _default_name = "visual_cube"


class VisualSphere(_Sphere, _VisualShape):
    """A sphere of `radius` [m] drawn only (no collision), moved by set_world_pose."""

    _default_name = "visual_sphere"


class VisualCylinder(_Cylinder, _VisualShape):
    """A cylinder (`radius`, `height` [m], axis z) drawn only (no collision)."""

    _default_name = "visual_cylinder"


class VisualCapsule(_Capsule, _VisualShape):
    """A capsule (`radius` [m], cylindrical part `height` [m], axis z) drawn only (no collision)."""

    _default_name = "visual_capsule"


class VisualCone(_Cone, _VisualShape):
    """A cone (`radius`, `height` [m], apex +z) drawn only (no collision)."""

    _default_name = "visual_cone"


class FixedCuboid(_Cuboid, _FixedShape):
    """A static box collider, edge `size` [m] times scale; moved by set_world_pose, never by physics."""

    _default_name = "fixed_cube"


class FixedSphere(_Sphere, _FixedShape):
    """A static sphere collider of `radius` [m]; never moved by physics."""

    _default_name = "fixed_sphere"


class FixedCylinder(_Cylinder, _FixedShape):
    """A static cylinder collider (`radius`, `height` [m], axis z); never moved by physics."""

    _default_name = "fixed_cylinder"


class FixedCapsule(_Capsule, _FixedShape):
    """A static capsule collider (`radius` [m], cylindrical part `height` [m]); never moved by physics."""

    _default_name = "fixed_capsule"


class FixedCone(_Cone, _FixedShape):
    """A static cone collider (`radius`, `height` [m], apex +z); never moved by physics."""

    _default_name = "fixed_cone"


class DynamicCuboid(_Cuboid, _DynamicShape):
    """A box rigid body (free joint), edge `size` [m] times scale; 0.02 kg unless mass or density is given."""

    _default_name = "dynamic_cube"


class DynamicSphere(_Sphere, _DynamicShape):
    """A sphere rigid body of `radius` [m]; 0.02 kg unless mass or density is given."""

    _default_name = "dynamic_sphere"


class DynamicCylinder(_Cylinder, _DynamicShape):
    """A cylinder rigid body (`radius`, `height` [m]); 0.02 kg unless mass or density is given."""

    _default_name = "dynamic_cylinder"


class DynamicCapsule(_Capsule, _DynamicShape):
    """A capsule rigid body (`radius` [m], cylindrical part `height` [m]); 0.02 kg unless mass or density is given."""

    _default_name = "dynamic_capsule"


class DynamicCone(_Cone, _DynamicShape):
    """A cone rigid body (`radius`, `height` [m], apex +z); 0.02 kg unless mass or density is given."""

    _default_name = "dynamic_cone"
