"""Pieces shared by both timing algorithms (`waypoints` and `dense`, which never import each other).

Ruckig's 1-D rest-to-rest problem, the distance to a polyline, the duration stretch, the
endpoint checks and the construction of failed and "nothing to move" results.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import ruckig

from manip.timing.result import TimingResult, TimingStatus
from manip.trajectory import PiecewiseJerkProfile, Trajectory

logger = logging.getLogger(__name__)

# Ruckig is given limits shrunk by this relative margin so that its round-off never
# crosses the caller's limits, which are then checked exactly (no tolerance).
LIMIT_MARGIN = 1e-9

#: What ruckig's Python binding raises when it fails: RuckigError, or a ValueError for a result code
#: its `Result` enum lacks (-101, ErrorTrajectoryDuration: a motion beyond its numerical range, hours).
RUCKIG_ERRORS = (ruckig.RuckigError, ValueError)


class RuckigFailure(RuntimeError):
    """Ruckig failed or returned an unusable profile (reported as `TimingStatus.RUCKIG_FAIL`)."""


class RestToRest:
    """A reusable 1-D ruckig problem from rest at 0 to rest at a length [rad]."""

    def __init__(self) -> None:
        self.otg = ruckig.Ruckig(1)
        self.inp = ruckig.InputParameter(1)
        for name in ("current_position", "current_velocity", "current_acceleration", "target_velocity",
                     "target_acceleration"):
            setattr(self.inp, name, [0.0])
        self.traj = ruckig.Trajectory(1)

    def calculate(self, length: float, v: float, a: float, j: float) -> ruckig.Result:
        """Solve to `length` with limits (v, a, j) used as given; raises one of `RUCKIG_ERRORS`."""
        self.inp.target_position = [length]
        self.inp.max_velocity = [v]
        self.inp.max_acceleration = [a]
        self.inp.max_jerk = [j]
        return self.otg.calculate(self.inp, self.traj)

    def rest_profile(self, what: str):
        """Ruckig's profile of the last solution, which must have no brake/accel pre-trajectory."""
        prof = self.traj.profiles[0][0]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise RuckigFailure(f"ruckig used a brake/accel pre-trajectory on a rest-to-rest {what}")
        return prof


def polyline_distances(q: np.ndarray, path: np.ndarray) -> np.ndarray:
    """(N,) Euclidean distance of each row of `q` (N, dof) to the polyline `path` (P, dof) [rad].

    Euclidean (exact through the orthogonal projection, and symmetric enough for the
    triangle inequalities the blend relies on); it bounds the L-inf distance from above.
    """
    if len(path) < 2:
        return np.linalg.norm(q - path[0], axis=1)
    a = path[:-1]  # (S, dof)
    d = np.diff(path, axis=0)
    dd = np.einsum("sd,sd->s", d, d)
    rel = q[:, None, :] - a[None, :, :]  # (N, S, dof)
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(dd > 0, np.einsum("nsd,sd->ns", rel, d) / dd, 0.0)
    lam = np.clip(lam, 0.0, 1.0)
    return np.linalg.norm(rel - lam[:, :, None] * d[None, :, :], axis=2).min(axis=1)


def too_short(duration: float | None, t_min: float) -> str:
    """The DURATION_TOO_SHORT message when `duration` [s] is below the fastest `t_min` [s], else ""."""
    if duration is not None and duration < t_min * (1 - 1e-12):
        return f"requested duration {duration:.4f} s is shorter than the fastest feasible {t_min:.4f} s"
    return ""


def stretch_factor(t_min: float, duration: float | None, dt: float) -> float:
    """Uniform time stretch (>= 1) from the fastest `t_min` > 0 [s] to `duration` (or `t_min`)
    rounded up to a whole number (>= 1) of `dt` [s]."""
    target = t_min if duration is None else float(duration)
    n_steps = int(np.ceil(target / dt - 1e-9))
    return max(n_steps, 1) * dt / t_min


def endpoint_problems(traj: Trajectory, path: np.ndarray) -> list[str]:
    """What is wrong with the ends of `traj` (exactly at the path's (K, dof) ends, at rest)."""
    problems = []
    if not (np.array_equal(traj.positions[0], path[0]) and np.array_equal(traj.positions[-1], path[-1])):
        problems.append("endpoints differ from the path's")
    if np.any(traj.velocities[[0, -1]] != 0) or np.any(traj.accelerations[[0, -1]] != 0):
        problems.append("not at rest at both ends")
    return problems


def failure(
    function: str, mode: str, status: TimingStatus, message: str, waypoints: np.ndarray, t_start: float,
    minimum_duration: float = float("nan"), max_deviation: float = float("nan"),
) -> TimingResult:
    """A failed result of `function` (logged), with zero velocities at the (K', dof) `waypoints`."""
    logger.info("%s failed: %s", function, message)
    return TimingResult(
        False, status, None, mode, minimum_duration, max_deviation, waypoints, np.zeros_like(waypoints),
        np.zeros(max(len(waypoints) - 1, 0)), time.perf_counter() - t_start, message,
    )


def still_result(
    point: np.ndarray, dt: float, names: tuple[str, ...], mode: str, waypoints: np.ndarray, t_start: float
) -> TimingResult:
    """Nothing to move: one sample at `point` (dof,) [rad], at rest, whatever `duration` was asked.

    `waypoints` is the (1, dof) point reported as used.
    """
    dof = point.size
    zeros = np.zeros((dof, 1))
    profile = PiecewiseJerkProfile(knots=np.zeros((dof, 2)), p0=point[:, None], v0=zeros, a0=zeros, j=zeros)
    traj = Trajectory.from_profile(profile, dt, names)
    return TimingResult(
        True, TimingStatus.SUCCESS, traj, mode, 0.0, 0.0, waypoints, np.zeros_like(waypoints), np.zeros(0),
        time.perf_counter() - t_start, "",
    )
