"""`PositionConstraint`: a link's origin kept inside a world-frame box."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manip.constraints.base import Constraint, link_or_ee, reach_weights
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.validation import as_real_array

#: Share of the box's smallest half-extent the planner aims inside (`Constraint.margin`), at most MAX_MARGIN.
MARGIN_FRACTION = 0.3
MAX_MARGIN = 0.02  # [m]


@dataclass(frozen=True)
class PositionConstraint(Constraint):
    """`link`'s origin stays in the box lower <= p <= upper (world frame) over the whole motion.

    Residual rows (6): p - upper and lower - p [m]; the violation (their largest) is the
    signed distance to the box in the L-inf sense (> 0 outside, the depth inside).

    Args:
        lower: (3,) the box's lower corner [m] (-inf: unbounded along that axis).
        upper: (3,) the box's upper corner [m] (+inf: unbounded), upper > lower.
        link: the constrained frame; None = the robot's end-effector.

    Raises:
        InvalidInputError: wrong shapes, NaN, or upper <= lower on an axis.
    """

    lower: tuple = (-np.inf, -np.inf, -np.inf)
    upper: tuple = (np.inf, np.inf, np.inf)
    link: str | None = None
    unit = "m"

    def __post_init__(self) -> None:
        lo, hi = _corner(self.lower, "lower"), _corner(self.upper, "upper")
        if np.any(hi <= lo):
            axis = "xyz"[int(np.argmax(hi <= lo))]
            raise InvalidInputError(f"upper must be > lower on every axis; along {axis}: lower {lo.tolist()}, "
                                    f"upper {hi.tolist()} (a box of zero thickness cannot be kept over a motion)")
        object.__setattr__(self, "lower", tuple(lo.tolist()))
        object.__setattr__(self, "upper", tuple(hi.tolist()))
        if self.link is not None and (not isinstance(self.link, str) or not self.link):
            raise InvalidInputError(f"link must be a frame name (a non-empty str) or None; got {self.link!r}")

    def check(self, kinematics: Kinematics) -> None:
        kinematics.frame_id(link_or_ee(self.link, kinematics), "PositionConstraint link")

    def position(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        """(N, 3) the link's origin [m] at Q (N, dof)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        if Q.shape[0] <= 16:  # one compiled call: cheaper for a few configurations
            return kinematics.frame_jacobians(Q, fid)[1]
        return kinematics.frame_transforms(Q, [fid])[1][:, 0]

    def residual(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        p = self.position(kinematics, Q)
        return np.concatenate([p - np.asarray(self.upper), np.asarray(self.lower) - p], axis=1)

    def jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        Jv = kinematics.frame_jacobians(Q, fid)[2][:, 0:3]
        return np.concatenate([Jv, -Jv], axis=1)

    def segment_bound(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        # the origin's speed is at most sum_k rho_k |q_k'| (`reach_weights`); each row is a coordinate
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        return np.abs(np.atleast_2d(Q1) - np.atleast_2d(Q0)) @ reach_weights(kinematics, fid)

    @property
    def margin(self) -> float:
        half = 0.5 * (np.asarray(self.upper) - np.asarray(self.lower))
        return float(min(MAX_MARGIN, MARGIN_FRACTION * np.min(half)))

    def explain(self, kinematics: Kinematics, q: np.ndarray) -> str:
        p = self.position(kinematics, q)[0]
        v = float(self.violation(kinematics, q)[0])
        where = f"{v:.4g} m outside" if v > 0 else f"{-v:.4g} m inside"
        return (f"{link_or_ee(self.link, kinematics)} at ({p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g}) m is {where} the box "
                f"{_fmt(self.lower)} .. {_fmt(self.upper)} m")


def _corner(value, what: str) -> np.ndarray:
    a = as_real_array(value, what)
    if a.shape != (3,):
        raise InvalidInputError(f"{what} must have shape (3,) (x, y, z) [m]; got {a.shape}")
    if np.any(np.isnan(a)):
        raise InvalidInputError(f"{what} must not hold NaN (use -inf / inf for an unbounded axis); got {a.tolist()}")
    return a.astype(float).copy()


def _fmt(v) -> str:
    return "(" + ", ".join(f"{x:.3g}" for x in v) + ")"
