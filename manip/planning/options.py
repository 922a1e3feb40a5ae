"""`PlanOptions`: the per-call options of the planning calls, validated in one place."""

from __future__ import annotations

import numbers
from dataclasses import dataclass, fields

import numpy as np

from manip import curobo_names
from manip.constraints import Constraint
from manip.errors import InvalidInputError
from manip.validation import fraction, integer, positive, sample_count

#: Values of the `smoothness` option.
SMOOTHNESS = ("time_optimal", "smooth")
#: With `smoothness="smooth"` the jerk limits are multiplied by this (timing and optimiser).
SMOOTH_JERK_FRACTION = 0.25
#: Largest `ik_solutions` (each is a goal the planner tries to reach).
MAX_IK_SOLUTIONS = 1000
#: Largest `search_iterations` (each iteration may add a node to the search's trees: memory).
MAX_SEARCH_ITERATIONS = 1_000_000


@dataclass(frozen=True)
class PlanOptions:
    """Options of one planning call (`plan_joints`, `plan_pose`, `plan_goalset`, `plan_batch`).

    Attributes:
        time_budget: planning wall-time budget [s]. Every stage of a plan is also bounded by
            counts (RRT iterations, shortcut rounds, optimiser QPs, attempts), so a plan that
            finishes within its budget gives the same result on any machine; one cut short by
            it may not (a TIMEOUT, or a note in `PlanResult.message`: `context.SAFETY_NET`).
        search_iterations: RRT-Connect iterations of a plan's main path search at most (the
            coarse search; its fine-resolution repairs get as many again), a count: a plan
            bounded by it does not depend on the machine's speed. None = the search's own cap
            (`planning.path.search.MAX_ITERATIONS`), which in hard scenes the time budget usually
            cuts first (as before this option). `manip.batch.plan_many` and `manip.datagen`
            set it (`manip.batch.problem.BATCH_SEARCH_ITERATIONS`).
        seed: random seed of this call (IK restarts, sampling, shortcutting).
        dt: sample period of the returned trajectory [s].
        velocity_scale: factor in (0, 1] on the velocity limits.
        acceleration_scale: factor in (0, 1] on the acceleration and jerk limits.
        duration: stretch the motion to this length [s], rounded up to a multiple of `dt`
            (TRAJOPT_FAIL if shorter than feasible); None = as fast as the limits allow. duration / dt may not exceed
            `manip.validation.MAX_SAMPLES` (and neither may the fastest motion's length / dt).
        ik_solutions: collision-free IK solutions sought per goal pose (the goals reached
            fastest are planned to first; BENCHMARKS.md, "Constants").
        linear_step: Cartesian step of linear motions [m].
        optimize_clearance: push the shortcut path's waypoints away from obstacles (tens of
            ms in cluttered scenes).
        trajopt: run the trajectory optimiser on searched paths (faster, shorter, smoother
            motions; falls back to the shortcut path when it fails).
        smoothness: "time_optimal" (the fastest trajectory within the limits) or "smooth"
            (jerk limits x SMOOTH_JERK_FRACTION and a jerk-weighted optimiser: gentler,
            somewhat slower motions).
        constraints: `manip.Constraint`s (`OrientationConstraint`, `PositionConstraint`, ...)
            that hold over the whole continuous motion: the search steers on their set, the
            optimiser keeps them as rows, and the certificate proves them between samples
            (`planning.constrained`). A tuple (a single constraint is taken as one).
    """

    time_budget: float = 5.0
    search_iterations: int | None = None
    seed: int = 0
    dt: float = 1.0 / 60.0
    velocity_scale: float = 1.0
    acceleration_scale: float = 1.0
    duration: float | None = None
    ik_solutions: int = 24
    linear_step: float = 0.005
    optimize_clearance: bool = False
    trajopt: bool = True
    smoothness: str = "time_optimal"
    constraints: tuple = ()

    def __post_init__(self) -> None:
        def put(name, value):
            object.__setattr__(self, name, value)

        put("time_budget", positive(self.time_budget, "time_budget", "s"))
        if self.search_iterations is not None:
            n = self.search_iterations
            if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral) or not 1 <= n <= MAX_SEARCH_ITERATIONS:
                raise InvalidInputError(f"search_iterations must be None or an integer in [1, {MAX_SEARCH_ITERATIONS}]; "
                                        f"got {n!r}")
            put("search_iterations", int(n))
        put("dt", positive(self.dt, "dt", "s"))
        put("velocity_scale", fraction(self.velocity_scale, "velocity_scale"))
        put("acceleration_scale", fraction(self.acceleration_scale, "acceleration_scale"))
        if self.duration is not None:
            put("duration", positive(self.duration, "duration", "s"))
            sample_count(self.duration, self.dt, "duration (or dt)")
        put("linear_step", positive(self.linear_step, "linear_step", "m"))
        put("seed", integer(self.seed, "seed", 0))
        put("ik_solutions", integer(self.ik_solutions, "ik_solutions", 1))
        if self.ik_solutions > MAX_IK_SOLUTIONS:
            raise InvalidInputError(f"ik_solutions must be at most {MAX_IK_SOLUTIONS}; got {self.ik_solutions}")
        for name in ("optimize_clearance", "trajopt"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise InvalidInputError(f"{name} must be True or False; got {getattr(self, name)!r}")
            put(name, bool(getattr(self, name)))
        if not isinstance(self.smoothness, str) or self.smoothness not in SMOOTHNESS:
            raise InvalidInputError(f"smoothness must be one of {list(SMOOTHNESS)}; got {self.smoothness!r}")
        put("constraints", _constraints(self.constraints))

    @property
    def jerk_scale(self) -> float:
        """Factor on the jerk limits: `acceleration_scale`, times SMOOTH_JERK_FRACTION when smooth."""
        return self.acceleration_scale * (SMOOTH_JERK_FRACTION if self.smoothness == "smooth" else 1.0)

    @classmethod
    def names(cls) -> list[str]:
        """The option names, sorted."""
        return sorted(f.name for f in fields(cls))

    def updated(self, options: dict) -> PlanOptions:
        """These options with `options` (a dict of keyword arguments) applied and validated.

        Raises:
            InvalidInputError: an unknown option (the valid names are listed) or a bad value.
        """
        if not isinstance(options, dict):
            raise InvalidInputError(f"options must be a dict of keyword arguments; got {type(options).__name__}")
        unknown = sorted(set(map(str, options)) - set(self.names()))
        if unknown:
            raise InvalidInputError(f"unknown planning option(s) {unknown}; valid: {self.names()}"
                                    + curobo_names.unknown_options(unknown))
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(options)
        return PlanOptions(**values)



def _constraints(value) -> tuple:
    """`value` as a tuple of `manip.constraints.Constraint` (a single one becomes a 1-tuple)."""
    if isinstance(value, Constraint):
        return (value,)
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
        raise InvalidInputError(f"constraints must be a tuple of manip constraints (OrientationConstraint, "
                                f"PositionConstraint, ...); got {value!r}")
    out = tuple(value)
    bad = [c for c in out if not isinstance(c, Constraint)]
    if bad:
        raise InvalidInputError(f"constraints must hold manip constraints (OrientationConstraint, PositionConstraint, "
                                f"or a manip.constraints.Constraint subclass); got {bad[0]!r} ({type(bad[0]).__name__})")
    return out
