"""`GroundPlane`: an infinite collision plane drawn as a checkerboard (Isaac's `GroundPlane`)."""

from __future__ import annotations

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.prims.geometry_prim import GeometryPrim, PhysicsMaterial
from manip.validation import positive


class GroundPlane(GeometryPrim):
    """An infinite collision plane, its normal along +z (Isaac's `GroundPlane`).

    Args:
        prim_path: e.g. "/World/groundPlane".
        name: scene name (default "ground_plane").
        size: half-extent of the drawn checkerboard [m] (collision is infinite).
        z_position: height of the plane [m].
        color: RGB of the checkerboard's dark squares.
        physics_material / static_friction / dynamic_friction / restitution: surface
            (friction: see `manip.sim.prims.geometry_prim`; restitution not simulated).
    """

    _family = "ground"
    shape_kind = "plane"  # the geometry type, as the planner names it

    _wraps_existing = False

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
        visual_material=None,
        static_friction: float = 0.5,
        dynamic_friction: float = 0.5,
        restitution: float = 0.8,
    ):
        self._size = positive(size if size is not None else 5.0, "size", "m")
        if physics_material is None:
            physics_material = PhysicsMaterial(
                prim_path + "/physicsMaterial", name + "_material", static_friction, dynamic_friction, restitution
            )
        z = float(z_position)
        if not np.isfinite(z):
            raise InvalidInputError(f"z_position must be finite; got {z_position}")
        super().__init__(prim_path, name, [0.0, 0.0, z], None, None, scale, visible,
                         color=color if color is not None else [0.2, 0.3, 0.4], physics_material=physics_material,
                         visual_material=visual_material)

    def _geom_type_size(self):
        return mujoco.mjtGeom.mjGEOM_PLANE, [self._size, self._size, 0.05]

    def add_to_spec(self, spec: mujoco.MjSpec) -> mujoco.MjsBody:
        tex_name = self.prim_path + "/texture"
        c = self._color
        spec.add_texture(name=tex_name, type=mujoco.mjtTexture.mjTEXTURE_2D, builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
                         rgb1=c.tolist(), rgb2=np.clip(c + 0.1, 0, 1).tolist(), width=300, height=300)
        mat = spec.add_material(name=self.prim_path + "/material", texrepeat=[5, 5], texuniform=True, reflectance=0.1)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex_name
        body = super().add_to_spec(spec)
        geom = body.first_geom()
        geom.material = self.prim_path + "/material"
        geom.rgba = [1.0, 1.0, 1.0, 1.0 if self._visible else 0.0]
        return body

    def shape_dimensions(self) -> np.ndarray:
        return np.zeros(0)
