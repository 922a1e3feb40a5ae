"""`PhysicsContext` (`World.get_physics_context()`): Isaac's physics-scene settings on MuJoCo.

What maps: gravity (`set_gravity(value)`: the value along the stage's up axis z, Isaac's sign
convention, -9.81 pulls down; `get_gravity()` -> (direction, magnitude)) and the physics step
(`set_physics_dt` / `get_physics_dt`, the World's). PhysX's solver and performance settings
(solver type, broadphase, CCD, stabilization, GPU dynamics and buffer sizes, thresholds) have
no MuJoCo equivalent: their setters check the value and keep it for the getters, and change
nothing (logged once per setting at INFO); `enable_gpu_dynamics(True)` warns (MuJoCo runs on the
CPU). The solver's own options are MuJoCo's, `World.model.opt`.
"""

from __future__ import annotations

import logging
import math
from typing import Any, Callable, Protocol

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.utils.not_supported import declare as declare_not_supported

logger = logging.getLogger(__name__)


class _Simulation(Protocol):
    """What the context reads and sets: the World's step and compiled model."""

    model: Any

    def get_physics_dt(self) -> float: ...

    def set_simulation_dt(self, physics_dt: float | None = None, rendering_dt: float | None = None) -> None: ...


def _flag(value: Any, what: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"{what} must be True or False; got {value!r}")
    return bool(value)


def _choice(options: tuple[str, ...]) -> Callable[[Any, str], str]:
    def check(value: Any, what: str) -> str:
        if value not in options:
            raise InvalidInputError(f"{what} must be one of {', '.join(options)}; got {value!r}")
        return value
    return check


def _non_negative(value: Any, what: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidInputError(f"{what} must be a number >= 0; got {value!r}") from None
    if not math.isfinite(v) or v < 0:
        raise InvalidInputError(f"{what} must be a finite number >= 0; got {value!r}")
    return v


def _count(value: Any, what: str) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 0:
        raise InvalidInputError(f"{what} must be an integer >= 0; got {value!r}")
    return int(value)


#: PhysX settings kept for their getters: name -> (setter, getter, check, default). The setters of
#: the first block are written out below (Isaac names their argument); the rest take `value`.
KEPT_SETTINGS: dict[str, tuple[str, str, Callable[[Any, str], Any], Any]] = {
    "ccd": ("enable_ccd", "is_ccd_enabled", _flag, False),
    "stabilization": ("enable_stablization", "is_stablization_enabled", _flag, True),
    "broadphase_type": ("set_broadphase_type", "get_broadphase_type", _choice(("MBP", "GPU", "SAP")), "MBP"),
    "solver_type": ("set_solver_type", "get_solver_type", _choice(("TGS", "PGS")), "TGS"),
    "scene_query_support": ("set_enable_scene_query_support", "get_enable_scene_query_support", _flag, True),
    "invert_collision_group_filter": ("set_invert_collision_group_filter", "get_invert_collision_group_filter",
                                      _flag, False),
    "solve_articulation_contact_last": ("set_solve_articulation_contact_last",
                                        "get_solve_articulation_contact_last", _flag, False),
    "bounce_threshold": ("set_bounce_threshold", "get_bounce_threshold", _non_negative, 0.2),
    "friction_offset_threshold": ("set_friction_offset_threshold", "get_friction_offset_threshold",
                                  _non_negative, 0.04),
    "friction_correlation_distance": ("set_friction_correlation_distance", "get_friction_correlation_distance",
                                      _non_negative, 0.025),
    **{f"gpu_{n}": (f"set_gpu_{n}", f"get_gpu_{n}", _count, d) for n, d in (
        ("max_rigid_contact_count", 524288), ("max_rigid_patch_count", 81920),
        ("found_lost_pairs_capacity", 1024), ("found_lost_aggregate_pairs_capacity", 1024),
        ("total_aggregate_pairs_capacity", 1024), ("max_soft_body_contacts", 1048576),
        ("max_particle_contacts", 1048576), ("heap_capacity", 67108864), ("temp_buffer_capacity", 16777216),
        ("max_num_partitions", 8), ("collision_stack_size", 67108864))},
}
_NAMED_ARGUMENT = ("ccd", "stabilization", "broadphase_type", "solver_type", "scene_query_support",
                   "invert_collision_group_filter", "solve_articulation_contact_last")


class PhysicsContext:
    """The World's physics scene (Isaac's `PhysicsContext`; see the module docstring).

    Args:
        simulation: the World (or SimulationContext) it belongs to.
        gravity: (3,) [m/s^2], used when the World compiles.
        prim_path: Isaac's physics scene path (kept for its `prim_path`).
    """

    def __init__(self, simulation: _Simulation, gravity: np.ndarray, prim_path: str = "/physicsScene"):
        self._simulation = simulation
        self._gravity = np.array(gravity, dtype=float)
        self._prim_path = prim_path
        self._settings = {name: default for name, (_, _, _, default) in KEPT_SETTINGS.items()}
        self._gpu_dynamics = False
        self._logged: set[str] = set()

    @property
    def prim_path(self) -> str:
        return self._prim_path

    @property
    def device(self) -> str:
        return "cpu"

    @property
    def use_gpu_sim(self) -> bool:
        return False

    @property
    def use_gpu_pipeline(self) -> bool:
        return False

    @property
    def use_fabric(self) -> bool:
        return False

    # ------------------------------------------------------------------ what maps
    @property
    def gravity(self) -> np.ndarray:
        """The gravity vector (3,) [m/s^2] the World compiles with."""
        return self._gravity.copy()

    def set_gravity(self, value: float) -> None:
        """Gravity `value` [m/s^2] along z (negative: downwards, Isaac's convention), at once if compiled."""
        v = float(np.asarray(value, dtype=float)) if np.ndim(value) == 0 else math.nan
        if not math.isfinite(v):
            raise InvalidInputError(f"gravity value must be one finite number [m/s^2] along z (e.g. -9.81); "
                                    f"got {value!r}")
        self._gravity = np.array([0.0, 0.0, v])
        if self._simulation.model is not None:
            self._simulation.model.opt.gravity[:] = self._gravity

    def get_gravity(self) -> tuple[list[float], float]:
        """(direction (3,) unit list, magnitude [m/s^2]); direction -z for a downward pull."""
        g = float(np.linalg.norm(self._gravity))
        direction = (self._gravity / g).tolist() if g > 0 else [0.0, 0.0, -1.0]
        return direction, g

    def set_physics_dt(self, dt: float = 1.0 / 60.0, substeps: int = 1) -> None:
        """The World's physics step `dt` [s] (0 <= dt <= 1; 0: physics does not simulate, as in
        Isaac); `substeps` (Isaac's minimum frame rate of rendering) is checked and unused:
        `rendering_dt` sets the rendering rate."""
        if isinstance(dt, (bool, np.bool_)) or not isinstance(dt, (int, float, np.floating, np.integer)) \
                or not 0.0 <= float(dt) <= 1.0:
            raise InvalidInputError(f"dt must be a number in [0, 1] [s]; got {dt!r}")
        if substeps is not None:
            _count(substeps, "substeps")
        self._simulation.set_simulation_dt(physics_dt=float(dt))

    def get_physics_dt(self) -> float:
        return self._simulation.get_physics_dt()

    # ------------------------------------------------------------------ kept, no MuJoCo equivalent
    def enable_gpu_dynamics(self, flag: bool) -> None:
        """Kept; True warns: MuJoCo runs on the CPU (there is no GPU pipeline to enable)."""
        self._gpu_dynamics = _flag(flag, "flag")
        if self._gpu_dynamics:
            logger.warning("enable_gpu_dynamics(True): manip.sim runs MuJoCo on the CPU; the setting is kept, "
                           "nothing changes")

    def is_gpu_dynamics_enabled(self) -> bool:
        return self._gpu_dynamics

    def enable_fabric(self, enable: bool) -> None:
        """Kept for Isaac scripts: there is no Fabric; reading poses is always current."""
        _flag(enable, "enable")

    def warm_start(self) -> None:
        """Nothing to start: the World compiles at its reset."""

    def enable_ccd(self, flag: bool) -> None:
        """PhysX continuous collision detection: kept (MuJoCo's substeps bound travel between contact checks)."""
        self._keep("ccd", flag)

    def enable_stablization(self, flag: bool) -> None:
        """PhysX's stabilization pass: kept, no MuJoCo equivalent."""
        self._keep("stabilization", flag)

    enable_stabilization = enable_stablization  # Isaac 5's spelling

    def set_broadphase_type(self, broadcast_type: str) -> None:
        """"MBP", "GPU" or "SAP": kept (MuJoCo has its own broadphase)."""
        self._keep("broadphase_type", broadcast_type)

    def set_solver_type(self, solver_type: str) -> None:
        """"TGS" or "PGS": kept (MuJoCo's solver is World.model.opt.solver)."""
        self._keep("solver_type", solver_type)

    def set_enable_scene_query_support(self, enable_scene_query_support: bool) -> None:
        """Kept (no PhysX scene queries here)."""
        self._keep("scene_query_support", enable_scene_query_support)

    def set_invert_collision_group_filter(self, invert_collision_group_filter: bool) -> None:
        """Kept (no PhysX collision groups here)."""
        self._keep("invert_collision_group_filter", invert_collision_group_filter)

    def set_solve_articulation_contact_last(self, solve_articulation_contact_last: bool) -> None:
        """Kept (a PhysX solver ordering)."""
        self._keep("solve_articulation_contact_last", solve_articulation_contact_last)

    def _keep(self, name: str, value: Any) -> None:
        setter, _, check, _ = KEPT_SETTINGS[name]
        self._settings[name] = check(value, setter)
        if name not in self._logged:
            self._logged.add(name)
            logger.info("PhysicsContext.%s: a PhysX setting without a MuJoCo equivalent; kept, nothing changes",
                        setter)


def _accessors(name: str) -> tuple[Callable, Callable]:
    setter, getter, _, _ = KEPT_SETTINGS[name]

    def set_(self: PhysicsContext, value: Any) -> None:
        self._keep(name, value)

    def get(self: PhysicsContext) -> Any:
        return self._settings[name]

    set_.__name__, get.__name__ = setter, getter
    set_.__doc__ = f"PhysX's {name.replace('_', ' ')}: checked and kept (no MuJoCo equivalent; see the module)."
    get.__doc__ = f"The {name.replace('_', ' ')} last set (PhysX's default until then)."
    return set_, get


for _name, (_setter, _getter, _, _) in KEPT_SETTINGS.items():
    _set, _get = _accessors(_name)
    if _name not in _NAMED_ARGUMENT:
        setattr(PhysicsContext, _setter, _set)
    setattr(PhysicsContext, _getter, _get)

declare_not_supported(PhysicsContext)
