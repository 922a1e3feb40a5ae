"""Isaac 5's view names: in `isaacsim.core.prims`, `XFormPrim`, `RigidPrim`, `GeometryPrim` and
`Articulation` are the batched views (4.x's `XFormPrimView`, `RigidPrimView`, ...) and the
single-prim classes are `SingleXFormPrim`, `SingleRigidPrim`, ...

manip.sim has one class per 4.x name, the single prim (`SingleXFormPrim` is `XFormPrim`). Called
as a view, it makes the view instead: given `prim_paths_expr=`, a plural pose argument
(`positions=`, `translations=`, `orientations=`, `scales=`, `visibilities=`), or a path that is
an expression (a regular expression such as "/World/Cube_.*": USD prim names are letters,
digits and underscores only). A plain path given by position ("/World/Franka") stays a single
prim: a 5.x script viewing one prim by position gets the single prim's API (arrays without the
leading batch axis).

The modules that define the views register them here (`register`); the single classes ask
`view_call` in their `__new__`. Only the four classes themselves dispatch, never a subclass
(a `DynamicCuboid` is always a single object).
"""

from __future__ import annotations

import re
from typing import Any, Callable

#: Arguments only a view takes.
VIEW_ARGUMENTS = ("prim_paths_expr", "positions", "translations", "orientations", "scales", "visibilities")
_EXPRESSION = re.compile(r"[.*+?\[\](){}|^$\\]")
_VIEWS: dict[type, Callable[..., Any]] = {}


def register(single: type, make_view: Callable[..., Any]) -> None:
    """Let `single(...)` called as a view return `make_view(...)` (the same arguments)."""
    _VIEWS[single] = make_view


def is_view_call(args: tuple, kwargs: dict) -> bool:
    """Whether a call to one of the four names asks for a view (see the module docstring)."""
    if any(k in kwargs for k in VIEW_ARGUMENTS):
        return True
    path = args[0] if args else kwargs.get("prim_path")
    return isinstance(path, str) and _EXPRESSION.search(path) is not None


def view_call(cls: type, args: tuple, kwargs: dict) -> Any | None:
    """The view `cls(*args, **kwargs)` makes as Isaac 5's view name, or None (a single prim)."""
    make_view = _VIEWS.get(cls)
    if make_view is None or not is_view_call(args, kwargs):
        return None
    if args and "prim_paths_expr" not in kwargs:
        args, kwargs = args[1:], {"prim_paths_expr": args[0], **kwargs}
    elif "prim_path" in kwargs and "prim_paths_expr" not in kwargs:
        kwargs = {"prim_paths_expr": kwargs.pop("prim_path"), **kwargs}
    return make_view(*args, **kwargs)
