"""`GeometryPrimView`: Isaac's batched view of shapes (`omni.isaac.core.prims.GeometryPrimView`,
Isaac 5's `isaacsim.core.prims.GeometryPrim` called as a view).

An `XFormPrimView` (poses, scales, visibilities) whose prims are shapes (`GeometryPrim`s:
Visual/Fixed/Dynamic objects), with their collision switches (`enable_collision`,
`disable_collision`, `is_collision_enabled`), collision approximations and physics materials
in batch, each row the single prim's own call. PhysX's contact and rest offsets and torsional
patch radii do not exist in MuJoCo (they raise, as on `GeometryPrim`); contact forces are read
with `RigidPrimView(..., contact_filter_prim_paths_expr=...)`.
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.prims import isaac5_views
from manip.sim.prims.geometry_prim import GeometryPrim
from manip.sim.prims.views import XFormPrimView
from manip.sim.scenes.stage import SimulationError, get_current_stage
from manip.sim.utils.not_supported import declare as declare_not_supported


class GeometryPrimView(XFormPrimView):
    """Shapes matching `prim_paths_expr` (regular expressions per path segment).

    Args:
        prim_paths_expr: e.g. "/World/Cube_.*".
        name: scene name.
        positions, translations, orientations: (N, 3), (N, 4) poses applied at the first binding.
        collisions: (N,) bools: True enables a shape's contacts at the first binding (as Isaac
            applies its collision API), False leaves it as it is.
        reset_xform_properties, track_contact_forces, prepare_contact_sensors,
        disable_stablization, contact_filter_prim_paths_expr: Isaac's, accepted (see the module
            docstring for contact forces).
    """

    def __init__(self, prim_paths_expr: str, name: str = "geometry_prim_view", positions=None, translations=None,
                 orientations=None, scales=None, visibilities=None, reset_xform_properties: bool = True,
                 collisions=None, track_contact_forces: bool = False, prepare_contact_sensors: bool = False,
                 disable_stablization: bool = True, contact_filter_prim_paths_expr=None):
        super().__init__(prim_paths_expr, name, positions, translations, orientations, scales, visibilities,
                         reset_xform_properties)
        self._collisions = None if collisions is None else np.asarray(collisions, dtype=bool).ravel()

    def bind_simulation(self, sim) -> None:
        super().bind_simulation(sim)
        if self._collisions is not None:
            if self._collisions.size != self.count:
                raise InvalidInputError(f"{self.name}: collisions has {self._collisions.size} entries for "
                                        f"{self.count} prims {self.prim_paths}")
            for prim, on in zip(self._shapes(None), self._collisions):
                if on:
                    prim.set_collision_enabled(True)
            self._collisions = None

    def _shapes(self, indices) -> list[GeometryPrim]:
        """The shape objects of `indices` (all by default)."""
        self._need()
        stage = get_current_stage()
        out = []
        for i in self._idx(indices):
            prim = stage.get_prim(self._paths[i])
            if not isinstance(prim, GeometryPrim):
                raise SimulationError(f"{self.name}: {self._paths[i]!r} is not a shape (a robot's link has the "
                                      "model's geoms): collision settings are per shape (Visual/Fixed/Dynamic objects)")
            out.append(prim)
        return out

    def _per_row(self, values, n: int, what: str) -> list:
        rows = list(values) if isinstance(values, (list, tuple, np.ndarray)) else [values] * n
        if len(rows) != n:
            raise InvalidInputError(f"{what}: {len(rows)} values for {n} prims")
        return rows

    # ------------------------------------------------------------------ collisions
    def is_collision_enabled(self, indices=None) -> np.ndarray:
        """(K,) bool: whether each shape makes contacts."""
        return np.array([p.get_collision_enabled() for p in self._shapes(indices)], dtype=bool)

    def enable_collision(self, indices=None) -> None:
        """Switch the shapes' contacts on (at once and at every later compile)."""
        for p in self._shapes(indices):
            p.set_collision_enabled(True)

    def disable_collision(self, indices=None) -> None:
        """Switch the shapes' contacts off."""
        for p in self._shapes(indices):
            p.set_collision_enabled(False)

    def apply_collision_apis(self, indices=None) -> None:
        """Isaac applies the collision APIs; here every shape has them (nothing to do)."""
        self._shapes(indices)

    def set_collision_approximations(self, approximation_types, indices=None) -> None:
        """Each shape's collision approximation token (see `GeometryPrim.set_collision_approximation`)."""
        shapes = self._shapes(indices)
        for p, token in zip(shapes, self._per_row(approximation_types, len(shapes), "approximation_types")):
            p.set_collision_approximation(token)

    def get_collision_approximations(self, indices=None) -> list[str]:
        """Each shape's collision approximation token."""
        return [p.get_collision_approximation() for p in self._shapes(indices)]

    # ------------------------------------------------------------------ materials
    def apply_physics_materials(self, physics_materials, weaker_than_descendants=None, indices=None) -> None:
        """One material for every shape, or a list of one per shape (`indices`)."""
        shapes = self._shapes(indices)
        materials = self._per_row(physics_materials, len(shapes), "physics_materials")
        weaker = self._per_row(False if weaker_than_descendants is None else weaker_than_descendants, len(shapes),
                               "weaker_than_descendants")
        for p, material, w in zip(shapes, materials, weaker):
            p.apply_physics_material(material, bool(w))

    def get_applied_physics_materials(self, indices=None) -> list:
        """Each shape's physics material (None where none is applied)."""
        return [p.get_applied_physics_material() for p in self._shapes(indices)]


declare_not_supported(GeometryPrimView)
isaac5_views.register(GeometryPrim, GeometryPrimView)  # Isaac 5's GeometryPrim(prim_paths_expr=...)

__all__ = ["GeometryPrimView"]
