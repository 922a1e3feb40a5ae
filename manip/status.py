"""One style for every status enum of manip (PlanStatus, IKStatus, TimingStatus).

Values are lowercase names ("success", "ik_fail"); each enum keeps a table of hints beside
it (what the status means and what to change), read through `status.hint`. Results carry a
`message` with the detail of one call; the hint is the general advice.
"""

from __future__ import annotations

from enum import Enum


class Status(Enum):
    """Base of the status enums: `hint` reads the subclass's `_hints()` table."""

    @property
    def hint(self) -> str:
        """What the status means and what to change."""
        return type(self)._hints().get(self, "")

    @classmethod
    def _hints(cls) -> dict:
        return {}

    def __str__(self) -> str:
        return self.name


def no_truth_value(result) -> bool:
    """`bool()` of a result: refused, naming `success` (a result object would always be true,
    so `if result:` would let a failed plan through).

    Raises:
        TypeError: always.
    """
    status = getattr(result, "status", None)
    raise TypeError(f"a {type(result).__name__} has no truth value: test `.success` "
                    f"(this one: success={getattr(result, 'success', None)}, status={status})")
