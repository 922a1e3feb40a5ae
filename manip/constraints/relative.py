"""`RelativePoseConstraint`: the pose of one link in another's frame held (two hands carrying one box).

The relative pose T_ab(q) = T_a(q)^-1 T_b(q) of `link_b` in `link_a`'s frame stays within
`position_tolerance` [m] and `rotation_tolerance` [rad] of its value at the start of the plan
(`Constraint.at_start` binds it; or give `reference`), over the whole continuous motion.

Residual rows (2), each a fraction of its tolerance so that one margin fits both:
|p_ab - p_ref| / position_tolerance - 1 and angle(R_ref^T R_ab) / rotation_tolerance - 1.

Derivatives and bounds (world-aligned Jacobians [v; w] of both frames):

- d p_ab = R_a^T (v_b - v_a + [p_b - p_a]x w_a): a joint moving both frames moves them
  rigidly together and changes nothing; one moving only b moves b's origin by at most its
  reach rho_k^b |dq_k| (`reach_weights`); one moving only a turns b's origin about its axis,
  at most (|p_b - p_a| + rho_k^a) |dq_k|, with |p_b - p_a| <= its value at the segment's
  start plus both origins' largest displacement over the segment (sum (rho^a + rho^b) |dq|).
- d angle(R_err) = u . R_b^T (w_b - w_a) with u the unit axis of R_err (the right-perturbation
  derivative of the angle), so the angle changes at most sum |dq_k| over the revolute joints
  moving one frame and not the other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from manip import quaternion as quat
from manip.constraints.base import Constraint, reach_weights
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.pose import Pose

#: Share of each tolerance the planner aims inside (`Constraint.margin`, a fraction: the rows are fractions).
MARGIN_FRACTION = 0.3


def _tolerance(value, what: str, unit: str) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"{what} must be a positive number [{unit}]; got {value!r}")
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise InvalidInputError(f"{what} must be a positive finite number [{unit}]; got {value!r} (an exact relative "
                                "pose, tolerance 0, cannot be certified over a continuous motion)")
    return v


@dataclass(frozen=True)
class RelativePoseConstraint(Constraint):
    """`link_b`'s pose in `link_a`'s frame stays within the tolerances of its value at the start.

    Args:
        link_a: the reference frame (e.g. "left_panda_hand").
        link_b: the held frame (e.g. "right_panda_hand").
        position_tolerance: largest change of link_b's origin in link_a's frame [m].
        rotation_tolerance: largest rotation of link_b relative to link_a [rad], in (0, pi).
        reference: the relative pose to hold; None (the default): its value at the plan's start.

    Raises:
        InvalidInputError: names that are not non-empty distinct strings, tolerances that are
            not positive, a reference that is not a single Pose.
    """

    link_a: str
    link_b: str
    position_tolerance: float = 0.005
    rotation_tolerance: float = 0.02
    reference: Pose | None = None
    unit = "fraction of the tolerance"

    def __post_init__(self) -> None:
        for what in ("link_a", "link_b"):
            v = getattr(self, what)
            if not isinstance(v, str) or not v:
                raise InvalidInputError(f"{what} must be a frame name (a non-empty str); got {v!r}")
        if self.link_a == self.link_b:
            raise InvalidInputError(f"link_a and link_b must be two different frames; got '{self.link_a}' twice")
        object.__setattr__(self, "position_tolerance", _tolerance(self.position_tolerance, "position_tolerance", "m"))
        rot = _tolerance(self.rotation_tolerance, "rotation_tolerance", "rad")
        if rot >= math.pi:
            raise InvalidInputError(f"rotation_tolerance must be in (0, pi) [rad]; got {rot!r}")
        object.__setattr__(self, "rotation_tolerance", rot)
        if self.reference is not None and (not isinstance(self.reference, Pose) or self.reference.is_batch):
            raise InvalidInputError(f"reference must be a single manip.Pose or None; got {self.reference!r}")

    # ------------------------------------------------------------------ the interface
    def check(self, kinematics: Kinematics) -> None:
        kinematics.frame_id(self.link_a, "RelativePoseConstraint link_a")
        kinematics.frame_id(self.link_b, "RelativePoseConstraint link_b")

    def at_start(self, kinematics: Kinematics, q: np.ndarray) -> RelativePoseConstraint:
        """This constraint holding the relative pose at `q` (dof,) (unless it has a reference)."""
        self.check(kinematics)
        return self if self.reference is not None else replace(self, reference=self.relative_pose(kinematics, q))

    def relative_pose(self, kinematics: Kinematics, q: np.ndarray) -> Pose:
        """link_b's pose in link_a's frame at q (dof,)."""
        return kinematics.fk(q, self.link_a).inverse() @ kinematics.fk(q, self.link_b)

    def _frames(self, kinematics: Kinematics, Q: np.ndarray):
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fa = kinematics.frame_id(self.link_a)
        fb = kinematics.frame_id(self.link_b)
        R, p = kinematics.frame_transforms(Q, [fa, fb])
        return Q, R[:, 0], p[:, 0], R[:, 1], p[:, 1]

    def _errors(self, kinematics: Kinematics, Q: np.ndarray):
        """(e_p (N, 3) [m] in frame a, angle (N,) [rad], R_err (N, 3, 3), frames)."""
        if self.reference is None:
            raise InvalidInputError("RelativePoseConstraint has no reference pose: give it through a plan's "
                                    "constraints= (bound to the start) or give reference=")
        Q, Ra, pa, Rb, pb = self._frames(kinematics, Q)
        p_ab = np.einsum("nji,nj->ni", Ra, pb - pa)
        R_ab = np.einsum("nji,njk->nik", Ra, Rb)
        R_ref = quat.to_matrix(self.reference.quaternion)
        R_err = np.einsum("ji,njk->nik", R_ref, R_ab)
        cos = np.clip((np.trace(R_err, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
        axis_s = np.stack([R_err[:, 2, 1] - R_err[:, 1, 2], R_err[:, 0, 2] - R_err[:, 2, 0],
                           R_err[:, 1, 0] - R_err[:, 0, 1]], axis=1) / 2.0   # sin(angle) u
        angle = np.arctan2(np.linalg.norm(axis_s, axis=1), cos)
        return p_ab - self.reference.position, angle, axis_s, (Ra, pa, Rb, pb)

    def residual(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        e_p, angle, _, _ = self._errors(kinematics, Q)
        return np.stack([np.linalg.norm(e_p, axis=1) / self.position_tolerance - 1.0,
                         angle / self.rotation_tolerance - 1.0], axis=1)

    def jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        e_p, angle, axis_s, (Ra, pa, Rb, pb) = self._errors(kinematics, Q)
        Ja = kinematics.frame_jacobians(Q, kinematics.frame_id(self.link_a))[2]
        Jb = kinematics.frame_jacobians(Q, kinematics.frame_id(self.link_b))[2]
        d = pb - pa
        cross_d = np.zeros((len(Q), 3, 3))   # [d]x
        cross_d[:, 0, 1], cross_d[:, 0, 2], cross_d[:, 1, 2] = -d[:, 2], d[:, 1], -d[:, 0]
        cross_d[:, 1, 0], cross_d[:, 2, 0], cross_d[:, 2, 1] = d[:, 2], -d[:, 1], d[:, 0]
        dp = np.einsum("nji,njk->nik", Ra, Jb[:, :3] - Ja[:, :3] + cross_d @ Ja[:, 3:])
        n_p = np.linalg.norm(e_p, axis=1, keepdims=True)
        g_p = np.where(n_p > 1e-12, e_p / np.maximum(n_p, 1e-12), 0.0)   # zero gradient at zero error
        s = np.linalg.norm(axis_s, axis=1, keepdims=True)
        u = np.where(s > 1e-12, axis_s / np.maximum(s, 1e-12), 0.0)
        dw = np.einsum("nji,njk->nik", Rb, Jb[:, 3:] - Ja[:, 3:])      # relative angular velocity in frame b
        rows = [np.einsum("ni,nik->nk", g_p, dp) / self.position_tolerance,
                np.einsum("ni,nik->nk", u, dw) / self.rotation_tolerance]
        return np.stack(rows, axis=1)

    def segment_bound(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        Q0 = np.atleast_2d(np.asarray(Q0, dtype=float))
        dq = np.abs(np.atleast_2d(np.asarray(Q1, dtype=float)) - Q0)
        fa, fb = kinematics.frame_id(self.link_a), kinematics.frame_id(self.link_b)
        rho_a, rho_b = reach_weights(kinematics, fa), reach_weights(kinematics, fb)
        in_a, in_b = _moves(kinematics, fa), _moves(kinematics, fb)
        only_a, only_b = in_a & ~in_b, in_b & ~in_a
        revolute = np.array([bool(kinematics.joint_revolute[k]) for k in _joint_of_column(kinematics)])
        _, _, pa, _, pb = self._frames(kinematics, Q0)
        reach = np.linalg.norm(pb - pa, axis=1) + dq @ (rho_a + rho_b)       # |p_b - p_a| over the segment
        position = dq @ np.where(only_b, rho_b, 0.0) + (dq * only_a) @ rho_a + reach * (dq @ (only_a & revolute))
        rotation = dq @ ((only_a | only_b) & revolute).astype(float)
        return np.maximum(position / self.position_tolerance, rotation / self.rotation_tolerance)

    @property
    def margin(self) -> float:
        return MARGIN_FRACTION

    def explain(self, kinematics: Kinematics, q: np.ndarray) -> str:
        if self.reference is None:
            return f"{self.link_b} relative to {self.link_a}: no reference pose yet"
        e_p, angle, _, _ = self._errors(kinematics, q)
        return (f"{self.link_b} has moved {float(np.linalg.norm(e_p[0])) * 1e3:.3g} mm and turned "
                f"{float(angle[0]):.4g} rad relative to {self.link_a} (tolerances "
                f"{self.position_tolerance * 1e3:.3g} mm, {self.rotation_tolerance:.4g} rad)")


def _joint_of_column(kinematics: Kinematics) -> list[int]:
    """For each column of q, the index (0-based, in `joint_specs`) of its joint."""
    out = [0] * kinematics.dof
    for j, spec in enumerate(kinematics.joint_specs):
        out[spec.q_index] = j
    return out


def _moves(kinematics: Kinematics, frame_id: int) -> np.ndarray:
    """(dof,) bool: the joints that move frame `frame_id`."""
    chain = kinematics.jacobian_tables(frame_id)[0]
    out = np.zeros(kinematics.dof, dtype=bool)
    for j in chain:
        out[kinematics.joint_specs[j - 1].q_index] = True
    return out
