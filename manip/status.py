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



def truth_is_success(result) -> bool:
    """`bool(result)` is `result.success`: `if result:` and `assert result` test the outcome
    (an object's default truth, always true, would let a failed plan through)."""
    return bool(result.success)


def no_truth_value(result) -> bool:
    """`bool()` of a batch result (one success per item): refused, naming `success`.

    Raises:
        TypeError: always.
    """
    raise TypeError(f"a {type(result).__name__} has no truth value: test `.success` (one per item: "
                    f"`.success.all()`, `.success.any()`)")
