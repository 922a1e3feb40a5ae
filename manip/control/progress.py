"""Progress detection of the reactive controller: a still target the frame no longer approaches.

A reactive step only descends locally: in a local minimum (the arm against its own
self-collision margins, an obstacle in the way, a target out of reach) every QP is still
solved while the frame stops approaching the target, or is even led away from it.
`ProgressMonitor` watches the errors the steps report: when, for a target that stays
within `still_distance` of where it was, neither the position error fell by
`min_position_progress` nor the orientation error by `min_orientation_progress` below the
best so far over `stall_time` seconds of steps, and the target is not reached, the step is
reported `StepStatus.STALLED`. A target that moves starts a new window.
"""

from __future__ import annotations

import numpy as np

from manip.validation import positive


class ProgressMonitor:
    """Whether the controlled frame still approaches a still target.

    Args:
        stall_time: time without progress [s] after which steps are reported stalled (> 0).
        reached_position: position error [m] at or below which the target counts as reached
            (default 1 mm; with `reached_orientation`, a reached target never stalls).
        reached_orientation: orientation error [rad] counted as reached (default 0.01).
        min_position_progress: the smallest decrease of the position error [m] counted as
            progress (default 1 mm).
        min_orientation_progress: the same for the orientation error [rad] (default 0.01).
        still_distance: a target moved more than this [m] (or rotated more than 10 times
            this in rad) since the window started starts a new window (default 1 mm).
    """

    def __init__(self, stall_time: float, *, reached_position: float = 1e-3, reached_orientation: float = 0.01,
                 min_position_progress: float = 1e-3, min_orientation_progress: float = 0.01,
                 still_distance: float = 1e-3):
        self.stall_time = positive(stall_time, "stall_time", "s")
        self._reached = (reached_position, reached_orientation)
        self._min_progress = (min_position_progress, min_orientation_progress)
        self._still = still_distance
        self.reset()

    def reset(self) -> None:
        """Forget the target and the errors (a new window starts at the next update)."""
        self._target: tuple[np.ndarray, np.ndarray | None] | None = None
        self._best = (np.inf, np.inf)
        self._idle = 0.0

    def _moved(self, position: np.ndarray, orientation: np.ndarray | None) -> bool:
        if self._target is None:
            return True
        p0, o0 = self._target
        if (o0 is None) != (orientation is None) or float(np.linalg.norm(position - p0)) > self._still:
            return True
        if orientation is None:
            return False
        angle = 2.0 * np.arccos(min(abs(float(o0 @ orientation)), 1.0))
        return angle > 10.0 * self._still

    def update(self, position: np.ndarray, orientation: np.ndarray | None, position_error: float,
               orientation_error: float, dt: float) -> bool:
        """Record one step towards the target (position (3,) [m], orientation (4,) wxyz or
        None) with the errors at its start [m, rad]; True if the frame has stalled."""
        if self._moved(position, orientation):
            self._target = (np.array(position, dtype=float), None if orientation is None else
                            np.array(orientation, dtype=float))
            self._best = (position_error, orientation_error)
            self._idle = 0.0
            return False
        if position_error <= self._reached[0] and orientation_error <= self._reached[1]:
            self._idle = 0.0
            return False
        best_p, best_o = self._best
        progress = (position_error <= best_p - self._min_progress[0]
                    or orientation_error <= best_o - self._min_progress[1])
        if progress:
            self._best = (min(best_p, position_error), min(best_o, orientation_error))
            self._idle = 0.0
            return False
        self._idle += dt
        return self._idle >= self.stall_time
