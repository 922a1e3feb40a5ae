"""Named callbacks (physics, timeline, stage, render) and the events they receive.

Names follow Isaac Sim: adding a name that is taken, or removing one that does not exist,
logs an error through `carb.log_error` (as Isaac's `SimulationContext` does) and changes
nothing; it does not raise. A callback that is not callable, or cannot be called with one
argument (the step size or the event), raises InvalidInputError when it is added.
"""

from __future__ import annotations

import inspect
from typing import Callable

from manip.errors import InvalidInputError
from manip.sim.core.carb_logging import carb


class TimelineEvent:
    """What a timeline callback receives: `type` is "PLAY", "PAUSE" or "STOP" (render
    callbacks get "RENDER"); `payload` is Isaac's event payload: {"currentTime": t [s]} for the
    timeline, {"dt": rendering_dt [s]} for a render (Kit's update event)."""

    def __init__(self, type: str, payload: dict | None = None):
        self.type = type
        self.payload = dict(payload or {})

    def __repr__(self) -> str:
        return f"TimelineEvent({self.type!r})"


class CallbackTable:
    """Callbacks of one kind by name, called in the order they were added.

    Args:
        kind: what the callbacks are for ("physics", "timeline", ...), used in messages.
    """

    def __init__(self, kind: str):
        self.kind = kind
        self._fns: dict[str, Callable] = {}

    def add(self, name: str, fn: Callable) -> bool:
        """Register `fn` as `name`. Returns False (and logs an error, as Isaac) if the name
        is taken; the existing callback is kept.

        Raises:
            InvalidInputError: `fn` is not callable, or cannot take the one argument it is
                called with (found at registration, not at the first step).
        """
        if not callable(fn):
            raise InvalidInputError(f"{self.kind} callback {name!r} must be callable; got {fn!r}")
        try:
            inspect.signature(fn).bind(None)
        except TypeError:
            arg = "step_size [s]" if self.kind == "physics" else "event"
            raise InvalidInputError(
                f"{self.kind} callback {name!r} must take one argument ({arg}), as Isaac calls it; "
                f"got {getattr(fn, '__qualname__', fn)!r} with signature {inspect.signature(fn)}") from None
        except ValueError:  # a callable without an inspectable signature (some builtins)
            pass
        if name in self._fns:
            carb.log_error(
                f"{self.kind.capitalize()} callback `{name}` already exists; the new one is ignored "
                f"(remove it first or use another name; existing: {sorted(self._fns)})"
            )
            return False
        self._fns[name] = fn
        return True

    def remove(self, name: str) -> bool:
        """Forget `name`. Returns False (and logs an error listing the names, as Isaac) if
        there is no callback of that name."""
        if name not in self._fns:
            carb.log_error(f"{self.kind.capitalize()} callback `{name}` doesn't exist (existing: {sorted(self._fns)})")
            return False
        del self._fns[name]
        return True

    def __contains__(self, name: object) -> bool:
        return name in self._fns

    def names(self) -> list[str]:
        return list(self._fns)

    def clear(self) -> None:
        self._fns.clear()

    def call(self, *args) -> None:
        """Call every callback with `args` (a callback may add or remove callbacks)."""
        for fn in list(self._fns.values()):
            fn(*args)
