"""Settings of the trajectory optimiser (`planning.trajopt.optimizer`, `planning.trajopt.sco`), with the
measurements behind their defaults."""

from __future__ import annotations

from dataclasses import dataclass

from manip.errors import InvalidInputError
from manip.planning.trajopt import qp
from manip.validation import flag, integer, non_negative, positive

__all__ = ["SMOOTH", "TrajOptSettings"]


@dataclass(frozen=True)
class TrajOptSettings:
    """Settings of the trajectory optimiser.

    Attributes:
        intervals: B-spline pieces N (N - 3 free control points per joint).
        samples_per_interval: collision samples per piece.
        margin: sphere-cover clearance [m] kept from obstacles (on top of the padding).
        activation: terms farther than margin + activation are left out of the QP [m].
        iterations: SCO iterations per duration (at most).
        tolerance: an SCO stops when a step lowers the merit by less than this fraction;
            the free-duration SCO stops when its model predicts less than this fraction of
            the duration to gain.
        limit_row_slack: limit rows used less than (1 - this) of their limit at the
            current point are left out of the QP (they are soft, and the result is re-timed
            exactly).
        trust_region: largest move of a control point per iteration [rad] at first and at
            most; it halves after a rejected step, and each duration round starts at twice
            the previous round's final radius.
        line_search: halvings of a step that does not lower the merit tried before the
            trust region shrinks (each costs a clearance evaluation, not a QP; 3 against 1:
            ~8 % fewer QPs, BENCHMARKS.md "Round thirteen").
        ray_points: control points tied to the seed's first / last segment at an end near
            an obstacle (each keeps one more piece of the motion on that segment).
        rounds: durations tried (the seed's first, then by bisection towards the lower bound).
        second_chance: when the seed's duration gives no usable motion (none, or none
            faster than `max_duration`), start once more from the spline fitted to the seed
            at the duration where it is within the limits (the fit of a ruckig-timed polyline
            exceeds the acceleration limits about 1.9 x at the seed's own duration).
        bisection: where the next duration lies between the longest infeasible and the
            shortest feasible one (0.5: halfway).
        duration_tolerance: the search stops once the best duration is within this fraction
            of the longest target not reached.
        penalty: weight of the clearance violation [1/m] (L1) against the objective.
        velocity_weight, acceleration_weight, jerk_weight: objective weights (terms are
            squared fractions of the limits).
        free_duration: optimise the duration inside the SCO (`sco.sco_free_step`) after
            `first_iterations` at the seed's duration; False: the bisection over fixed
            durations (`rounds`, `bisection`, `duration_tolerance`, `second_chance`).
        time_weight: weight of the duration (as a fraction of the starting one) against the
            regulariser and the clearance penalty in the free-duration SCO.
        free_iterations: QPs of the free-duration SCO at most.
        first_iterations: SCO iterations at the seed's duration before the free-duration SCO
            (0: start it from the fitted seed).
        solver: a `qpsolvers` solver name ("osqp", "daqp", ...).

    The measurements behind the defaults: BENCHMARKS.md, "Constants".
    """

    intervals: int = 16
    samples_per_interval: int = 5
    margin: float = 0.008
    activation: float = 0.02
    iterations: int = 6
    tolerance: float = 5e-3
    limit_row_slack: float = 0.6
    trust_region: float = 0.15
    rounds: int = 6
    ray_points: int = 1
    bisection: float = 0.3
    duration_tolerance: float = 0.03
    penalty: float = 1e4
    second_chance: bool = True
    line_search: int = 3
    velocity_weight: float = 200.0
    acceleration_weight: float = 0.01
    jerk_weight: float = 0.001
    free_duration: bool = True
    time_weight: float = 3e4
    free_iterations: int = 32
    first_iterations: int = 2
    solver: str = "piqp"

    def __post_init__(self) -> None:
        def name(field: str) -> str:
            return f"TrajOptSettings.{field}"

        for field, least in (("intervals", 4), ("samples_per_interval", 1), ("iterations", 1), ("rounds", 1),
                             ("ray_points", 1), ("line_search", 0), ("free_iterations", 1), ("first_iterations", 0)):
            integer(getattr(self, field), name(field), least)
        for field in ("bisection", "duration_tolerance", "limit_row_slack"):
            if not 0.0 < non_negative(getattr(self, field), name(field)) < 1.0:
                raise InvalidInputError(f"{name(field)} must be a number in (0, 1); got {getattr(self, field)!r}")
        for field in ("margin", "activation", "tolerance", "velocity_weight", "acceleration_weight", "jerk_weight"):
            non_negative(getattr(self, field), name(field))
        positive(self.trust_region, name("trust_region"), "rad")
        positive(self.penalty, name("penalty"))
        positive(self.time_weight, name("time_weight"))
        flag(self.second_chance, name("second_chance"))
        flag(self.free_duration, name("free_duration"))
        if not qp.solver_available(self.solver):
            raise InvalidInputError(f"TrajOptSettings.solver must be 'piqp' or an installed qpsolvers solver "
                                    f"({', '.join(qp.installed_solvers())}); got {self.solver!r}")
        if self.intervals >= 8 and self.ray_points > self.intervals // 2 - 2:  # rays need N >= 8
            raise InvalidInputError(f"TrajOptSettings.ray_points must be <= intervals // 2 - 2 = "
                                    f"{self.intervals // 2 - 2}; got {self.ray_points}")


#: `smoothness="smooth"`: a jerk objective at fixed durations (the free-duration SCO would
#: trade the jerk for time; BENCHMARKS.md, "Constants"); its SCO stops at the `tolerance` its
#: bisection was measured with (3e-3; the default's 5e-3 was measured on the free-duration SCO), and
#: halves a rejected step once (`line_search` 1; the default's 3 was measured on the free-duration SCO).
SMOOTH = TrajOptSettings(velocity_weight=0.05, acceleration_weight=0.05, jerk_weight=1.0, free_duration=False,
                         tolerance=3e-3, line_search=1)
