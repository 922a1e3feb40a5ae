"""Named callbacks (physics, timeline, stage, render) and the events they receive."""

from __future__ import annotations

from typing import Callable

from manip.errors import InvalidInputError, UnknownNameError


class TimelineEvent:
    """What a timeline callback receives: `type` is "PLAY", "PAUSE" or "STOP" (render
    callbacks get "RENDER")."""

    def __init__(self, type: str):
        self.type = type

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

    def add(self, name: str, fn: Callable) -> None:
        """Register `fn` as `name`.

        Raises:
            InvalidInputError: `fn` is not callable, or the name is taken.
        """
        if not callable(fn):
            raise InvalidInputError(f"{self.kind} callback {name!r} must be callable; got {fn!r}")
        if name in self._fns:
            raise InvalidInputError(
                f"a {self.kind} callback named {name!r} already exists; remove it first or use another name "
                f"(existing: {sorted(self._fns)})"
            )
        self._fns[name] = fn

    def remove(self, name: str) -> None:
        """Forget `name`.

        Raises:
            UnknownNameError: no callback of that name (the message lists them).
        """
        if name not in self._fns:
            raise UnknownNameError(f"{self.kind} callback", name, sorted(self._fns))
        del self._fns[name]

    def __contains__(self, name: object) -> bool:
        return name in self._fns

    def clear(self) -> None:
        self._fns.clear()

    def call(self, *args) -> None:
        """Call every callback with `args` (a callback may add or remove callbacks)."""
        for fn in list(self._fns.values()):
            fn(*args)
