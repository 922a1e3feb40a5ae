"""`GeometryPrim` (a prim with one MuJoCo geom, base of the shapes) and `PhysicsMaterial`.

Physics materials: MuJoCo has one sliding friction per geom, so a material's dynamic
friction is used (static friction only if dynamic is missing); a collider without a
material has PhysX's default friction 0.5. Two surfaces combine their frictions by their
materials' combine modes, "average" by default, as PhysX
(`manip.sim.scenes.contact_model`). Restitution is not modelled (MuJoCo contacts are
inelastic); it is kept for reference only.
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.materials.visual_material import PreviewSurface, VisualMaterial, rgb, unique_material_path
from manip.sim.prims.xform_prim import XFormPrim
from manip.sim.scenes.contact_model import PHYSX_DEFAULT_FRICTION, check_combine_mode, switch_pairs
from manip.sim.scenes.stage import SimHandle, SimulationError
from manip.sim.utils.not_supported import declare as declare_not_supported
from manip.validation import non_negative

#: Whether each family's geoms collide ("ground" is the GroundPlane's).
_FAMILY_COLLIDES = {"visual": False, "fixed": True, "dynamic": True, "ground": True}


class PhysicsMaterial:
    """Friction/restitution of a surface (Isaac's `PhysicsMaterial`).

    Args:
        prim_path: path of the material (informative only).
        name: its name.
        static_friction: static friction coefficient (used if dynamic is None).
        dynamic_friction: sliding friction coefficient (what MuJoCo uses).
        restitution: kept for reference, not simulated.
    """

    prim_path: str
    name: str

    def __init__(
        self,
        prim_path: str = "/World/Physics_Materials/material",
        name: str = "physics_material",
        static_friction: float | None = None,
        dynamic_friction: float | None = None,
        restitution: float | None = None,
        *,
        friction_combine_mode: str = "average",
        restitution_combine_mode: str = "average",
    ):
        self.prim_path = prim_path
        self.name = name
        self._static = None if static_friction is None else non_negative(static_friction, "static_friction")
        self._dynamic = None if dynamic_friction is None else non_negative(dynamic_friction, "dynamic_friction")
        self._restitution = restitution
        self._friction_mode = check_combine_mode(friction_combine_mode)
        self._restitution_mode = check_combine_mode(restitution_combine_mode, "restitution_combine_mode")

    def set_static_friction(self, friction: float) -> None:
        """Static friction (used by MuJoCo only without a dynamic one); geoms built from the next reset."""
        self._static = non_negative(friction, "static_friction")

    def set_dynamic_friction(self, friction: float) -> None:
        """Sliding friction; objects using the material get it at their next reset."""
        self._dynamic = non_negative(friction, "dynamic_friction")

    def set_restitution(self, restitution: float) -> None:
        """Kept for reference (restitution is not simulated)."""
        self._restitution = float(restitution)

    def set_friction_combine_mode(self, mode: str) -> None:
        """How this material's friction combines with another's: "average" (PhysX's default),
        "min", "multiply" or "max"; of two modes the later in that list applies."""
        self._friction_mode = check_combine_mode(mode)

    def get_friction_combine_mode(self) -> str:
        return self._friction_mode

    def set_restitution_combine_mode(self, mode: str) -> None:
        """Kept for reference (restitution is not simulated)."""
        self._restitution_mode = check_combine_mode(mode, "restitution_combine_mode")

    def get_restitution_combine_mode(self) -> str:
        return self._restitution_mode

    def get_static_friction(self) -> float | None:
        return self._static

    def get_dynamic_friction(self) -> float | None:
        return self._dynamic

    def get_restitution(self) -> float | None:
        return self._restitution

    def mujoco_friction(self) -> float | None:
        """The sliding friction MuJoCo uses: dynamic friction, else static, else None."""
        return self._dynamic if self._dynamic is not None else self._static


#: USD's collision approximation tokens (`UsdPhysics.MeshCollisionAPI`).
COLLISION_APPROXIMATIONS = ("none", "convexHull", "convexDecomposition", "meshSimplification", "boundingSphere",
                            "boundingCube", "sdf", "sphereFill")


class GeometryPrim(XFormPrim):
    """A prim with one geometry (base of the shape classes)."""

    _mounts_on_links = False  # a body (a robot's link) or a shape of its own, never a frame on a link

    _family = "visual"
    shape_kind = "cuboid"  # the geometry type, as the planner names it

    def __init__(
        self,
        prim_path: str,
        name: str | None = None,
        position=None,
        translation=None,
        orientation=None,
        scale=None,
        visible: bool | None = None,
        *,
        reset_xform_properties: bool = True,
        collision: bool = False,
        track_contact_forces: bool = False,
        prepare_contact_sensor: bool = False,
        disable_stablization: bool = True,
        contact_filter_prim_paths_expr=None,
        color=None,
        physics_material: PhysicsMaterial | None = None,
        visual_material=None,
    ):
        """Isaac's arguments; `collision=True` enables the geometry's contacts (as Isaac applies
        its collision API; False leaves them as they are). `track_contact_forces`,
        `prepare_contact_sensor`, `disable_stablization` and `contact_filter_prim_paths_expr`
        are PhysX settings accepted for Isaac's signature: MuJoCo always computes contacts
        (read them with `RigidPrimView(..., contact_filter_prim_paths_expr=...)`)."""
        for flag, value in (("collision", collision), ("track_contact_forces", track_contact_forces),
                            ("prepare_contact_sensor", prepare_contact_sensor),
                            ("disable_stablization", disable_stablization)):
            if not isinstance(value, (bool, np.bool_)):
                raise InvalidInputError(f"{flag} must be True or False; got {value!r}")
        self._collision: bool | None = None  # set_collision_enabled's choice (None: the family's default)
        self._color = rgb(color) if color is not None else np.array([0.5, 0.5, 0.5])
        self._physics_material = physics_material
        self._geom_id = -1
        self._opacity = 1.0
        self._visual_material: VisualMaterial | None = None
        if visual_material is not None and not isinstance(visual_material, VisualMaterial):
            raise InvalidInputError(f"visual_material must be a VisualMaterial (PreviewSurface, OmniPBR, OmniGlass); "
                                    f"got {type(visual_material).__name__}")
        super().__init__(prim_path, name, position, translation, orientation, scale, visible)
        if collision:
            self.set_collision_enabled(True)
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_color"):
            self._color = self._wrapped_object.get_color()
            self._visual_material = self._wrapped_object.get_applied_visual_material()
        elif visual_material is not None:
            self.apply_visual_material(visual_material)
        elif self._family != "ground":
            # Isaac gives each shape made without a material its own PreviewSurface with its colour.
            self.apply_visual_material(PreviewSurface(unique_material_path(), color=self._color))

    # shape parameters: overridden
    def _geom_type_size(self) -> tuple[int, list[float]]:
        raise NotImplementedError

    def add_to_spec(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        dynamic = self._family == "dynamic"
        body = spec.worldbody.add_body(
            name=self.prim_path, pos=self._pose[0].tolist(), quat=self._pose[1].tolist(), mocap=not dynamic
        )
        if dynamic:
            body.add_freejoint(name=self.prim_path + "/root_joint")
        gtype, size = self._geom_type_size()
        collides = self._collides()
        kwargs = dict(
            name=self.prim_path + "/geom",
            type=gtype,
            size=size,
            rgba=[*self._color.tolist(), self._opacity if self._visible else 0.0],
            contype=1 if collides else 0,
            conaffinity=1 if collides else 0,
            group=0 if collides else 2,
        )
        if gtype == mujoco.mjtGeom.mjGEOM_MESH:
            kwargs["meshname"] = self._build_mesh(spec)
        if collides:  # PhysX's default material without one (MuJoCo's default is 1.0)
            f = self._physics_material.mujoco_friction() if self._physics_material is not None else None
            kwargs["friction"] = [f if f is not None else PHYSX_DEFAULT_FRICTION, 0.005, 0.0001]
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

    def bind_simulation(self, sim: SimHandle) -> None:
        super().bind_simulation(sim)
        self._geom_id = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_GEOM, self.prim_path + "/geom")

    def _apply_visibility(self) -> None:
        if self._sim is not None and self._geom_id >= 0:
            self._sim.model.geom_rgba[self._geom_id, 3] = self._opacity if self._visible else 0.0

    def get_color(self) -> np.ndarray:
        """The colour drawn (3,), RGB in [0, 1]."""
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_color"):
            return self._wrapped_object.get_color()
        return self._color.copy()

    def set_color(self, color) -> None:
        """Set the colour, RGB >= 0 (1 full; above 1 drawn saturated, as USD's): of the applied visual
        material if there is one (every object sharing it changes, as editing the material in
        Isaac), else of this object."""
        c = rgb(color)
        if self._visual_material is not None:
            self._visual_material.set_color(c)
        else:
            self.show_color(c)

    def show_color(self, color, opacity: float = 1.0) -> None:
        """Draw this object in `color` (3,) RGB with `opacity` in [0, 1] (what a bound visual
        material calls; `set_color` is the user's call)."""
        self._color = np.array(color, dtype=float)
        self._opacity = float(opacity)
        if self._wrapped_object is not None:
            self._wrapped_object.show_color(color, opacity)
        if self._sim is not None and self._geom_id >= 0:
            self._sim.model.geom_rgba[self._geom_id, :3] = self._color
            self._apply_visibility()

    # ------------------------------------------------------------------ visual materials
    def apply_visual_material(self, visual_material: VisualMaterial, weaker_than_descendants: bool = False) -> None:
        """Draw this object with `visual_material` (a PreviewSurface, OmniPBR, OmniGlass);
        its colour applies at once. `weaker_than_descendants` is accepted (no child prims here).

        Raises:
            InvalidInputError: not a VisualMaterial.
        """
        if not isinstance(visual_material, VisualMaterial):
            raise InvalidInputError(f"apply_visual_material needs a VisualMaterial (PreviewSurface, OmniPBR, "
                                    f"OmniGlass); got {type(visual_material).__name__}")
        if self._wrapped_object is not None:
            self._wrapped_object.apply_visual_material(visual_material, weaker_than_descendants)
            self._visual_material = visual_material
            return
        if self._visual_material is not None:
            self._visual_material.unbind(self)
        self._visual_material = visual_material
        visual_material.bind(self)

    def get_applied_visual_material(self) -> VisualMaterial | None:
        """The visual material drawing this object (a shape's own PreviewSurface unless another
        was applied)."""
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_applied_visual_material"):
            return self._wrapped_object.get_applied_visual_material()
        return self._visual_material

    def is_visual_material_applied(self) -> bool:
        return self._visual_material is not None

    def get_applied_physics_material(self) -> PhysicsMaterial | None:
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_applied_physics_material"):
            return self._wrapped_object.get_applied_physics_material()
        return self._physics_material

    def apply_physics_material(self, physics_material: PhysicsMaterial, weaker_than_descendants: bool = False) -> None:
        """Use this material's friction: at once against surfaces it meets with MuJoCo's own
        contacts; combined with the other surface's by the combine modes
        (`manip.sim.scenes.contact_model`) from the next `World.reset()`, which rebuilds the
        contact pairs."""
        if not isinstance(physics_material, PhysicsMaterial):
            raise InvalidInputError(f"apply_physics_material needs a PhysicsMaterial; got "
                                    f"{type(physics_material).__name__}")
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "apply_physics_material"):
            self._wrapped_object.apply_physics_material(physics_material, weaker_than_descendants)
            self._physics_material = physics_material
            return
        self._own_geometry("apply_physics_material")
        self._physics_material = physics_material
        f = physics_material.mujoco_friction()
        if self._sim is not None and f is not None and self._geom_id >= 0:
            self._sim.model.geom_friction[self._geom_id, 0] = f
        self._mark_changed()

    def _collides(self) -> bool:
        return _FAMILY_COLLIDES[self._family] if self._collision is None else self._collision

    def _own_geometry(self, what: str) -> None:
        """Raise unless this prim is a shape (a robot's link has the model's geoms)."""
        if self._wrapped_reference is not None:
            raise SimulationError(f"{what}: {self.prim_path!r} is a link of the model at "
                                  f"{self._wrapped_reference.prim_path!r}, whose geoms and collision settings are "
                                  "the model's; collisions can be switched for shapes (Visual/Fixed/Dynamic objects)")

    def get_collision_enabled(self) -> bool:
        """Whether the geometry makes contacts.

        Raises:
            SimulationError: a robot's link (not a shape).
        """
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "get_collision_enabled"):
            return self._wrapped_object.get_collision_enabled()
        self._own_geometry("get_collision_enabled")
        if self._sim is not None and self._geom_id >= 0:
            m = self._sim.model
            return bool(m.geom_contype[self._geom_id] or m.geom_conaffinity[self._geom_id])
        return self._collides()

    def set_collision_enabled(self, enabled: bool) -> None:
        """Enable/disable contacts of the geometry: at once if compiled, and at every later
        compile (before the first `World.reset()` too).

        Raises:
            InvalidInputError: `enabled` not a bool.
            SimulationError: a robot's link (not a shape).
        """
        if not isinstance(enabled, (bool, np.bool_)):
            raise InvalidInputError(f"set_collision_enabled needs True or False; got {enabled!r}")
        if self._wrapped_object is not None and hasattr(self._wrapped_object, "set_collision_enabled"):
            self._wrapped_object.set_collision_enabled(enabled)
            return
        self._own_geometry("set_collision_enabled")
        self._collision = bool(enabled)
        if self._sim is not None and self._geom_id >= 0:
            v = 1 if enabled else 0
            self._sim.model.geom_contype[self._geom_id] = v
            self._sim.model.geom_conaffinity[self._geom_id] = v
            switch_pairs(self._sim.model, self._geom_id)  # the friction pairs ignore contype/conaffinity

    def set_collision_approximation(self, approximation_type: str) -> None:
        """Isaac's mesh collision approximation token ("none", "convexHull", ...), kept for the getter:
        the shapes here are primitives, collided exactly whatever the token (as PhysX's Cube, Sphere, ...).

        Raises:
            InvalidInputError: not one of USD's tokens (`COLLISION_APPROXIMATIONS`).
        """
        if approximation_type not in COLLISION_APPROXIMATIONS:
            raise InvalidInputError(f"collision approximation must be one of {list(COLLISION_APPROXIMATIONS)}; "
                                    f"got {approximation_type!r}")
        target = self._wrapped_object if isinstance(self._wrapped_object, GeometryPrim) else self
        target._approximation = approximation_type

    def get_collision_approximation(self) -> str:
        """The token set by `set_collision_approximation` (default "none": the exact shape)."""
        target = self._wrapped_object if isinstance(self._wrapped_object, GeometryPrim) else self
        return getattr(target, "_approximation", "none")

    @property
    def geom_id(self) -> int:
        """Index of the MuJoCo geom (-1 before the World compiles)."""
        return self._geom_id

    def shape_dimensions(self) -> np.ndarray:
        """Dimensions in the `CollisionObject` convention (see Scene.get_collision_objects)."""
        raise NotImplementedError


declare_not_supported(GeometryPrim)
