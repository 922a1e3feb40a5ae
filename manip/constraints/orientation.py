"""`OrientationConstraint`: a link's axis kept within a tolerance of a world direction (keep a cup upright)."""

from __future__ import annotations

import functools
import math
import weakref
from dataclasses import dataclass

import numpy as np

from manip.constraints import certify
from manip.constraints.base import Constraint, link_or_ee, revolute_chain_weights
from manip.constraints.tilt_kernels import hold_tilt, project_tilt
from manip.errors import InvalidInputError
from manip.jit import kernel_array
from manip.kinematics import Kinematics
from manip.validation import vec

#: Share of the tolerance the planner aims inside the cone (`Constraint.margin`).
MARGIN_FRACTION = 0.3
#: Faces of the polygon inside the cone that the trajectory optimiser keeps (`optimizer_rows`).
OPTIMIZER_FACES = 16
#: Faces nearest the link's axis given to the optimiser at each configuration.
OPTIMIZER_ROWS = 1
#: Tolerances up to this [rad] use the polygon's faces in the optimiser; wider cones, the angle.
OPTIMIZER_FACES_MAX_TOLERANCE = math.pi / 4


def unit_vector(value, what: str) -> np.ndarray:
    """(3,) a unit vector: a finite 3-vector whose norm is within 1e-3 of 1 (then normalised).

    Raises:
        InvalidInputError: naming `what`: wrong shape, non-finite, zero or not unit.
    """
    v = vec(value, 3, what)
    n = float(np.linalg.norm(v))
    if n == 0.0:
        raise InvalidInputError(f"{what} must be a unit vector (x, y, z); got the zero vector")
    if abs(n - 1.0) > 1e-3:
        raise InvalidInputError(f"{what} must be a unit vector (norm within 1e-3 of 1); got {v.tolist()} of norm "
                                f"{n:.6g}: pass {what} / |{what}|")
    return v / n


@dataclass(frozen=True)
class OrientationConstraint(Constraint):
    """The unit vector `axis` of `link`'s frame stays within `tolerance` of the world's `direction`.

    The tilt theta(q) = angle(R_link(q) axis, direction) [rad] stays <= tolerance over the
    whole continuous motion. Keep a cup upright: `axis=(0, 0, 1)` of the frame that holds the
    cup's axis, `direction=(0, 0, 1)`.

    Args:
        axis: (3,) unit vector in the link's frame.
        direction: (3,) unit vector in the world (base) frame.
        tolerance: largest tilt [rad], in (0, pi).
        link: the constrained frame; None = the robot's end-effector.

    Raises:
        InvalidInputError: a zero, non-unit or non-finite vector, a tolerance outside (0, pi).
    """

    axis: tuple = (0.0, 0.0, 1.0)
    direction: tuple = (0.0, 0.0, 1.0)
    tolerance: float = 0.1
    link: str | None = None
    unit = "rad"

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", tuple(unit_vector(self.axis, "axis").tolist()))
        object.__setattr__(self, "direction", tuple(unit_vector(self.direction, "direction").tolist()))
        tol = self.tolerance
        if isinstance(tol, (bool, np.bool_)) or not isinstance(tol, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"tolerance must be a number of radians in (0, pi); got {tol!r}")
        tol = float(tol)
        if not (math.isfinite(tol) and 0.0 < tol < math.pi):
            raise InvalidInputError(
                f"tolerance must be in (0, pi) [rad]; got {tol!r} (an exact orientation, tolerance 0, cannot be "
                "held by a continuous motion of most arms: give a small positive tolerance)")
        object.__setattr__(self, "tolerance", tol)
        if self.link is not None and (not isinstance(self.link, str) or not self.link):
            raise InvalidInputError(f"link must be a frame name (a non-empty str) or None; got {self.link!r}")
        # arrays the hot paths use (the projection and the certificate call them per configuration)
        d = np.array(self.direction)
        object.__setattr__(self, "_a", _frozen(np.array(self.axis)))
        object.__setattr__(self, "_d", _frozen(d))
        object.__setattr__(self, "_cross_d", _frozen(np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]],
                                                               [-d[1], d[0], 0.0]])))  # u @ it = u x d

    # ------------------------------------------------------------------ the interface
    def check(self, kinematics: Kinematics) -> None:
        kinematics.frame_id(link_or_ee(self.link, kinematics), "OrientationConstraint link")

    def tilt(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        """(N,) the angle [rad] between the link's axis and `direction` at Q (N, dof)."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        # up to ~a hundred configurations (the planner's and the certificate's usual calls): one
        # compiled call is cheaper than the batched transforms' NumPy steps
        R = kinematics.frame_jacobians(Q, fid)[0] if Q.shape[0] <= 128 else kinematics.frame_transforms(Q, [fid])[0][:, 0]
        # arccos: within 1e-8 rad of the exact angle here, and cheaper than atan2(|u x d|, u . d)
        return np.arccos(np.clip((R @ self._a) @ self._d, -1.0, 1.0))

    def residual(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        return (self.tilt(kinematics, Q) - self.tolerance)[:, None]

    def jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> np.ndarray:
        return self.residual_and_jacobian(kinematics, Q)[1]

    def residual_and_jacobian(self, kinematics: Kinematics, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # u' = w x u and cos(theta) = u . d give theta' = -n . w, n = (u x d) / |u x d|, w = J_w q'
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        R, _, J = kinematics.frame_jacobians(Q, fid)
        u = R @ self._a
        c = u @ self._cross_d  # u x d
        s = np.sqrt(np.einsum("ni,ni->n", c, c))
        n = c / np.maximum(s, 1e-12)[:, None]  # theta = 0 or pi: c = 0, a zero gradient
        theta = np.arctan2(s, u @ self._d)
        return (theta - self.tolerance)[:, None], -np.einsum("ni,nij->nj", n, J[:, 3:6])[:, None, :]

    def optimizer_rows(self, kinematics: Kinematics, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The faces of a regular polygon inside the cone, as rows e_k . u - s <= 0 (u the
        link's axis in the world, e_k OPTIMIZER_FACES unit vectors normal to `direction`,
        s = sin(tolerance) cos(pi / faces): the polygon's corners on the cone) and -u . d <= 0 (the
        cone's half of the sphere): where they hold, the tilt is within the tolerance.
        The tilt's angle is a cone whose curvature across the tilt is 1 / sin(tilt) (about 11
        per rad at 0.09 rad): the optimiser's linear model of it fails over a step of a few
        hundredths of a radian and its trust region collapses; a face is linear in u. Wider
        tolerances (> OPTIMIZER_FACES_MAX_TOLERANCE) use the angle."""
        if self.tolerance > OPTIMIZER_FACES_MAX_TOLERANCE:
            return self.residual_and_jacobian(kinematics, Q)
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        R, _, J = kinematics.frame_jacobians(Q, fid)
        u = R @ self._a  # (N, 3)
        E = _faces(self.direction, OPTIMIZER_FACES)  # (K, 3)
        s = math.sin(self.tolerance) * math.cos(math.pi / E.shape[0])
        # the OPTIMIZER_ROWS faces nearest u (the others are farther from it than its step can
        # go), and -u . d <= 0: the cone's half of the sphere
        near = np.argsort(-(u @ E.T), axis=1)[:, :OPTIMIZER_ROWS]  # (N, m)
        F = np.concatenate([E[near], np.broadcast_to(-self._d, (len(u), 1, 3))], axis=1)
        rows = np.einsum("nki,ni->nk", F, u)
        rows[:, :-1] -= s
        # d(f . u)/dq = f . (w x u) = (u x f) . w, w = J_w q'
        return rows, np.einsum("nki,nij->nkj", _cross_rows(u, F), J[:, 3:6])

    def segment_bound(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        return np.abs(np.atleast_2d(Q1) - np.atleast_2d(Q0)) @ tilt_weights(self, kinematics)

    def project_alone(self, kinematics: Kinematics, q: np.ndarray, max_steps: int, damping: float):
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        q, converged = project_tilt(kernel_array(q), kinematics.lower, kinematics.upper,
                                    *kinematics.fk_tables(), *kinematics.jacobian_tables(fid), self._a, self._d,
                                    self.tolerance, self.margin, damping, max_steps)
        return q if converged else None

    def hold_alone(self, kinematics: Kinematics, Q0: np.ndarray, Q1: np.ndarray, slack: np.ndarray):
        fid = kinematics.frame_id(link_or_ee(self.link, kinematics))
        f_joint, f_R = kinematics.jacobian_tables(fid)[3:5]
        return hold_tilt(kernel_array(Q0), kernel_array(Q1), kernel_array(slack), tilt_weights(self, kinematics),
                         *kinematics.fk_tables(), f_joint, f_R, self._a, self._d, self.tolerance,
                         certify.FIRST_SPLIT, certify.MAX_DEPTH)

    @property
    def margin(self) -> float:
        return MARGIN_FRACTION * self.tolerance

    def explain(self, kinematics: Kinematics, q: np.ndarray) -> str:
        theta = float(self.tilt(kinematics, q)[0])
        link = link_or_ee(self.link, kinematics)
        return (f"the tilt of {link}'s axis {_fmt(self.axis)} from {_fmt(self.direction)} is {theta:.4g} rad "
                f"({math.degrees(theta):.1f} deg; tolerance {self.tolerance:.4g} rad)")


def tilt_weights(c: OrientationConstraint, kinematics: Kinematics) -> np.ndarray:
    """(dof,) w such that the tilt changes at most sum_k w_k |dq_k| along a straight joint-space
    segment (a bound for every configuration, so it holds over the whole segment).

    theta' = -n . omega with n = (u x d) / |u x d| a unit vector normal to both u (the link's
    axis) and d (`direction`), omega = sum_k a_k q_k' (a_k: the world axis of revolute joint k,
    unit): so |theta'| <= sum_k |a_k . n| |q_k'|, and |a_k . n| <= 1. Two joints have a
    constant, smaller bound: the root joint (parent: the fixed world) has a constant world axis
    a, and n is normal to d, so |a . n| <= |a x d| (0 for a vertical first joint and an upright
    constraint); the frame's own parent joint has a constant axis a_f in the frame, and n is
    normal to u, so |a . n| <= |a_f x axis| (0 when the constrained axis is that joint's axis).
    """
    cache = _WEIGHTS.setdefault(kinematics, {})
    key = (c.link, c.axis, c.direction)
    if key in cache:
        return cache[key]
    fid = kinematics.frame_id(link_or_ee(c.link, kinematics))
    w = revolute_chain_weights(kinematics, fid)
    chain, _, revolute, f_joint, f_R, _ = kinematics.jacobian_tables(fid)
    specs = kinematics.joint_specs
    if len(chain):
        root = specs[int(chain[-1]) - 1]
        if root.revolute and root.parent == 0:  # its axis is fixed in the world
            a = np.asarray(root.R_placement) @ np.asarray(root.axis)
            w[root.q_index] = min(w[root.q_index], float(np.linalg.norm(np.cross(a, c.direction))))
        last = specs[int(f_joint) - 1] if f_joint > 0 else None
        if last is not None and last.revolute:  # its axis is fixed in the frame
            a_f = np.asarray(f_R).T @ np.asarray(last.axis)
            w[last.q_index] = min(w[last.q_index], float(np.linalg.norm(np.cross(a_f, c.axis))))
    w.setflags(write=False)
    cache[key] = w
    return w


#: tilt_weights per kinematics and (link, axis, direction).
_WEIGHTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


@functools.lru_cache(maxsize=64)
def _faces(direction: tuple, faces: int) -> np.ndarray:
    """(faces, 3) unit vectors normal to `direction`, evenly spaced around it (read-only)."""
    d = np.asarray(direction)
    a = np.eye(3)[int(np.argmin(np.abs(d)))]
    e1 = np.cross(d, a)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    phi = 2.0 * np.pi * np.arange(faces) / faces
    return _frozen(np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)


def _cross_rows(u: np.ndarray, F: np.ndarray) -> np.ndarray:
    """(N, K, 3) u[n] x F[n, k] for u (N, 3), F (N, K, 3) (np.cross costs ~0.1 ms a call)."""
    out = np.empty(F.shape)
    u0, u1, u2 = u[:, 0:1], u[:, 1:2], u[:, 2:3]
    out[..., 0] = u1 * F[..., 2] - u2 * F[..., 1]
    out[..., 1] = u2 * F[..., 0] - u0 * F[..., 2]
    out[..., 2] = u0 * F[..., 1] - u1 * F[..., 0]
    return out


def _frozen(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def _fmt(v) -> str:
    return "(" + ", ".join(f"{x:.3g}" for x in v) + ")"
