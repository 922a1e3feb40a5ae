"""PhysX's sleep threshold of rigid bodies (`RigidPrim.set_sleep_threshold`,
`RigidPrimView.set_sleep_thresholds`): checked against PhysX's range, kept for the getters,
and without effect.

PhysX puts a body to sleep when its mass-normalised kinetic energy [m^2/s^2] stays below the
threshold; manip.sim leaves MuJoCo's sleeping off, so nothing sleeps, as PhysX with a threshold
of 0 (set without a warning). Any other value is kept and warned about once per prim (view).
The getters return PhysX's default (PhysxRigidBodyAPI `physxRigidBody:sleepThreshold`,
0.00005 m^2/s^2) until a value is set.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)

#: PhysxRigidBodyAPI's default sleep threshold [m^2/s^2] (range [0, inf)).
PHYSX_RIGID_SLEEP_THRESHOLD = 5e-5

_WHY = "manip.sim leaves MuJoCo's sleeping off: nothing sleeps (as PhysX with a threshold of 0)"


def _check(values: np.ndarray, name: str) -> np.ndarray:
    bad = ~np.isfinite(values) | (values < 0)
    if bad.any():
        raise InvalidInputError(f"{name} must be finite numbers >= 0 [m^2/s^2, PhysX's mass-normalised kinetic "
                                f"energy; range [0, inf)]; got {values[bad].tolist()}")
    return values


def _warn_once(owner, call: str, values: np.ndarray) -> None:
    if np.any(values != 0) and not owner.__dict__.get("_sleep_warned"):
        owner.__dict__["_sleep_warned"] = True
        logger.warning("%s: kept for the getter, changes nothing: %s", call, _WHY)


class RigidSleepThreshold:
    """`set_sleep_threshold` / `get_sleep_threshold` of one rigid body (see the module)."""

    def set_sleep_threshold(self, threshold: float) -> None:
        """PhysX's sleep threshold [m^2/s^2], >= 0: kept, no effect (nothing sleeps in manip.sim)."""
        if isinstance(threshold, bool) or not isinstance(threshold, (int, float, np.floating, np.integer)) \
                or not math.isfinite(threshold) or threshold < 0:
            raise InvalidInputError(f"threshold must be a finite number >= 0 [m^2/s^2]; got {threshold!r}")
        value = np.array([float(threshold)])
        _warn_once(self, f"{type(self).__name__}.set_sleep_threshold({float(threshold)!r})", value)
        self.__dict__["_sleep_threshold"] = float(value[0])

    def get_sleep_threshold(self) -> float:
        """The threshold last set [m^2/s^2] (PhysX's default 5e-05 until then)."""
        return self.__dict__.get("_sleep_threshold", PHYSX_RIGID_SLEEP_THRESHOLD)


class RigidViewSleepThresholds:
    """`set_sleep_thresholds` / `get_sleep_thresholds` of a view of rigid bodies (see the module)."""

    def _sleep_values(self) -> np.ndarray:
        values = self.__dict__.get("_sleep_thresholds")
        if values is None or values.shape != (self.count,):
            values = np.full(self.count, PHYSX_RIGID_SLEEP_THRESHOLD)
            self.__dict__["_sleep_thresholds"] = values
        return values

    def set_sleep_thresholds(self, thresholds, indices=None) -> None:
        """Set (K,) PhysX sleep thresholds [m^2/s^2], >= 0, of the prims `indices` (one value: all of
        them): kept, no effect."""
        idx = self._idx(indices)
        try:
            t = np.asarray(thresholds, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise InvalidInputError(f"thresholds must be {idx.size} numbers [m^2/s^2]; got {thresholds!r}") from None
        if t.size == 1 and idx.size != 1:
            t = np.full(idx.size, t[0])
        if t.shape != (idx.size,):
            raise InvalidInputError(f"thresholds must be {idx.size} values (one per prim of indices); got shape "
                                    f"{np.shape(thresholds)}")
        _check(t, "thresholds")
        _warn_once(self, f"{type(self).__name__}.set_sleep_thresholds", t)
        self._sleep_values()[idx] = t

    def get_sleep_thresholds(self, indices=None, clone: bool = True) -> np.ndarray:
        """(K,) the thresholds last set [m^2/s^2] (PhysX's default 5e-05 until then)."""
        return self._sleep_values()[self._idx(indices)].copy()
