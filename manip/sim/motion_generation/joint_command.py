"""`JointCommand`: the joint command a reactive controller integrates from frame to frame.

Shared by `RmpFlow` and `manip.sim.RMPFlowController`. manip's QP controller takes each step
from a joint configuration. Starting every step from the measured joints of a simulated
robot makes the command follow the drives' sag: position drives without gravity
compensation settle below their command, so a command rebuilt from the measurement sinks
frame after frame (into an obstacle below the arm, when the collision limit caps the
correction; measured in tests/sim/motion_generation/test_rmpflow_api.py). So the command is
integrated: each step starts from the last command, and from the measured state only on
the first step, after `reset()`, or when the robot is more than `resync_tolerance` from the
command (blocked, teleported, moved by hand).
"""

from __future__ import annotations

import numpy as np

from manip.validation import positive


class JointCommand:
    """The last joint command, and when to start again from the measurement.

    Args:
        resync_tolerance: largest gap [rad] between the command and the measured joints
            before a step starts from the measurement; None: never (after the first step).
    """

    def __init__(self, resync_tolerance: float | None = 0.1):
        self.resync_tolerance = None if resync_tolerance is None else positive(resync_tolerance, "resync_tolerance",
                                                                              "rad")
        self.positions: np.ndarray | None = None
        self.velocities: np.ndarray | None = None

    def reset(self) -> None:
        """Forget the command (the next step starts from the measurement)."""
        self.positions = None
        self.velocities = None

    def start(self, measured_positions: np.ndarray, measured_velocities: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray | None]:
        """(positions to step from, velocities for the controller's acceleration limit) for this
        step: the measured state, or the last command."""
        q = np.asarray(measured_positions, dtype=float)
        tol = self.resync_tolerance
        if self.positions is None or (tol is not None and np.max(np.abs(q - self.positions), initial=0.0) > tol):
            self.positions = q.copy()
            self.velocities = np.asarray(measured_velocities, dtype=float).copy()
        return self.positions, self.velocities

    def update(self, positions: np.ndarray, velocities: np.ndarray) -> None:
        """Record the step's command."""
        self.positions = np.asarray(positions, dtype=float).copy()
        self.velocities = np.asarray(velocities, dtype=float).copy()


__all__ = ["JointCommand"]
