"""Isaac's `omni.isaac.core.utils.bounds` on manip's World: `create_bbox_cache`, `compute_aabb`,
`compute_combined_aabb` (tutorials place objects on a table's top or space them by their bounds).

A box is Isaac's (6,) array [min x, min y, min z, max x, max y, max z] [m] in the world frame,
tight (`manip.sim.scenes.aabb`: each geom bounded exactly in the current state), of the prim and
everything below it, as USD's `ComputeWorldBound`: an object, a robot (all its links) or a
robot's link. A shape not compiled yet is bounded from its pose and size, as Isaac bounds USD
prims before any simulation. (manip's `manip.sim.utils.bounds` is another idea: the physical
bounds of setter values.)
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.core.world import World
from manip.sim.scenes.aabb import geom_box
from manip.sim.scenes.stage import SimulationError, get_current_stage, is_prim_path_valid


class BBoxCache:
    """What `create_bbox_cache` returns: bounds are computed on demand from the current state,
    so there is nothing to cache (`Clear()` is accepted, as on USD's `UsdGeom.BBoxCache`)."""

    def __init__(self, time=None, use_extents_hint: bool = True):
        self.time = time
        self.use_extents_hint = bool(use_extents_hint)

    def Clear(self) -> None:  # USD's name
        """Nothing to clear."""


def create_bbox_cache(time=None, use_extents_hint: bool = True) -> BBoxCache:
    """A bounding-box cache for `compute_aabb` (Isaac's signature; `time` and
    `use_extents_hint` are accepted and change nothing: bounds are of the current state)."""
    return BBoxCache(time, use_extents_hint)


def compute_aabb(bbox_cache: BBoxCache | None, prim_path: str, include_children: bool = False) -> np.ndarray:
    """(6,) world box [min x, y, z, max x, y, z] [m] of the prim at `prim_path` and everything
    below it (`include_children` accepted: USD's world bound always includes the subtree).

    Raises:
        InvalidInputError: no prim at `prim_path`, or no World.
        SimulationError: a robot (or its link) before the `world.reset()` that compiles it.
    """
    if not isinstance(prim_path, str) or not is_prim_path_valid(prim_path):
        raise InvalidInputError(f"compute_aabb: no prim at {prim_path!r} (is_prim_path_valid is False)")
    world = World.instance()
    if world is None:
        raise InvalidInputError("compute_aabb needs a World (create one and add the objects first)")
    for name in world.scene.get_object_names():   # a scene object: the scene's tight box (before a reset too)
        if getattr(world.scene.get_object(name), "prim_path", None) == prim_path:
            box = world.scene.compute_object_AABB(name)
            return np.concatenate([box[0], box[1]])
    sim = world.physics_sim_view
    if sim is None:
        raise SimulationError(f"compute_aabb({prim_path!r}): a robot is bounded once compiled; call world.reset() first")
    m = sim.model
    bodies = {b for b in range(m.nbody) if m.body(b).name == prim_path or m.body(b).name.startswith(prim_path + "/")}
    geoms = [g for g in range(m.ngeom) if int(m.geom_bodyid[g]) in bodies]
    if not geoms:   # a frame (a mounted prim, a bare transform): its point
        prim = get_current_stage().get_prim(prim_path)
        if prim is None or not hasattr(prim, "get_world_pose"):
            raise SimulationError(f"compute_aabb({prim_path!r}): no geometry in the compiled world below this path; "
                                  "reset the World after adding it")
        p = np.asarray(prim.get_world_pose()[0], dtype=float)
        return np.concatenate([p, p])
    sim.ensure_kinematics()
    boxes = np.array([geom_box(m, sim.data, g) for g in geoms])
    return np.concatenate([boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)])


def compute_combined_aabb(bbox_cache: BBoxCache | None, prim_paths: list[str]) -> np.ndarray:
    """(6,) world box enclosing the boxes of every prim of `prim_paths` (as `compute_aabb`).

    Raises:
        InvalidInputError: an empty list, or a path without a prim.
    """
    if isinstance(prim_paths, str) or not len(prim_paths):
        raise InvalidInputError(f"compute_combined_aabb needs a non-empty list of prim paths; got {prim_paths!r}")
    boxes = np.array([compute_aabb(bbox_cache, p) for p in prim_paths])
    return np.concatenate([boxes[:, :3].min(axis=0), boxes[:, 3:].max(axis=0)])


__all__ = ["BBoxCache", "compute_aabb", "compute_combined_aabb", "create_bbox_cache"]
