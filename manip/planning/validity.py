"""`Validity`: the collision and limit questions the planners ask, in one object.

The planners (RRT-Connect, shortcutting, the trajectory optimiser, linear motions) are
handed this object instead of reaching back into `MotionGenerator`. Two resolutions:
`resolution` [rad] is the planners' fine check (paths are searched and repaired at it,
joint-space L-inf), `search_resolution` a coarser, cheaper screen used while searching (a
necessary condition only). Returned trajectories are then certified over their whole
continuous interpolation (`certify`). A `MotionGenerator` hands each plan a Validity on
a snapshot of its checker, so a plan sees one world while other threads edit it.

A strict Validity (`strict()`) also certifies every straight motion it accepts over its
whole continuous length (the fine resolution can miss a graze thinner than its step): the
planner's later attempts use it once timed trajectories failed the certificate
(`planning.pipeline.STRICT_ATTEMPT`): first only on the segments of a path planned without
it (`planning.path.search.repair_path`), then, if that fails, for a whole strict plan.
"""

from __future__ import annotations

import numpy as np

from manip.collision import CollisionChecker
from manip.kinematics import Kinematics

#: An advancing tree stops this many check steps before its first contact.
ADVANCE_BACKOFF_STEPS = 3


class Validity:
    """Validity of configurations and straight joint-space motions for one robot and world.

    Args:
        checker: the collision checker (robot, world, attached objects, padding).
        kinematics: the robot's kinematics (joint limits).
        resolution: fine check resolution [rad] (the guarantee).
        search_resolution: coarse screening resolution [rad] (>= resolution to be useful).
        certified: also certify every accepted straight motion continuously (slower).
    """

    def __init__(self, checker: CollisionChecker, kinematics: Kinematics, resolution: float, search_resolution: float,
                 certified: bool = False):
        self.checker = checker
        self.kinematics = kinematics
        self.resolution = resolution
        self.search_resolution = max(resolution, search_resolution)
        self.certified = certified

    #: The constraints every answer also requires (`planning.constrained.ConstrainedValidity`).
    constraints: tuple = ()
    #: Steering of the path search along a constraint set (`ConstrainedValidity.steer`); None:
    #: straight extensions.
    steer = None

    def constraint_problem(self, q: np.ndarray) -> str:
        """Why `q` (dof,) violates a constraint ("": none does; this validity has none)."""
        return ""

    def strict(self) -> Validity:
        """This validity with every accepted straight motion certified (`certified=True`)."""
        return Validity(self.checker, self.kinematics, self.resolution, self.search_resolution, certified=True)

    def loose(self) -> Validity:
        """This validity without the certification of accepted motions (`certified=False`)."""
        return Validity(self.checker, self.kinematics, self.resolution, self.search_resolution)

    def _certified(self, q0: np.ndarray, q1: np.ndarray) -> bool:
        return bool(self.checker.certify_path(np.stack([q0, q1])).certified)

    def configs(self, Q: np.ndarray) -> np.ndarray:
        """(N,) True where a configuration of Q (N, dof) or (dof,) is collision-free."""
        return ~self.checker.in_collision_batch(np.atleast_2d(Q))

    def motion(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> bool:
        """True when the straight motion q0 -> q1 is free at `resolution` (default: the fine one;
        a strict validity also certifies it at the fine resolution)."""
        if not self.checker.state.motion_free(q0, q1, self.resolution if resolution is None else resolution):
            return False
        return not self.certified or resolution not in (None, self.resolution) or self._certified(q0, q1)

    def coarse_motion(self, q0: np.ndarray, q1: np.ndarray) -> bool:
        """`motion` at the search resolution."""
        return self.motion(q0, q1, self.search_resolution)

    def segments(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) validity of the segments Q0[i] -> Q1[i] at the fine resolution (screened coarsely first)."""
        ok = self.screen(Q0, Q1)
        if ok.any():
            ok[ok] = self.screened(np.asarray(Q0)[ok], np.asarray(Q1)[ok])
        return ok

    def screened(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) `segments` of segments Q0[i] -> Q1[i] that passed `screen` (the rest of the
        check: the fine resolution, and the certificate of a strict validity), for callers that
        screened many and check a few (`planning.path.shortcut`)."""
        Q0, Q1 = np.asarray(Q0, dtype=float), np.asarray(Q1, dtype=float)
        ok = np.ones(Q0.shape[0], dtype=bool)
        if ok.size and self.search_resolution > self.resolution:
            ok = self.checker.state.segments_free(Q0, Q1, self.resolution)
        if self.certified:
            for i in np.flatnonzero(ok):
                ok[i] = self._certified(Q0[i], Q1[i])
        return ok

    def screen(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        """(M,) validity at the search resolution (a necessary condition, cheaper)."""
        Q0, Q1 = np.asarray(Q0, dtype=float), np.asarray(Q1, dtype=float)
        return self.checker.state.segments_free(Q0, Q1, self.search_resolution)

    def certify(self, path: np.ndarray):
        """`CollisionChecker.certify_path`: the continuous interpolation of `path` (K, dof)
        proved collision-free (a `MotionCertificate`)."""
        return self.checker.certify_path(path)

    def certify_trajectory(self, traj):
        """`certify` of a timed trajectory's samples (a constrained validity also proves its
        constraints for the true motion between them, `planning.constrained`)."""
        return self.certify(traj.positions)

    def path(self, path: np.ndarray) -> bool:
        """True when every segment of the polyline `path` (K, dof) is free at the fine resolution."""
        return bool(self.segments(path[:-1], path[1:]).all()) if len(path) > 1 else bool(self.configs(path).all())

    def advance(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> np.ndarray | None:
        """The farthest configuration on q0 -> q1 reachable without collision, kept a few
        check steps short of the first contact (None if there is no room to move).

        q0 must be collision-free (a node of a search tree): the check starts at the first
        sample after it."""
        fine = resolution in (None, self.resolution)
        resolution = self.resolution if resolution is None else resolution
        t, steps = self.checker.state.advance(q0, q1, resolution)
        t_stop = 1.0 if t is None else t - ADVANCE_BACKOFF_STEPS / steps
        if self.certified and fine:
            while t_stop > 0 and not self._certified(q0, q0 + t_stop * (q1 - q0)):
                t_stop -= max(0.5 * t_stop, ADVANCE_BACKOFF_STEPS / steps)  # back off until certified
        if t_stop <= 0:
            return None
        return q1.copy() if t_stop >= 1.0 else q0 + t_stop * (q1 - q0)

    def coarse_advance(self, q0: np.ndarray, q1: np.ndarray) -> np.ndarray | None:
        """`advance` at the search resolution."""
        return self.advance(q0, q1, self.search_resolution)

    def limit_excess(self, q: np.ndarray) -> float:
        """How far [rad] `q` (dof,) lies outside the joint limits (0 inside)."""
        k = self.kinematics
        return float(max(0.0, np.max(k.lower - q), np.max(q - k.upper)))

    def goal_problem(self, goal: np.ndarray) -> str:
        """Why the goal configuration (dof,) cannot be planned to ("" when it can)."""
        bad = self.kinematics.limit_violations(goal)
        if bad:
            return "goal outside the joint limits: " + "; ".join(bad)
        if self.checker.in_collision(goal):
            return "goal in collision: " + describe_contacts(self.checker.collision_report(goal))
        return ""


def describe_contacts(report) -> str:
    """'a touches b (1.2 mm deep)' for the deepest few contacts of a CollisionReport."""
    parts = [f"{c.a} touches {c.b} ({max(0.0, -c.distance) * 1e3:.1f} mm deep, {c.kind})" for c in report.contacts[:3]]
    more = len(report.contacts) - 3
    return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")
