"""How many attempts an IK call makes, and their random starts.

An attempt is one descent: the first from `seed_q`, the others from random configurations.
`max_attempts` is manip's name for the count; cuRobo calls it `num_seeds` (`IKSolverConfig`
and `IKSolver.solve_single(..., num_seeds=)`: the seeds tried per goal), accepted with a
DeprecationWarning naming `max_attempts`.
"""

from __future__ import annotations

import warnings

import numpy as np

from manip.errors import InvalidInputError
from manip.validation import integer


class LazyRng:
    """A np.random.Generator created on first use (most solves never restart)."""

    def __init__(self, seed: int):
        self._seed = seed
        self._rng: np.random.Generator | None = None

    def uniform(self, low: np.ndarray, high: np.ndarray, size: tuple[int, ...] | None = None) -> np.ndarray:
        if self._rng is None:
            self._rng = np.random.default_rng(self._seed)
        return self._rng.uniform(low, high, size)


def at_least_one(value: int, what: str) -> int:
    """`value` checked as an integer >= 1 (InvalidInputError naming `what` otherwise)."""
    return integer(value, what, 1)


def renamed(old: str, old_value, new: str, new_value, stacklevel: int = 4):
    """The value of keyword `new`, or of its deprecated name `old` (with a DeprecationWarning)."""
    if old_value is None:
        return new_value
    if new_value is not None:
        raise InvalidInputError(f"give {new} only ({old} is its deprecated name)")
    warnings.warn(f"{old} is deprecated; use {new}", DeprecationWarning, stacklevel=stacklevel)
    return old_value


def call_attempts(default: int, max_attempts: int | None, num_seeds: int | None) -> int:
    """The attempts per goal of one call: `max_attempts`, or cuRobo's `num_seeds` (deprecated
    name, warned about), else the solver's `default`.

    Raises:
        InvalidInputError: a value that is not an integer >= 1, or both names given.
    """
    if num_seeds is not None:
        num_seeds = at_least_one(num_seeds, "num_seeds")
    value = renamed("num_seeds", num_seeds, "max_attempts", max_attempts, stacklevel=4)
    return default if value is None else at_least_one(value, "max_attempts")
