"""Isaac's prim-tree and transform helpers (`omni.isaac.core.utils.prims`: `get_prim_children`,
`get_prim_parent`, `get_prim_path`, `get_prim_type_name`, `get_prim_object_type`,
`get_all_matching_child_prims`, `get_first_matching_child_prim`, `define_prim`;
`omni.isaac.core.utils.xforms`: `get_world_pose`, `get_local_pose`) on manip's stage.

A prim is what `get_prim_at_path` returns (manip's object there, or the `XFormPrim` of a robot's
link) or its path; the tree is flat below a referenced model as in Isaac's robot USD files (the
model's links are its children). Poses are (position (3,) [m], quaternion (4,) (w, x, y, z)).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.prims.xform_prim import model_frame_pose
from manip.sim.scenes.stage import ReferencePrim, child_paths, get_prim_at_path
from manip.sim.utils.prims import LIGHT_TYPES, create_prim


def _path(prim: Any, what: str = "prim") -> str:
    """The path of `prim` (an object with `prim_path`, or a path)."""
    path = prim if isinstance(prim, str) else getattr(prim, "prim_path", None)
    if not isinstance(path, str):
        raise InvalidInputError(f"{what} must be a prim (what get_prim_at_path returns) or a prim path; got {prim!r}")
    return path


def _existing(prim_path: str, caller: str) -> Any:
    prim = get_prim_at_path(prim_path)
    if prim is None:
        raise InvalidInputError(f"{caller}: no prim at {prim_path!r} (is_prim_path_valid is False)")
    return prim


def get_prim_path(prim: Any) -> str:
    """The path of a prim (Isaac's takes a `Usd.Prim`; a path is returned as it is)."""
    return _path(prim)


def get_prim_children(prim: Any) -> list[Any]:
    """The prims one segment below `prim` (a robot's links below the robot; a link's mounted prims)."""
    return [get_prim_at_path(p) for p in child_paths(_path(prim))]


def get_prim_parent(prim: Any) -> Any | None:
    """The prim one segment above `prim` (None at "/World", which is no object here)."""
    return get_prim_at_path(_path(prim).rsplit("/", 1)[0])


def get_prim_type_name(prim_path: str, fabric: bool = False) -> str:
    """USD's type name of the prim at `prim_path`: "Cube", "Sphere", ..., "Camera", else "Xform".

    Raises:
        InvalidInputError: no prim there (Isaac raises too).
    """
    return _existing(_path(prim_path, "prim_path"), "get_prim_type_name").GetTypeName()


def get_prim_object_type(prim_path: str) -> str | None:
    """What Isaac's core API would wrap the prim in: "articulation" (a referenced robot's root),
    "rigid_body" (a dynamic object, a robot's link), "xform" (anything else), None (no prim)."""
    prim = get_prim_at_path(_path(prim_path, "prim_path"))
    if prim is None:
        return None
    if isinstance(prim, ReferencePrim):
        return "articulation"
    if getattr(prim, "_wrapped_reference", None) is not None and getattr(prim, "_body_id", -1) >= 0:
        return "rigid_body"   # a link (a body; a site is an xform)
    return "rigid_body" if hasattr(prim, "get_linear_velocity") and hasattr(prim, "get_mass") else "xform"


def get_all_matching_child_prims(prim_path: str, predicate: Callable[[str], bool] = lambda path: True,
                                 depth: int | None = None) -> list[Any]:
    """The prims at and below `prim_path` (breadth first, `prim_path` itself first) whose path
    `predicate` accepts, down to `depth` segments below it (None: all).

    Raises:
        InvalidInputError: no prim at `prim_path`, or a negative depth.
    """
    root = _path(prim_path, "prim_path")
    _existing(root, "get_all_matching_child_prims")
    if depth is not None and (isinstance(depth, bool) or not isinstance(depth, int) or depth < 0):
        raise InvalidInputError(f"depth must be None or a whole number >= 0; got {depth!r}")
    out, queue = [], [(root, 0)]
    while queue:
        path, level = queue.pop(0)
        if predicate(path):
            out.append(get_prim_at_path(path))
        if depth is None or level < depth:
            queue += [(child, level + 1) for child in child_paths(path)]
    return out


def get_first_matching_child_prim(prim_path: str, predicate: Callable[[str], bool]) -> Any | None:
    """The first prim at or below `prim_path` (breadth first) whose path `predicate` accepts, or None."""
    found = get_all_matching_child_prims(prim_path, predicate)
    return found[0] if found else None


def define_prim(prim_path: str, prim_type: str = "Xform", fabric: bool = False) -> Any:
    """Isaac's `define_prim`: `create_prim(prim_path, prim_type)` (an "Xform", "Scope", light or
    geometry type); a prim already there of that type is returned, as USD's Define does.

    Raises:
        InvalidInputError: a prim of another type at `prim_path`.
    """
    existing = get_prim_at_path(_path(prim_path, "prim_path"))
    if existing is not None:
        kind = existing.GetTypeName()
        if kind != ("Xform" if prim_type in ("Scope",) + LIGHT_TYPES else prim_type):  # lights are transforms here
            raise InvalidInputError(f"define_prim({prim_path!r}, {prim_type!r}): a {kind} is there already")
        return existing
    return create_prim(prim_path, prim_type)


def get_world_pose(prim_path: str, fabric: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """World pose of the prim at `prim_path` (`omni.isaac.core.utils.xforms.get_world_pose`):
    an object, a robot (its base) or a robot's link, in the current simulation state.

    Raises:
        InvalidInputError: no prim there.
    """
    prim = _existing(_path(prim_path, "prim_path"), "get_world_pose")
    if isinstance(prim, ReferencePrim):  # a robot's root: its base (teleports included)
        return tuple(np.asarray(v, dtype=float).copy() for v in model_frame_pose(prim))
    if not hasattr(prim, "get_world_pose"):
        raise InvalidInputError(f"get_world_pose: the prim at {prim_path!r} ({type(prim).__name__}) has no pose here; "
                                "wrap a referenced model in Robot / Articulation to read its base pose")
    position, orientation = prim.get_world_pose()
    return np.asarray(position, dtype=float).copy(), np.asarray(orientation, dtype=float).copy()


def get_local_pose(prim_path: str) -> tuple[np.ndarray, np.ndarray]:
    """Pose of the prim at `prim_path` in its parent's frame (`...utils.xforms.get_local_pose`):
    a robot's link in the robot's frame, a mounted prim in its link's, else the world pose.

    Raises:
        InvalidInputError: no prim there, or one without a pose.
    """
    prim = _existing(_path(prim_path, "prim_path"), "get_local_pose")
    if isinstance(prim, ReferencePrim):  # below "/World", the identity: its world pose
        return get_world_pose(prim_path)
    if not hasattr(prim, "get_local_pose"):
        raise InvalidInputError(f"get_local_pose: the prim at {prim_path!r} ({type(prim).__name__}) has no pose here")
    position, orientation = prim.get_local_pose()
    return np.asarray(position, dtype=float).copy(), np.asarray(orientation, dtype=float).copy()


__all__ = ["define_prim", "get_all_matching_child_prims", "get_first_matching_child_prim", "get_local_pose",
           "get_prim_children", "get_prim_object_type", "get_prim_parent", "get_prim_path", "get_prim_type_name",
           "get_world_pose"]
