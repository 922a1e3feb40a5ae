"""Isaac members manip.sim cannot provide raise NotImplementedError naming themselves and why
(the table: `manip.sim.isaac_api.NOT_SUPPORTED`)."""

from __future__ import annotations

from typing import Callable

from manip.sim.isaac_api import FUNCTIONS_NOT_SUPPORTED, NOT_SUPPORTED


def _stub(owner: str, name: str, why: str) -> Callable:
    def stub(*args, **kwargs):
        raise NotImplementedError(f"{owner}.{name} is not available in manip.sim: {why}")

    stub.__name__ = name
    stub.__qualname__ = f"{owner}.{name}"
    stub.__doc__ = f"Not available in manip.sim (raises NotImplementedError): {why}."
    stub.isaac_not_supported = why
    return stub


def declare(cls: type, key: str | None = None) -> type:
    """Give `cls` a raising member for each of its `NOT_SUPPORTED[key or cls.__name__]`
    entries that neither it nor a base class defines; returns `cls`. Properties (Isaac's
    `prim`, `app`, ...) raise when read."""
    owner = key or cls.__name__
    for name, why in NOT_SUPPORTED.get(owner, {}).items():
        if hasattr(cls, name):
            continue
        stub = _stub(owner, name, why)
        setattr(cls, name, property(stub, doc=stub.__doc__) if name in _PROPERTIES else stub)
    return cls


#: Isaac members that are properties (read, not called).
_PROPERTIES = {"prim", "prims", "app", "context", "backend", "device", "num_shapes"}


def function(name: str) -> Callable:
    """The raising stand-in of a module-level Isaac utility (`FUNCTIONS_NOT_SUPPORTED`)."""
    return _stub("omni.isaac.core.utils", name, FUNCTIONS_NOT_SUPPORTED[name])
