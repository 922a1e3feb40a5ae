"""Exceptions raised for caller errors.

Expected algorithmic failures (no IK solution, no plan within the budget) are reported in
result objects with a status; everything here means the *input* was wrong, and the message
says what was wrong and what is valid.
"""

from __future__ import annotations

from collections.abc import Iterable


class ManipError(Exception):
    """Base class of every exception raised by manip."""


class InvalidInputError(ManipError, ValueError):
    """An argument has the wrong shape, a non-finite value or is out of its valid range."""


class UnknownNameError(ManipError, KeyError):
    """A joint, link, frame, robot or object name that does not exist."""

    def __init__(self, kind: str, name: str, available: Iterable[str]):
        self.kind = kind
        self.name = name
        self.available = sorted(available)
        super().__init__(f"{kind} '{name}' not found; available: {', '.join(self.available)}")

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0])


class RobotConfigError(ManipError):
    """A robot configuration file is missing, malformed or inconsistent with its model."""
