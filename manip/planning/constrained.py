"""Planning with constraints (`PlanOptions.constraints`): every stage keeps them.

`ConstrainedValidity` is a `Validity` whose answers also require the constraints
(`manip.constraints`): a configuration is valid when collision-free and inside every
constraint's set; a straight motion when collision-free and certified to stay inside
(`constraints.segments_hold`: the bound of each constraint between samples, bisected). So
the straight line, the shortcuts, the repairs and the final certificate of the timed
trajectory (`certify`) keep them with no change to those stages. What changes:

- the path search steers on the constraint set (`steer`, CBiRRT's projection: steps of
  STEER_STEP rad towards the target, each projected onto the set with the constraints'
  Jacobians and checked as a straight motion), so the trees grow along it;
- `advance` stops before the first sample outside the set;
- the trajectory optimiser sees each constraint row as one more clearance term
  (`ConstrainedClearance`: its linearisation is a constraint row of the QP, kept
  `margin / 2` inside);
- the start and the goal are checked (`constraint_problem`: INVALID_START_CONSTRAINT /
  INVALID_GOAL_CONSTRAINT with the angle or distance in the message).

The guarantee of a returned trajectory is the collision certificate's plus the constraint
certificate over the same continuous interpolation of its samples.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from manip.collision.clearance import ClearanceTerms
from manip.constraints import (Constraint, certify_constraints, project, satisfied, segments_hold,
                               trajectory_deviation)
from manip.planning.validity import ADVANCE_BACKOFF_STEPS, Validity

#: Length [rad] (joint-space L2) of one projected step of the constrained search. The steps are
#: projected one after the other while their certificates are batched: 0.3 rad took 0.79 x / 0.94 x
#: the CPU of 0.15 rad on the 40- / 80-per-kind constrained sets, motion times 1.00 x median, about
#: 1.05 x at p90 (BENCHMARKS.md, "Constrained planning").
STEER_STEP = 0.3
#: Steps of the constrained steering checked together.
STEER_BATCH = 4
#: Segments `ConstrainedValidity` remembers as keeping the constraints (then it forgets them all).
HELD_MEMORY = 4096
#: Scale [m] of a constraint term in the optimiser: one margin of a constraint weighs like this much clearance.
TERM_SCALE = 0.01


class ConstrainedValidity(Validity):
    """`Validity` that also requires `constraints` (see the module docstring).

    Args:
        base: the unconstrained validity (checker snapshot, kinematics, resolutions).
        constraints: the `Constraint`s, checked against the robot here.
        certified: as `Validity`.
    """

    def __init__(self, base: Validity, constraints: Sequence[Constraint], certified: bool | None = None):
        super().__init__(base.checker, base.kinematics, base.resolution, base.search_resolution,
                         base.certified if certified is None else certified)
        self.constraints = tuple(constraints)
        for c in self.constraints:
            c.check(self.kinematics)
        # segments `screen` found to keep the constraints (their ends' bytes): shortcutting
        # screens many candidates and then checks the screened ones again with `segments`
        self._held: set[bytes] = set()

    def strict(self) -> ConstrainedValidity:
        return ConstrainedValidity(self, self.constraints, True)

    def loose(self) -> ConstrainedValidity:
        return ConstrainedValidity(self, self.constraints, False)

    def unconstrained(self) -> Validity:
        """The same checks without the constraints."""
        return Validity(self.checker, self.kinematics, self.resolution, self.search_resolution, self.certified)

    # ------------------------------------------------------------------ questions
    def holds(self, Q: np.ndarray) -> np.ndarray:
        """(N,) True where every constraint holds at Q (N, dof)."""
        return satisfied(self.constraints, self.kinematics, Q)

    def _segments_hold(self, Q0: np.ndarray, Q1: np.ndarray, remember: bool = False) -> np.ndarray:
        """(M,) True where the segment Q0[i] -> Q1[i] keeps every constraint (`segments_hold`);
        segments remembered by an earlier call with `remember` are not certified again."""
        Q0, Q1 = np.atleast_2d(Q0), np.atleast_2d(Q1)
        keys = [a.tobytes() + b.tobytes() for a, b in zip(Q0, Q1)] if self._held or remember else None
        ok = np.zeros(Q0.shape[0], dtype=bool) if keys is None else np.array([k in self._held for k in keys])
        if not ok.all():
            todo = ~ok
            ok[todo] = segments_hold(self.constraints, self.kinematics, Q0[todo], Q1[todo])[0]
        if remember:
            if len(self._held) > HELD_MEMORY:
                self._held.clear()
            self._held.update(k for k, held in zip(keys, ok) if held)
        return ok

    def configs(self, Q: np.ndarray) -> np.ndarray:
        Q = np.atleast_2d(Q)
        ok = self.holds(Q)
        if ok.any():
            ok[ok] = super().configs(Q[ok])
        return ok

    def motion(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> bool:
        return bool(self._segments_hold(q0[None], q1[None])[0]) and super().motion(q0, q1, resolution)

    def segments(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        ok = self._segments_hold(Q0, Q1)
        if ok.any():
            ok[ok] = super().segments(np.asarray(Q0)[ok], np.asarray(Q1)[ok])
        return ok

    def screen(self, Q0: np.ndarray, Q1: np.ndarray) -> np.ndarray:
        ok = self._segments_hold(Q0, Q1, remember=True)
        if ok.any():
            ok[ok] = super().screen(np.asarray(Q0)[ok], np.asarray(Q1)[ok])
        return ok

    def certify(self, path: np.ndarray, deviation: np.ndarray | None = None):
        """The collision certificate, then the constraints' (`certify_constraints`) over the
        same interpolation (and, with `deviation` (K-1, dof) [rad], over any motion that
        strays that far from it): the first that fails is returned."""
        cert = super().certify(path)
        if not cert.certified:
            return cert
        held = certify_constraints(self.constraints, self.kinematics, path, deviation)
        return held if not held.certified else cert

    def certify_trajectory(self, traj):
        """`certify` of a timed trajectory's samples, the constraints proved for the true
        motion between them too (`trajectory_deviation`: its accelerations and the jerk limits)."""
        return self.certify(traj.positions, trajectory_deviation(traj.accelerations, traj.dt,
                                                                 self.kinematics.limits.jerk))

    def advance(self, q0: np.ndarray, q1: np.ndarray, resolution: float | None = None) -> np.ndarray | None:
        res = self.resolution if resolution is None else resolution
        d = q1 - q0
        steps = max(1, math.ceil(float(np.max(np.abs(d))) / res))
        t = np.arange(1, steps + 1) / steps
        out = np.flatnonzero(~self.holds(q0[None] + t[:, None] * d[None]))
        t_stop = 1.0 if out.size == 0 else t[out[0]] - ADVANCE_BACKOFF_STEPS / steps
        while t_stop > 0 and not self._segments_hold(q0[None], (q0 + t_stop * d)[None])[0]:
            t_stop -= max(0.5 * t_stop, 1.0 / steps)
        if t_stop <= 0:
            return None
        q_end = q1 if t_stop >= 1.0 else q0 + t_stop * d
        return super().advance(q0, q_end, resolution)

    def steer(self, q_from: np.ndarray, q_to: np.ndarray, resolution: float | None = None) -> np.ndarray | None:
        """Configurations (K, dof) from `q_from` towards `q_to` along the constraint set: steps
        of STEER_STEP, each projected onto the set (`constraints.project`) and checked as a
        straight motion (collisions at `resolution`, certified when strict, and the
        constraints certified; STEER_BATCH steps at a time), up to the first that fails; ends
        at `q_to` itself when it reaches it. None when not even one step is possible."""
        chain: list[np.ndarray] = []
        q = q_from
        dist = float(np.linalg.norm(q_to - q))
        coarse = resolution is not None and resolution != self.resolution
        batch: list[np.ndarray] = []
        for k in range(int(dist / STEER_STEP) + 8):
            stop = dist < 1e-9
            if not stop:
                if dist <= STEER_STEP and self.holds(q_to[None])[0]:
                    q_next = q_to
                else:
                    q_next = project(self.constraints, self.kinematics, q + (q_to - q) * min(1.0, STEER_STEP / dist))
                d_next = np.inf if q_next is None else float(np.linalg.norm(q_to - q_next))
                stop = d_next >= dist - 1e-3 * STEER_STEP  # no projection, or no progress (pushed back)
                if not stop:
                    batch.append(q_next)
                    q, dist = q_next, d_next
                    stop = q_next is q_to
            if batch and (stop or len(batch) == STEER_BATCH):
                Q1 = np.asarray(batch)
                Q0 = np.vstack([(chain[-1] if chain else q_from)[None], Q1[:-1]])
                ok = self._segments_hold(Q0, Q1)
                n = int(np.argmin(ok)) if not ok.all() else len(batch)
                if n:
                    free = (Validity.screen if coarse else Validity.segments)(self, Q0[:n], Q1[:n])
                    n = int(np.argmin(free)) if not free.all() else n
                chain.extend(batch[:n])
                stop = stop or n < len(batch)
                batch = []
            if stop:
                break
        return np.asarray(chain) if chain else None

    def constraint_problem(self, q: np.ndarray) -> str:
        """Why `q` (dof,) is outside a constraint's set ("" when it is inside every one)."""
        for c in self.constraints:
            if float(c.violation(self.kinematics, q[None])[0]) > 0.0:
                return c.explain(self.kinematics, q)
        return ""

    def goal_problem(self, goal: np.ndarray) -> str:
        return super().goal_problem(goal) or self.constraint_problem(goal)


class ConstrainedClearance:
    """A `ClearanceModel` whose terms also hold the constraint rows, for the optimiser.

    A row r (<= 0 inside, margin m) becomes the term d = target + TERM_SCALE (-r / m - 1/2)
    [m] with gradient -TERM_SCALE / m dr/dq: the optimiser's linearised clearance row
    d + g . dq >= target is the linearised constraint r + dr/dq . dq <= -m / 2.

    Args:
        clearance: the clearance model (bound to the plan's checker).
        constraints: the constraints.
        kinematics: the robot's kinematics.
        target: the clearance the optimiser keeps [m] (padding + its own margin).
    """

    def __init__(self, clearance, constraints: Sequence[Constraint], kinematics, target: float):
        self.clearance = clearance
        self.constraints = tuple(constraints)
        self.kinematics = kinematics
        self.target = float(target)
        self.checker = clearance.checker
        self.dof = clearance.dof

    def bound_to(self, checker) -> ConstrainedClearance:
        return ConstrainedClearance(self.clearance.bound_to(checker), self.constraints, self.kinematics, self.target)

    def terms(self, Q: np.ndarray, activation: float) -> ClearanceTerms:
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        base = self.clearance.terms(Q, activation)
        cfg, dist, grad = [base.config], [base.distance], [base.gradient]
        for c in self.constraints:
            m = c.margin
            r, J = c.optimizer_rows(self.kinematics, Q)  # (N, k), (N, k, dof)
            d = self.target + TERM_SCALE * (-r / m - 0.5)
            n, k = np.nonzero(d < activation)
            if n.size == 0:
                continue
            cfg.append(n.astype(np.int64))
            dist.append(d[n, k])
            grad.append(-TERM_SCALE / m * J[n, k])
        return ClearanceTerms(np.concatenate(cfg), np.concatenate(dist), np.concatenate(grad, axis=0))


def with_constraints(validity: Validity, constraints: Sequence[Constraint]) -> Validity:
    """`validity` requiring `constraints` too (itself when there are none)."""
    return ConstrainedValidity(validity, constraints) if constraints else validity
