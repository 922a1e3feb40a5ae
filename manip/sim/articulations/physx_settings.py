"""PhysX's per-articulation solver settings on an `Articulation`: checked, kept for their getters,
and without effect, with a warning saying so and where MuJoCo's counterpart lives.

- `set_solver_position_iteration_count` / `set_solver_velocity_iteration_count`: PhysX iterates
  each articulation's constraints a count of times; MuJoCo solves all constraints of the World
  at once, to a tolerance, with one iteration cap for the whole World
  (`World.model.opt.iterations`, `opt.tolerance`). A per-articulation count has no meaning
  there: set the World's cap directly (it applies to every robot and object).
- `set_sleep_threshold`: PhysX puts an articulation to sleep below a mass-normalised kinetic
  energy; manip.sim leaves MuJoCo's sleeping off (`mjENBL_SLEEP`), so nothing sleeps, as PhysX
  with a threshold of 0 (which is therefore set without a warning).
- `set_stabilization_threshold`: PhysX's stabilization pass has no MuJoCo equivalent.
- `set_enabled_self_collisions(False)` does change the simulation, from the next `world.reset()`
  (the World recompiles, as PhysX reads the flag when the articulation is created): every pair of
  the model's bodies is excluded from contact (MuJoCo's `<exclude>`); True restores the model's own
  filter (MuJoCo collides bodies that are not parent and child unless its MJCF excludes them).

Getters return the last value set, PhysX's defaults until then (PhysxArticulationAPI's schema: 32, 1,
5e-05 and 1e-05; round six had 0.005 and 0.001 for the thresholds).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.scenes.stage import get_current_stage

logger = logging.getLogger(__name__)

#: PhysxArticulationAPI's defaults (what Isaac's getters read from a robot's USD without them).
PHYSX_DEFAULTS = {"solver_position_iteration_count": 32, "solver_velocity_iteration_count": 1,
                  "sleep_threshold": 5e-5, "stabilization_threshold": 1e-5}

#: Values that are what manip.sim simulates already (no warning): nothing sleeps, as PhysX's 0.
AS_SIMULATED = {"sleep_threshold": 0.0}

#: Why each setting changes nothing here (the warning's text).
NO_EFFECT = {
    "solver_position_iteration_count": "MuJoCo solves every constraint of the World at once to a tolerance; its "
                                       "iteration cap is one setting for the whole World (World.model.opt.iterations)",
    "solver_velocity_iteration_count": "MuJoCo has no separate velocity iterations (its cap for the whole World is "
                                       "World.model.opt.iterations)",
    "sleep_threshold": "manip.sim leaves MuJoCo's sleeping off: nothing sleeps (as PhysX with a threshold of 0)",
    "stabilization_threshold": "PhysX's stabilization pass has no MuJoCo equivalent",
}


def _count(value, name: str, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) \
            or not low <= value <= 255:
        raise InvalidInputError(f"{name} must be a whole number in [{low}, 255] (PhysX's range); got {value!r}")
    return int(value)


def _threshold(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise InvalidInputError(f"{name} must be a finite number >= 0 [m^2/s^2, PhysX's mass-normalised energy]; "
                                f"got {value!r}")
    return float(value)


class PhysxArticulationSettings:
    """PhysX's articulation solver settings (see the module): kept, no effect, warned once each."""

    def _keep_physx(self, name: str, value) -> None:
        settings = self.__dict__.setdefault("_physx_settings", {})
        warned = self.__dict__.setdefault("_physx_warned", set())
        if value not in (PHYSX_DEFAULTS[name], AS_SIMULATED.get(name)) and name not in warned:
            warned.add(name)
            logger.warning("%s.set_%s(%r): kept for get_%s, changes nothing: %s", type(self).__name__, name, value,
                           name, NO_EFFECT[name])
        settings[name] = value

    def _physx(self, name: str):
        return self.__dict__.get("_physx_settings", {}).get(name, PHYSX_DEFAULTS[name])

    def set_enabled_self_collisions(self, flag: bool) -> None:
        """Whether the robot's links collide with each other, from the next `world.reset()`."""
        if not isinstance(flag, (bool, np.bool_)):
            raise InvalidInputError(f"flag must be a bool (True: the links collide with each other); got {flag!r}")
        self.reference.self_collisions = bool(flag)
        stage = get_current_stage()
        if stage.sim is not None:
            stage.mark_changed(self.prim_path)
            logger.info("%s.set_enabled_self_collisions(%s): applies from the next world.reset() (the World "
                        "recompiles)", type(self).__name__, bool(flag))

    def get_enabled_self_collisions(self) -> bool:
        """The flag last set (True until then: the model's own filter lets non-adjacent links collide)."""
        flag = self.reference.self_collisions
        return True if flag is None else flag

    def set_solver_position_iteration_count(self, count: int) -> None:
        """PhysX's position iterations, 1..255: kept, no effect (MuJoCo's cap: World.model.opt.iterations)."""
        self._keep_physx("solver_position_iteration_count", _count(count, "count", 1))

    def get_solver_position_iteration_count(self) -> int:
        """The count last set (PhysX's default 32 until then)."""
        return self._physx("solver_position_iteration_count")

    def set_solver_velocity_iteration_count(self, count: int) -> None:
        """PhysX's velocity iterations, 0..255: kept, no effect (MuJoCo has none of its own)."""
        self._keep_physx("solver_velocity_iteration_count", _count(count, "count", 0))

    def get_solver_velocity_iteration_count(self) -> int:
        """The count last set (PhysX's default 1 until then)."""
        return self._physx("solver_velocity_iteration_count")

    def set_sleep_threshold(self, threshold: float) -> None:
        """PhysX's sleep threshold [m^2/s^2], >= 0: kept, no effect (nothing sleeps in manip.sim)."""
        self._keep_physx("sleep_threshold", _threshold(threshold, "threshold"))

    def get_sleep_threshold(self) -> float:
        """The threshold last set (PhysX's default 5e-05 until then)."""
        return self._physx("sleep_threshold")

    def set_stabilization_threshold(self, threshold: float) -> None:
        """PhysX's stabilization threshold [m^2/s^2], >= 0: kept, no effect (no MuJoCo equivalent)."""
        self._keep_physx("stabilization_threshold", _threshold(threshold, "threshold"))

    def get_stabilization_threshold(self) -> float:
        """The threshold last set (PhysX's default 1e-05 until then)."""
        return self._physx("stabilization_threshold")
