"""Isaac's stage and prim utilities that work on manip's stage (`omni.isaac.core.utils.prims`,
the rest of `...utils.stage`); those that need USD raise NotImplementedError saying why."""

from __future__ import annotations

from typing import Any

from manip.errors import InvalidInputError
from manip.sim.core.world import World
from manip.sim.prims.views import compile_path_expression, path_matches
from manip.sim.scenes.stage import get_current_stage
from manip.sim.utils import not_supported
from manip.sim.utils.rotations import euler_angles_to_rot_matrix


def get_stage_units() -> float:
    """Metres per stage unit: always 1.0 (manip's stage is in metres)."""
    return 1.0


def is_stage_loading() -> bool:
    """False: the stage loads synchronously."""
    return False


def get_prim_at_path(prim_path: str, fabric: bool = False) -> Any | None:
    """The object (or referenced model) at `prim_path` on the stage, None if there is none
    (`fabric` accepted for Isaac's signature)."""
    return get_current_stage().get_prim(prim_path)


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
create_prim = not_supported.function("create_prim")
gf_quat_to_np_array = not_supported.function("gf_quat_to_np_array")
