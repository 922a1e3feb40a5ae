"""Visual materials: `VisualMaterial`, `PreviewSurface`, `OmniPBR`, `OmniGlass` (Isaac's
`omni.isaac.core.materials`).

A material holds what a surface looks like; `GeometryPrim.apply_visual_material(material)`
binds it to an object, and changing the material changes every object bound to it, as
editing a USD material does. As in Isaac, a shape created without `visual_material` gets
its own `PreviewSurface` at `/World/Looks/visual_material[_N]` carrying its `color` (0.5 grey
by default), so `cube.get_applied_visual_material().get_color()` reads the cube's colour.

What MuJoCo draws: the colour (diffuse colour, linear RGB >= 0: as in USD, a component above 1
is allowed and drawn saturated, so Isaac tutorials that pass 0-255 values draw the same saturated
colours as in Isaac) and opacity. Roughness,
metallic, textures (MDL/USD files), index of refraction and the rest are kept and returned
by their getters but not rendered (MuJoCo's renderer has no MDL shaders).
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.scenes.stage import validate_prim_path
from manip.validation import vec

#: Materials by prim path (a material lives while something refers to it).
_MATERIALS: weakref.WeakValueDictionary[str, VisualMaterial] = weakref.WeakValueDictionary()


def unique_material_path(initial: str = "/World/Looks/visual_material") -> str:
    """`initial`, or `initial_1`, `initial_2`, ... : the first prim path no material holds."""
    path, k = initial, 0
    while path in _MATERIALS:
        k += 1
        path = f"{initial}_{k}"
    return path


def rgb(color, what: str = "color") -> np.ndarray:
    """`color` as a finite, non-negative RGB (3,) (USD's linear diffuse colour; > 1 draws saturated)."""
    c = vec(color, 3, what)
    if np.any(c < 0):
        raise InvalidInputError(f"{what} must be RGB with components >= 0 (1 = full intensity); got {c}")
    return c


def _unit(value, what: str) -> float:
    v = float(value)
    if not 0.0 <= v <= 1.0:
        raise InvalidInputError(f"{what} must be in [0, 1]; got {value!r}")
    return v


class VisualMaterial:
    """A visual material bound to objects (Isaac's `VisualMaterial`, base of the shaders).

    Args:
        name: the material's name.
        prim_path: where it lives, e.g. "/World/Looks/red".
        prim, shaders_list, material: Isaac's USD handles; kept as given (no USD here).
    """

    _default_color = np.array([0.5, 0.5, 0.5])
    prim_path: str
    prim: Any
    shaders_list: list
    material: Any

    def __init__(self, name: str, prim_path: str, prim: Any = None, shaders_list: list | None = None,
                 material: Any = None):
        self.prim_path = validate_prim_path(prim_path)
        self._name = name
        self.prim = prim
        self.shaders_list = list(shaders_list) if shaders_list is not None else []
        self.material = material if material is not None else self
        self._color = self._default_color.copy()
        self._opacity = 1.0
        self._bound: weakref.WeakSet = weakref.WeakSet()
        _MATERIALS[prim_path] = self

    @property
    def name(self) -> str:
        return self._name

    # ------------------------------------------------------------------ binding (GeometryPrim calls these)
    def bind(self, geometry) -> None:
        """Draw `geometry` (a GeometryPrim) with this material from now on."""
        self._bound.add(geometry)
        geometry.show_color(self._color, self._opacity)

    def unbind(self, geometry) -> None:
        """`geometry` no longer uses this material."""
        self._bound.discard(geometry)

    def bound_prims(self) -> list:
        """The objects drawn with this material."""
        return list(self._bound)

    def _refresh(self) -> None:
        for g in list(self._bound):
            g.show_color(self._color, self._opacity)

    # ------------------------------------------------------------------ what MuJoCo draws
    def set_color(self, color) -> None:
        """Diffuse colour, RGB >= 0 (1 = full; above 1 draws saturated); every bound object is redrawn with it."""
        self._color = rgb(color)
        self._refresh()

    def get_color(self) -> np.ndarray:
        """Diffuse colour (3,), RGB as set."""
        return self._color.copy()

    def set_opacity(self, opacity: float) -> None:
        """Opacity in [0, 1] (MuJoCo's alpha)."""
        self._opacity = _unit(opacity, "opacity")
        self._refresh()

    def get_opacity(self) -> float:
        return self._opacity

    def __repr__(self) -> str:
        return f"{type(self).__name__}(prim_path={self.prim_path!r}, color={self._color.tolist()})"


class PreviewSurface(VisualMaterial):
    """USD's preview surface (Isaac's `PreviewSurface`): colour, roughness, metallic.

    Args:
        prim_path: where the material lives.
        name: its name.
        shader: Isaac's USD shader; kept as given.
        color: (3,) diffuse colour, RGB >= 0 (default 0.5 grey).
        roughness, metallic: in [0, 1] (kept, not rendered by MuJoCo).
    """

    def __init__(self, prim_path: str, name: str = "preview_surface", shader: Any = None, color=None,
                 roughness: float | None = None, metallic: float | None = None):
        super().__init__(name, prim_path, shaders_list=[shader] if shader is not None else None)
        self.shaders_list = [shader] if shader is not None else []
        if color is not None:
            self._color = rgb(color)
        self._roughness = _unit(roughness, "roughness") if roughness is not None else 0.5
        self._metallic = _unit(metallic, "metallic") if metallic is not None else 0.0

    def set_roughness(self, roughness: float) -> None:
        self._roughness = _unit(roughness, "roughness")

    def get_roughness(self) -> float:
        return self._roughness

    def set_metallic(self, metallic: float) -> None:
        self._metallic = _unit(metallic, "metallic")

    def get_metallic(self) -> float:
        return self._metallic


class OmniPBR(VisualMaterial):
    """Omniverse's PBR material (Isaac's `OmniPBR`): colour, texture and its placement,
    reflection roughness, metallic constant.

    Args:
        prim_path, name, shader: as PreviewSurface.
        texture_path: an image file (kept, not rendered: MuJoCo textures need their own asset).
        texture_scale, texture_translate: (2,) UV scale and offset.
        color: (3,) RGB >= 0.
    """

    def __init__(self, prim_path: str, name: str = "omni_pbr", shader: Any = None, texture_path: str | None = None,
                 texture_scale=None, texture_translate=None, color=None):
        super().__init__(name, prim_path, shaders_list=[shader] if shader is not None else None)
        if color is not None:
            self._color = rgb(color)
        self._texture = texture_path
        self._texture_scale = vec(texture_scale, 2, "texture_scale") if texture_scale is not None else np.ones(2)
        self._texture_translate = (vec(texture_translate, 2, "texture_translate") if texture_translate is not None
                                   else np.zeros(2))
        self._roughness = 0.5
        self._metallic = 0.0
        self._project_uvw = False

    def set_texture(self, path: str | None) -> None:
        self._texture = path

    def get_texture(self) -> str | None:
        return self._texture

    def set_texture_scale(self, x: float, y: float) -> None:
        self._texture_scale = vec([x, y], 2, "texture_scale")

    def get_texture_scale(self) -> np.ndarray:
        return self._texture_scale.copy()

    def set_texture_translate(self, x: float, y: float) -> None:
        self._texture_translate = vec([x, y], 2, "texture_translate")

    def get_texture_translate(self) -> np.ndarray:
        return self._texture_translate.copy()

    def set_project_uvw(self, flag: bool) -> None:
        self._project_uvw = bool(flag)

    def get_project_uvw(self) -> bool:
        return self._project_uvw

    def set_reflection_roughness(self, amount: float) -> None:
        self._roughness = _unit(amount, "reflection roughness")

    def get_reflection_roughness(self) -> float:
        return self._roughness

    def set_metallic_constant(self, amount: float) -> None:
        self._metallic = _unit(amount, "metallic constant")

    def get_metallic_constant(self) -> float:
        return self._metallic


class OmniGlass(VisualMaterial):
    """Omniverse's glass (Isaac's `OmniGlass`): colour, index of refraction, depth, thin
    walls. Drawn by MuJoCo as its colour at 0.3 opacity (no refraction).

    Args:
        prim_path, name, shader: as PreviewSurface.
        color: (3,) RGB in [0, 1] (default white).
        ior: index of refraction (default 1.491); depth [m] (0.001); thin_walled (False).
    """

    _default_color = np.array([1.0, 1.0, 1.0])

    def __init__(self, prim_path: str, name: str = "omni_glass", shader: Any = None, color=None,
                 ior: float | None = None, depth: float | None = None, thin_walled: bool | None = None):
        super().__init__(name, prim_path, shaders_list=[shader] if shader is not None else None)
        if color is not None:
            self._color = rgb(color)
        self._opacity = 0.3
        self._ior = float(ior) if ior is not None else 1.491
        self._depth = float(depth) if depth is not None else 0.001
        self._thin_walled = bool(thin_walled) if thin_walled is not None else False

    def set_ior(self, ior: float) -> None:
        self._ior = float(ior)

    def get_ior(self) -> float:
        return self._ior

    def set_depth(self, depth: float) -> None:
        self._depth = float(depth)

    def get_depth(self) -> float:
        return self._depth

    def set_thin_walled(self, thin_walled: bool) -> None:
        self._thin_walled = bool(thin_walled)

    def get_thin_walled(self) -> bool:
        return self._thin_walled
