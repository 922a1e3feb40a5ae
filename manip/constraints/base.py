"""`Constraint`: a condition on the whole configuration q that a plan keeps over its continuous motion.

The interface (mink's Task/Limit style: a constraint is a few pure functions of q; the
planner composes them). A new constraint (e.g. a relative pose of two links) implements
five methods and one attribute, and every planner stage then keeps it, without reading the
planner:

- `unit` ("rad", "m", ...): the unit of its residual rows.
- `check(kinematics)`: raise `UnknownNameError` / `InvalidInputError` when the constraint
  does not fit the robot (an unknown link); called once per plan.
- `residual(kinematics, Q)`: (N, m) rows, each <= 0 where the constraint holds at Q (N, dof)
  [unit]. Its *violation* is the largest row (`violation`): > 0 outside the allowed set,
  <= 0 inside, and how far inside.
- `jacobian(kinematics, Q)`: (N, m, dof) d residual / dq [unit/rad] (for the path search's
  projection onto the allowed set and the optimiser's linearised rows).
- `segment_bound(kinematics, Q0, Q1)`: (M,) a bound L of how fast every row can change
  along the straight joint-space segment q(t) = Q0 + t (Q1 - Q0), t in [0, 1]:
  |r(q(t)) - r(q(s))| <= L |t - s| for every row r. It must hold for the continuous motion,
  from the per-joint displacement |Q1 - Q0| and the robot's geometry (as the collision
  certificate bounds how far a link can move, `manip.collision.certify`); the certificate
  (`manip.constraints.certify`) then proves the violation stays <= 0 between samples:
  max over t <= (v0 + v1 + L) / 2, bisecting the segment until that closes.
- optionally `residual_and_jacobian(kinematics, Q)`: both at once (one kinematics pass; the
  projection calls it).
- optionally `optimizer_rows(kinematics, Q)`: the rows the trajectory optimiser linearises
  (default: the residual's). A residual that curves sharply in q (a cone's angle) can give
  smoother rows whose set lies inside the constraint's (`OrientationConstraint`: flat faces
  of a polygon inside its cone), so the optimiser's linear model holds over longer steps.
- `margin`: how far inside the set [unit] the planner aims (projections land there; the
  optimiser's rows keep it), so that short straight segments between such configurations
  certify without bisection. A fraction of the tolerance.
- optionally `project_alone` / `hold_alone`: the projection onto its set and the certificate
  of segments for this constraint alone in one compiled call (`OrientationConstraint`'s:
  `tilt_kernels`); the generic NumPy versions run otherwise.
- `explain(kinematics, q)`: a one-line description of the constrained quantity at q (dof,)
  with its tolerance, for messages ("tilt 0.23 rad of panda_hand's axis ... > 0.1 rad").

Constraints are immutable values (frozen dataclasses); `link=None` means the robot's
end-effector (`kinematics.config.ee_link`), resolved at each call. For the bound, this
module has `revolute_chain_weights` (a frame turns at most sum_k w_k |dq_k|) and
`reach_weights` (a frame's origin moves at most sum_k rho_k |dq_k|); a quantity relative to
two frames (a relative pose of two links) changes only through the joints that move one
and not the other (the chains' symmetric difference), by at most the sum of both bounds.
`OrientationConstraint` (`orientation.py`) and `PositionConstraint` (`position.py`) are the
worked examples; their tests (`tests/constraints/`) check the residual, the Jacobian against
finite differences and the bound along random segments.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from manip.kinematics import Kinematics


class Constraint(ABC):
    """A condition on the configuration that holds over the whole continuous motion.

    Attributes:
        unit: the unit of the residual rows ("rad", "m").
    """

    unit: str = ""

    @abstractmethod
    def check(self, kinematics: Kinematics) -> None:
        """Raise when the constraint does not fit the robot (e.g. `UnknownNameError` for a link)."""

    @abstractmethod
    def residual(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        """(N, m) rows, each <= 0 where the constraint holds at Q (N, dof) [unit]."""

    @abstractmethod
    def jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        """(N, m, dof) the rows' derivatives with respect to q [unit/rad] at Q (N, dof)."""

    @abstractmethod
    def segment_bound(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) bound L on every row's rate along Q0[i] -> Q1[i] (M, dof): |r(t) - r(s)| <= L |t - s|."""

    @property
    @abstractmethod
    def margin(self) -> float:
        """How far inside the allowed set [unit] the planner aims (> 0)."""

    @abstractmethod
    def explain(self, kinematics: Kinematics, q: np.ndarray) -> str:
        """The constrained quantity at q (dof,) and its tolerance, in words."""

    def residual_and_jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(residual (N, m), jacobian (N, m, dof)) at Q (N, dof); override to share the kinematics."""
        return self.residual(kinematics, Q), self.jacobian(kinematics, Q)

    def optimizer_rows(self, kinematics: Kinematics, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rows (N, k), jacobian (N, k, dof)) at Q (N, dof) for the trajectory optimiser's
        linearised constraint rows [unit]: wherever every row is <= 0 the constraint holds (an
        inner approximation of its set is fine; the certificate judges the result). Default:
        `residual_and_jacobian`."""
        return self.residual_and_jacobian(kinematics, Q)

    def project_alone(self, kinematics: Kinematics, q: np.ndarray, max_steps: int, damping: float):
        """Optional: `constraints.project([self], ...)` of q (dof,) in one compiled call ((dof,) or
        None); NotImplemented (the default): the generic projection runs."""
        return NotImplemented

    def hold_alone(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray, slack: np.ndarray):
        """Optional: the certificate of segments Q0[i] -> Q1[i] (M, dof) for this constraint with
        slack (M,) [unit] in one compiled call: (ok, bad, worst, evaluations) as
        `constraints.certify`'s; NotImplemented (the default): the generic proof runs."""
        return NotImplemented

    def at_start(self, kinematics: Kinematics, q: np.ndarray) -> Constraint:
        """This constraint for a plan that starts at q (dof,): itself, unless it refers to the
        start (`RelativePoseConstraint` holds the relative pose it has there)."""
        return self

    def violation(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        """(N,) the largest residual row at each of Q (N, dof) [unit]: > 0 outside the set."""
        return self.residual(kinematics, np.atleast_2d(Q)).max(axis=1)


def link_or_ee(link: str | None, kinematics: Kinematics) -> str:
    """`link`, or the robot's end-effector link when None."""
    return kinematics.config.ee_link if link is None else link


def revolute_chain_weights(kinematics: Kinematics, frame_id: int) -> np.ndarray:
    """(dof,) 1 for the revolute joints that move frame `frame_id`, else 0: a frame's rotation
    angle along a straight joint-space segment is at most sum_k w_k |dq_k| (each revolute
    joint turns it about a unit axis; prismatic joints do not turn it)."""
    chain, _, revolute, *_ = kinematics.jacobian_tables(frame_id)
    w = np.zeros(kinematics.dof)
    for j in chain:
        if revolute[j - 1]:
            w[kinematics.joint_specs[j - 1].q_index] = 1.0
    return w


def reach_weights(kinematics: Kinematics, frame_id: int) -> np.ndarray:
    """(dof,) rho_k [m] bounding, over every configuration, the distance from the axis of joint
    k to the origin of frame `frame_id` (0 for joints that do not move it; 1 for a prismatic
    joint, whose motion moves it by |dq_k|): its origin moves at most sum_k rho_k |dq_k| along
    a straight joint-space segment. rho_k sums the fixed offsets between the joints from k to
    the frame (the triangle inequality), plus the reach of the prismatic joints among them."""
    chain, _, revolute, f_joint, _, f_p = kinematics.jacobian_tables(frame_id)
    specs = kinematics.joint_specs
    lower, upper = kinematics.lower, kinematics.upper
    w = np.zeros(kinematics.dof)
    reach = float(np.linalg.norm(f_p))  # from the frame's joint to the frame
    for j in chain:  # from the frame's joint towards the base
        spec = specs[j - 1]
        if revolute[j - 1]:
            w[spec.q_index] = reach
        else:
            w[spec.q_index] = 1.0
            reach += max(abs(lower[spec.q_index]), abs(upper[spec.q_index]))
        reach += float(np.linalg.norm(spec.p_placement))
    return w
