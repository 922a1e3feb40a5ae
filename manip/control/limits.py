"""Joint position, velocity and acceleration limits as bounds on the step's displacement dq.

The same constraints as mink's `ConfigurationLimit` and `VelocityLimit`, written as the
QP's variable bounds lb <= dq <= ub instead of 2 x 2 x dof inequality rows (the solvers
handle bounds natively, and the step is faster):

    lb = max(-v_max dt, gain (q_min - q)),    ub = min(v_max dt, gain (q_max - q))

With gain < 1 a joint approaches its limit geometrically and never crosses it. A joint
already outside its range (a simulated arm overshooting by a hair) is brought back at up
to its velocity limit, so the bounds are never contradictory.

Acceleration limits (optional) need the joint velocities v0 at the start of the step:

    v0 dt - a_max dt^2 <= dq <= v0 dt + a_max dt^2

intersected with the bounds above; where they conflict the position and velocity limits
win (the acceleration limit is then exceeded rather than a joint limit).
"""

from __future__ import annotations

import numpy as np

from manip.limits import JointLimits


class StepBounds:
    """The displacement bounds of one control step from a robot's `manip.JointLimits`.

    Args:
        limits: the joints' position [rad], velocity [rad/s] and acceleration [rad/s^2]
            limits (already scaled by the controller's factors).
        gain: fraction of the remaining range a joint may use per step, (0, 1].
        use_acceleration: bound the step by the acceleration limits too (when `v0` is given).
    """

    def __init__(self, limits: JointLimits, gain: float, *, use_acceleration: bool):
        self.limits = limits
        self.gain = float(gain)
        self.use_acceleration = bool(use_acceleration)

    def bounds(self, q: np.ndarray, dt: float, v0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(lb, ub), (dof,) each: the displacement bounds of a step of `dt` [s] from `q`
        (with acceleration limits if `use_acceleration` and `v0` is given)."""
        lim = self.limits
        step = lim.velocity * dt
        lb = np.maximum(-step, self.gain * (lim.lower - q))
        ub = np.minimum(step, self.gain * (lim.upper - q))
        # Outside the range by more than one step can fix: move back as fast as allowed.
        np.minimum(lb, step, out=lb)
        np.maximum(ub, -step, out=ub)
        if self.use_acceleration and v0 is not None:
            reach = lim.acceleration * dt * dt
            centre = v0 * dt
            lb_a = np.minimum(np.maximum(lb, centre - reach), ub)
            ub_a = np.maximum(np.minimum(ub, centre + reach), lb)
            lb, ub = lb_a, ub_a
        return lb, ub

    def clamp(self, q: np.ndarray, dq: np.ndarray, dt: float) -> np.ndarray:
        """q + dq with dq inside the velocity bounds and the result inside the position
        limits (or no farther outside than `q` was): removes the QP solver's tolerance."""
        lim = self.limits
        step = lim.velocity * dt
        q_next = q + np.maximum(np.minimum(dq, step), -step)
        return np.maximum(np.minimum(q_next, np.maximum(lim.upper, q)), np.minimum(lim.lower, q))
