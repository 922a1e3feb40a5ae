"""The collision checker's sphere covers in a viser scene, on demand.

One batched-mesh node `/collision_spheres` holds every ball of the robot's (and attached
objects') sphere covers (`CollisionChecker.spheres(q)`): one icosphere instance per ball,
scaled by its radius, translucent over the robot's meshes.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import trimesh

#: Sphere colour [0-255] and opacity.
SPHERE_COLOR = (255, 60, 60)
SPHERE_OPACITY = 0.35


class SphereDrawing:
    """The robot's collision spheres, updated to a configuration.

    Args:
        scene: a viser `SceneApi`.
        spheres: `q (dof,) -> (centres (S, 3) [m], radii (S,) [m], owner names (S,))`,
            e.g. `CollisionChecker.spheres`.
        name: scene-tree name of the node.
    """

    def __init__(self, scene: Any, spheres: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, list[str]]],
                 name: str = "/collision_spheres"):
        self._scene = scene
        self._spheres = spheres
        self.name = name
        self.handle: Any = None
        self._unit = trimesh.creation.icosphere(subdivisions=2, radius=1.0)

    @property
    def visible(self) -> bool:
        """Whether the spheres are shown."""
        return self.handle is not None and bool(self.handle.visible)

    def show(self, q: np.ndarray) -> None:
        """Show the spheres at configuration q (dof,) [rad] (re-created: the count may change)."""
        centres, radii, _ = self._spheres(q)
        if self.handle is not None:
            self.handle.remove()
        n = len(radii)
        self.handle = self._scene.add_batched_meshes_simple(
            self.name, self._unit.vertices, self._unit.faces,
            batched_wxyzs=np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)), batched_positions=centres,
            batched_scales=np.asarray(radii, dtype=float), batched_colors=SPHERE_COLOR, opacity=SPHERE_OPACITY,
            cast_shadow=False, receive_shadow=False)

    def hide(self) -> None:
        """Remove the spheres from the scene."""
        if self.handle is not None:
            self.handle.remove()
            self.handle = None

    def update(self, q: np.ndarray) -> None:
        """Move the shown spheres to configuration q (dof,); nothing when hidden."""
        if self.handle is None:
            return
        centres, radii, _ = self._spheres(q)
        if len(radii) != len(self.handle.batched_positions):
            self.show(q)
            return
        self.handle.batched_positions = np.asarray(centres, dtype=np.float32)
