"""OMPL 2.0's constrained planning as the peer of `benchmarks/constrained.py`.

`ProjectedStateSpace` (Jacobian projection onto the constraint manifold, Kingston et al.
2019) over the Panda's 7-D joint space, RRT-Connect, OMPL's path simplification, the
solution interpolated along its geodesics (`PathGeometric.interpolate`: states `delta`
apart on the manifold), then TOPP-RA along a cubic spline through those states under 0.9 x the
velocity and acceleration limits (SPLINE_LIMIT_SCALE, SPLINE_GRID). The collision model and validity callback are
`OMPLPeer`'s (pinocchio + coal on the URDF meshes, 0.01 rad edge resolution).

The orientation constraint "axis a of `link` within `tolerance` of the world direction d"
is OMPL's equality constraint F(q) = [e1 . u, e2 . u] = 0 (u = R_link(q) a; e1, e2 unit and
orthogonal to d, so |F| = sin(tilt)) with satisfaction tolerance sin(tolerance): what
OMPL (and MoveIt's OMPL interface) offer for orientation constraints. OMPL checks it at the
states of the path (its geodesic steps); between them nothing is proved.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pinocchio as pin
import toppra
import toppra.algorithm
import toppra.constraint
from ompl import base as ob
from ompl import geometric as og

from . import PlannerOutput
from ._common import finite_difference_jerk, problem_arrays, uniform_times
from .ompl_peer import OMPLPeer


#: TOPP-RA along the spline: the limits' share and the grid step [rad of arc length] (the
#: spline through the dense geodesic states bends between gridpoints, where TOPP-RA does
#: not look: a finer grid and some slack keep the sampled motion within the true limits).
SPLINE_LIMIT_SCALE = 0.9
SPLINE_GRID = 0.002


class _Upright(ob.Constraint):
    """F(q) (2,) = the components of the link's axis orthogonal to `direction` (|F| = sin tilt)."""

    def __init__(self, peer: OMPLPeer, frame: int, axis: np.ndarray, direction: np.ndarray, tolerance: float):
        super().__init__(peer.dof, 2, float(np.sin(tolerance)))
        self.peer, self.frame, self.axis = peer, frame, axis
        e1 = np.cross(direction, [1.0, 0.0, 0.0])
        if np.linalg.norm(e1) < 0.1:
            e1 = np.cross(direction, [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        self.E = np.stack([e1, np.cross(direction, e1)])  # (2, 3)

    def _u(self, x) -> np.ndarray:
        p = self.peer
        pin.framesForwardKinematics(p.model, p.data, p._full(np.asarray(x)))
        return p.data.oMf[self.frame].rotation @ self.axis

    def function(self, x, out):
        out[:] = self.E @ self._u(x)

    def jacobian(self, x, out):
        p = self.peer
        full = p._full(np.asarray(x))
        J = pin.computeFrameJacobian(p.model, p.data, full, self.frame, pin.LOCAL_WORLD_ALIGNED)[3:6, p._arm_idx]
        u = p.data.oMf[self.frame].rotation @ self.axis
        out[:, :] = np.cross(u, self.E) @ J  # d(e . u) = e . (w x u) = (u x e) . w


class OMPLConstrainedPeer(OMPLPeer):
    """`OMPLPeer` with an orientation constraint on a ProjectedStateSpace (see the module doc).

    Args:
        delta: OMPL's geodesic step on the manifold [rad] (its default 0.05).
        **kwargs: as `OMPLPeer` (timeout_s, seed, ...).
    """

    name = "ompl_constrained"

    def __init__(self, delta: float = ob.CONSTRAINED_STATE_SPACE_DELTA, **kwargs: Any):
        super().__init__(**kwargs)
        self.delta = float(delta)

    def plan_upright(self, problem: Any, axis, direction, tolerance: float, link: str, seed: int = 0) -> PlannerOutput:
        """Plan from problem.start to its joint goal keeping the orientation constraint."""
        start, goal = problem_arrays(problem, self.joint_names)
        t_setup = time.perf_counter()
        self._build_world(problem.world)
        constraint = _Upright(self, self.model.getFrameId(link), np.asarray(axis, float), np.asarray(direction, float),
                              tolerance)
        css = ob.ProjectedStateSpace(self.space, constraint)
        csi = ob.ConstrainedSpaceInformation(css)
        css.setDelta(self.delta)
        ss = og.SimpleSetup(csi)
        n = self.dof
        ss.setStateValidityChecker(lambda s: self.is_valid(np.array([s[i] for i in range(n)])))
        ss.setPlanner(og.RRTConnect(csi))
        s0, s1 = css.allocState(), css.allocState()
        s0.copy([float(v) for v in start])
        s1.copy([float(v) for v in goal])
        ss.setStartAndGoalStates(s0, s1)
        setup_s = time.perf_counter() - t_setup
        stages: dict[str, float] = {}
        t0 = time.perf_counter()

        def fail(status: str) -> PlannerOutput:
            return PlannerOutput(False, status, time.perf_counter() - t0, setup_time_s=setup_s, stage_times_s=stages)

        status = ss.solve(self.timeout_s)
        stages["plan"] = time.perf_counter() - t0
        T_ = ob.PlannerStatus.PlannerStatusType
        if status.getStatus() != T_.EXACT_SOLUTION or not ss.haveExactSolutionPath():
            return fail("PLAN_FAIL")
        t2 = time.perf_counter()
        ss.simplifySolution(self.simplify_time_s)
        path = ss.getSolutionPath()
        path.interpolate()
        W = np.array([[s[i] for i in range(n)] for s in path.getStates()])
        stages["shortcut"] = time.perf_counter() - t2
        t3 = time.perf_counter()
        try:
            times, P, V, A = self._spline_timing(W)
        except (ValueError, RuntimeError) as exc:  # TOPP-RA failed
            stages["time_parameterization"] = time.perf_counter() - t3
            return fail(f"TIMING_FAIL: {exc}")
        stages["time_parameterization"] = time.perf_counter() - t3
        return PlannerOutput(True, "SUCCESS", time.perf_counter() - t0, times, P, V, A, finite_difference_jerk(times, A),
                             setup_time_s=setup_s, stage_times_s=stages, goal_configuration=goal.copy(),
                             n_waypoints=len(W))

    def _spline_timing(self, W: np.ndarray):
        """TOPP-RA along a cubic spline through the states W (K, 7), parameterised by arc length."""
        d = np.linalg.norm(np.diff(W, axis=0), axis=1)
        keep = np.concatenate([[True], d > 1e-9])
        W = W[keep]
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(W, axis=0), axis=1))])
        if len(W) < 2:
            raise ValueError("the path has a single state")
        path = toppra.SplineInterpolator(s, W, bc_type="clamped")
        v, a = SPLINE_LIMIT_SCALE * self.vlim, SPLINE_LIMIT_SCALE * self.alim
        vel = toppra.constraint.JointVelocityConstraint(np.stack([-v, v], axis=1))
        acc = toppra.constraint.JointAccelerationConstraint(
            np.stack([-a, a], axis=1), discretization_scheme=toppra.constraint.DiscretizationType.Interpolation)
        grid = np.unique(np.concatenate([s, np.linspace(0.0, s[-1], max(100, int(np.ceil(s[-1] / SPLINE_GRID)) + 1))]))
        algo = toppra.algorithm.TOPPRA([vel, acc], path, gridpoints=grid, solver_wrapper="seidel",
                                       parametrizer="ParametrizeConstAccel")
        traj = algo.compute_trajectory(0.0, 0.0)
        if traj is None:
            raise RuntimeError("TOPP-RA found no feasible parameterisation")
        times = uniform_times(float(traj.duration))
        return times, traj(times), traj(times, 1), traj(times, 2)
