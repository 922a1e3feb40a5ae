"""What a timing call returns: `TimingStatus` (with its hint table) and `TimingResult`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip.status import Status, truth_is_success
from manip.trajectory import Trajectory


class TimingStatus(Status):
    """Outcome of a timing call; `hint` says what it means and what to change."""

    SUCCESS = "success"
    DURATION_TOO_SHORT = "duration_too_short"
    RUCKIG_FAIL = "ruckig_fail"
    LIMIT_VIOLATION = "limit_violation"
    POSITION_LIMIT = "position_limit"
    DEVIATION_TOO_LARGE = "deviation_too_large"

    @classmethod
    def _hints(cls) -> dict:
        return _HINTS


_HINTS = {
    TimingStatus.SUCCESS: "the trajectory is within all limits, at rest at both ends and ends at the goal",
    TimingStatus.DURATION_TOO_SHORT: (
        "the requested duration is shorter than the fastest feasible one: see `minimum_duration`, "
        "or raise the velocity/acceleration/jerk scales"
    ),
    TimingStatus.RUCKIG_FAIL: (
        "ruckig could not compute a segment (should not happen for valid input): retry with mode='exact'"
    ),
    TimingStatus.LIMIT_VIOLATION: "the final verification failed (a bug: please report); retry with mode='exact'",
    TimingStatus.POSITION_LIMIT: (
        "along_path: the curve through the points leaves a position limit; time the path in 'blend' mode"
    ),
    TimingStatus.DEVIATION_TOO_LARGE: (
        "along_path: the curve strays beyond deviation_tolerance; raise it or time the path in 'blend' mode"
    ),
}


@dataclass(frozen=True, eq=False)
class TimingResult:
    """Result of `time_parameterize`, `time_parameterize_dense` and `time_path`.

    Attributes:
        success: True iff `trajectory` is valid (within all limits, at rest at both ends,
            ending exactly at the last waypoint).
        status: why it failed, if it did (`status.hint` says what to change).
        trajectory: the timed trajectory, or None on failure.
        mode: "exact" or "blend" (`time_parameterize`), "along_path" (`time_parameterize_dense`).
        minimum_duration: duration of the fastest trajectory found for this mode and these
            (scaled) limits [s], before stretching to `duration` / a multiple of `dt`.
        max_deviation: largest joint-space distance between the timed motion and the
            input path (the polyline through the given waypoints) [rad], Euclidean (an
            upper bound of the L-inf distance), measured at the samples and every
            <= 10 ms; ~0 in exact mode, <= `deviation_tolerance` in blend mode. In
            along_path mode: how far the spline strays from the polyline between the
            points it passes through (each piece vs. its chord, 17 samples per piece).
        waypoints: (K', dof) the waypoints used (duplicates and collinear points removed) [rad].
        waypoint_velocities: (K', dof) velocity at each waypoint [rad/s] (after time scaling).
        segment_durations: (K' - 1,) time between consecutive waypoints [s] (after scaling).
        compute_time: wall-clock time spent [s].
        message: human-readable detail.
    """

    __bool__ = truth_is_success   # `if result:` tests `.success` (not the object)

    success: bool
    status: TimingStatus
    trajectory: Trajectory | None
    mode: str
    minimum_duration: float
    max_deviation: float
    waypoints: np.ndarray
    waypoint_velocities: np.ndarray
    segment_durations: np.ndarray
    compute_time: float
    message: str = ""
