"""Materials (Isaac's `omni.isaac.core.materials`): the visual materials here; the physics
material lives with the geometry it is applied to (`manip.sim.prims.geometry_prim`)."""

from __future__ import annotations

from manip.sim.materials.visual_material import OmniGlass, OmniPBR, PreviewSurface, VisualMaterial

__all__ = ["OmniGlass", "OmniPBR", "PreviewSurface", "VisualMaterial"]
