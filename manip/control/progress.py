"""Progress detection of the reactive controller: a frame that no longer approaches its target.

A reactive step only descends locally: in a local minimum (the arm against its own
self-collision margins, an obstacle in the way, a target out of reach) every QP is still
solved while the frame stops approaching the target, or is even led away from it.
`ProgressMonitor` adds up, over the last `stall_time` seconds of steps, how much each step
brought the frame closer to that step's target (its error at the start of the step minus
its error, towards the same target, where the next step starts: the arm's configuration,
which may lag the command in a simulation): when neither the position
errors fell by `min_position_progress` in all nor the orientation errors by
`min_orientation_progress` (each, or a tenth of the current error if less), and the target
is not reached, the step is reported `StepStatus.STALLED`, and the following steps too
until the window shows ten times that progress (or half the error). Each step is judged against its
own target, so a moving target that the arm follows (each step closes on it) does not
stall, while an arm held back, led away, or oscillating in place does.
"""

from __future__ import annotations

from collections import deque

from manip.validation import positive


class ProgressMonitor:
    """Whether the controlled frame still approaches its target.

    Args:
        stall_time: time without progress [s] after which steps are reported stalled (> 0).
        reached_position: position error [m] at or below which the target counts as reached
            (default 1 mm; with `reached_orientation`, a reached target never stalls).
        reached_orientation: orientation error [rad] counted as reached (default 0.01).
        min_position_progress: the decrease of the position error [m] over `stall_time`
            that counts as progress (default 1 mm; a tenth of the error when that is less).
        min_orientation_progress: the same for the orientation error [rad] (default 0.01).
    """

    def __init__(self, stall_time: float, *, reached_position: float = 1e-3, reached_orientation: float = 0.01,
                 min_position_progress: float = 1e-3, min_orientation_progress: float = 0.01):
        self.stall_time = positive(stall_time, "stall_time", "s")
        self._reached = (reached_position, reached_orientation)
        self._min_progress = (min_position_progress, min_orientation_progress)
        self.reset()

    def reset(self) -> None:
        """Forget the steps so far (a new window starts)."""
        self._steps: deque[tuple[float, float, float]] = deque()  # (dt [s], position [m], orientation [rad] gains)
        self._span = 0.0  # time the window covers [s]
        self._gain = [0.0, 0.0]  # the window's summed gains
        self._stalled = False

    def update(self, errors_before: tuple[float, float], errors_after: tuple[float, float], dt: float) -> bool:
        """Record one step: the (position [m], orientation [rad]) errors towards its target at
        its start and where the next step starts, and its duration [s]. True if the frame
        has stalled."""
        gp, go = errors_before[0] - errors_after[0], errors_before[1] - errors_after[1]
        self._steps.append((dt, gp, go))
        self._span += dt
        self._gain[0] += gp
        self._gain[1] += go
        while len(self._steps) > 1 and self._span - self._steps[0][0] >= self.stall_time:
            old = self._steps.popleft()
            self._span -= old[0]
            self._gain[0] -= old[1]
            self._gain[1] -= old[2]
        p, o = errors_before
        if (p <= self._reached[0] and o <= self._reached[1]) or self._span < self.stall_time - 1e-9:
            self._stalled = False
            return False
        # an error already within its reached tolerance (e.g. the orientation of a
        # position-only target, always 0) shows no progress. Once stalled, it takes ten times
        # the progress (or half the error) to resume: an arm oscillating in place stays stalled.
        k = 10.0 if self._stalled else 1.0
        cap = 0.5 if self._stalled else 0.1
        moved_p = p > self._reached[0] and self._gain[0] >= min(k * self._min_progress[0], cap * p)
        moved_o = o > self._reached[1] and self._gain[1] >= min(k * self._min_progress[1], cap * o)
        self._stalled = not (moved_p or moved_o)
        return self._stalled
