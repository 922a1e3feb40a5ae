"""Isaac's stage and prim utilities that work on manip's stage (`omni.isaac.core.utils.prims`,
the rest of `...utils.stage`); those that need USD raise NotImplementedError saying why.

`create_prim` makes what manip's stage holds for a USD prim type: an "Xform" (or "Scope") is an
`XFormPrim`; a light ("DistantLight", "SphereLight", ...) is an `XFormPrim` too (its transform:
MuJoCo's headlight lights the scene, the light's attributes are not drawn); a geometry type
("Cube", "Sphere", "Cylinder", "Capsule", "Cone") is the `Visual*` shape of USD's default size
(a bare USD geometry has no collision or rigid body), its "size" / "radius" / "height"
attributes applied; a `usd_path` references that model (`add_reference_to_stage`)."""

from __future__ import annotations

import logging
from typing import Any

from manip.errors import InvalidInputError
from manip.sim.core.world import World
from manip.sim.objects.shapes import VisualCapsule, VisualCone, VisualCuboid, VisualCylinder, VisualSphere
from manip.sim.prims.views import compile_path_expression, path_matches
from manip.sim.prims.xform_prim import XFormPrim
from manip.sim.scenes.stage import (  # get_prim_at_path re-exported (a robot's link is a prim there)
    add_reference_to_stage,
    get_current_stage,
    get_prim_at_path,  # noqa: F401
)
from manip.sim.utils import not_supported
from manip.sim.utils.rotations import euler_angles_to_rot_matrix
from manip.sim.utils.semantics import add_update_semantics

logger = logging.getLogger(__name__)


def get_stage_units() -> float:
    """Metres per stage unit: always 1.0 (manip's stage is in metres)."""
    return 1.0


def is_stage_loading() -> bool:
    """False: the stage loads synchronously."""
    return False


def delete_prim(prim_path: str) -> None:
    """Delete the prim at `prim_path` and everything below it (a scene object at that path
    leaves the World's scene too); the model changes at the next `World.reset()`."""
    world = World.instance()
    if world is not None:
        for name in world.scene.get_object_names():
            obj = world.scene.get_object(name)
            if getattr(obj, "prim_path", None) == prim_path:
                world.scene.remove_object(name)
                return
    get_current_stage().remove_prim(prim_path)


def find_matching_prim_paths(prim_path_regex: str, prim_type: str | None = None) -> list[str]:
    """Prim paths of the stage (and, once compiled, the bodies of referenced models) whose
    every path segment fully matches the expression's segment (Isaac's rule, as the views').

    Raises:
        InvalidInputError: a `prim_type` (manip has no USD prim types: match by path).
    """
    if prim_type is not None:
        raise InvalidInputError(f"find_matching_prim_paths(prim_type={prim_type!r}): manip has no USD prim types; "
                                "match by path only")
    segments = compile_path_expression(prim_path_regex)
    stage = get_current_stage()
    paths = stage.prim_paths()
    if stage.sim is not None:
        m = stage.sim.model
        paths += [m.body(b).name for b in range(1, m.nbody) if m.body(b).name not in paths]
    return [p for p in paths if path_matches(segments, p)]


euler_to_rot_matrix = euler_angles_to_rot_matrix
open_stage = not_supported.function("open_stage")
save_stage = not_supported.function("save_stage")
gf_quat_to_np_array = not_supported.function("gf_quat_to_np_array")


#: USD's light types: an XFormPrim here (MuJoCo's headlight lights the scene).
LIGHT_TYPES = ("DistantLight", "SphereLight", "DomeLight", "RectLight", "DiskLight", "CylinderLight")
#: USD geometry types -> (Visual shape, USD's default dimensions, the attributes that set them).
GEOMETRY_TYPES = {
    "Cube": (VisualCuboid, {"size": 2.0}),
    "Sphere": (VisualSphere, {"radius": 1.0}),
    "Cylinder": (VisualCylinder, {"radius": 1.0, "height": 2.0}),
    "Capsule": (VisualCapsule, {"radius": 0.5, "height": 1.0}),
    "Cone": (VisualCone, {"radius": 1.0, "height": 2.0}),
}


def create_prim(prim_path: str, prim_type: str = "Xform", position=None, translation=None, orientation=None,
                scale=None, usd_path: str | None = None, semantic_label: str | None = None,
                semantic_type: str = "class", attributes: dict | None = None) -> Any:
    """Create a prim on the stage (Isaac's `create_prim`; what each type becomes: the module
    docstring) and return it (manip's object: there is no Usd.Prim).

    Args:
        prim_path: where, e.g. "/World/Light".
        prim_type: "Xform", "Scope", a light type, or a geometry type.
        position / translation: (3,) [m] (the same here: no parent transforms); orientation
            (4,) (w, x, y, z); scale (3,).
        usd_path: a model file to reference there (an Isaac asset path, MJCF or URDF).
        semantic_label, semantic_type: the prim's semantic label (`add_update_semantics`), read by
            the Camera's semantic_segmentation annotator.
        attributes: USD attributes: a geometry's "size" / "radius" / "height" [m]; a light's
            (intensity, color, ...) are not drawn.

    Raises:
        InvalidInputError: a prim already at `prim_path`, an attribute the type does not have.
        NotImplementedError: another prim type (meshes, materials, cameras: use manip.sim's classes).
    """
    prim = _create_prim(prim_path, prim_type, position, translation, orientation, scale, usd_path, dict(attributes or {}))
    if semantic_label is not None:
        add_update_semantics(prim_path, semantic_label, semantic_type)
    return prim


def _create_prim(prim_path, prim_type, position, translation, orientation, scale, usd_path, attributes) -> Any:
    existing = get_current_stage().get_prim(prim_path)
    if existing is not None:  # as Isaac's: create, never wrap
        raise InvalidInputError(f"create_prim: a prim already exists at {prim_path!r} ({type(existing).__name__})")
    if usd_path is not None:
        ref = add_reference_to_stage(usd_path, prim_path)
        if any(v is not None for v in (position, translation, orientation, scale)) or attributes:
            logger.warning("create_prim(%r, usd_path=...): place the model with its robot wrapper "
                           "(Robot(prim_path, position=...)); the pose and attributes given here are not used",
                           prim_path)
        return ref
    if prim_type in GEOMETRY_TYPES:
        cls, dims = GEOMETRY_TYPES[prim_type]
        unknown = sorted(set(attributes) - set(dims))
        if unknown:
            raise InvalidInputError(f"create_prim: a {prim_type} has the attributes {sorted(dims)}; got {unknown}")
        return cls(prim_path, position=position, translation=translation, orientation=orientation, scale=scale,
                   **{**dims, **attributes})
    if prim_type in ("Xform", "Scope") + LIGHT_TYPES:
        if prim_type in LIGHT_TYPES or attributes:
            logger.info("create_prim(%r, %r): a transform here; MuJoCo's headlight lights the scene, the "
                        "attributes %s are not drawn", prim_path, prim_type, sorted(attributes))
        return XFormPrim(prim_path, position=position, translation=translation, orientation=orientation,
                         scale=scale)
    raise NotImplementedError(
        f"create_prim(prim_type={prim_type!r}) is not available in manip.sim (no USD prims): it makes "
        f"'Xform', 'Scope', lights {LIGHT_TYPES} and geometry {tuple(GEOMETRY_TYPES)}; for others use manip.sim's "
        "classes (Camera, the Fixed/Dynamic shapes, add_reference_to_stage for models)")
