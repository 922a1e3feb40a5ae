"""Peer planners for the side-by-side MotionBenchMaker benchmark (issue 6).

Each peer is a thin adapter around a planner a user could pick instead of `manip`, set up on
the SAME robot model (example-robot-data Panda URDF/SRDF, fingers open at 0.04 m), the same
obstacles and the same Franka velocity/acceleration limits, and returning a
time-parameterised trajectory sampled every 0.01 s:

- ``roboplan``: RoboPlan (C++ RRT-Connect on Pinocchio + coal, its path shortcutter, its
  TOPP-RA), pose goals through its ``SimpleIk``.
- ``ompl``: OMPL RRT-Connect in the 7-D joint box, a Python validity checker calling
  pinocchio + coal on the exact collision meshes, OMPL's path simplifier, then TOPP-RA
  (``toppra``) under velocity and acceleration limits; pose goals through a small
  damped-least-squares IK (pinocchio) with random restarts.
- ``vamp`` and ``mplib`` are listed by `available_peers()` with the reason they cannot run
  in this environment (see README.md).

Usage::

    from benchmarks.peers import available_peers, get_peer
    peer = get_peer("roboplan")             # builds models (not timed)
    out = peer.plan(problem, "joint", seed=0)
    out.success, out.plan_time_s, out.positions  # (T, 7) every 0.01 s

What `plan_time_s` covers: everything the planner needs to turn (start, goal) into an
executable trajectory: IK for pose goals, planning, shortcutting/simplification, time
parameterisation and sampling. Adding the problem's obstacles to the peer's collision world
is done before the clock starts and reported separately in `setup_time_s`.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from manip.errors import ManipError, UnknownNameError

__all__ = [
    "PlannerOutput",
    "Peer",
    "PeerUnavailableError",
    "PEER_NAMES",
    "available_peers",
    "get_peer",
]


@dataclass(frozen=True)
class PlannerOutput:
    """What a peer returns for one problem.

    Attributes:
        success: the planner reports a trajectory (NOT yet verified; the driver verifies).
        status: "SUCCESS", "IK_FAIL", "PLAN_FAIL" (no path within the budget),
            "TIMING_FAIL" (time parameterisation failed), "INVALID_START", "INVALID_GOAL",
            or "ERROR: <message>" for an exception raised inside the peer library.
        plan_time_s: wall time of IK (pose goals) + planning + shortcutting + time
            parameterisation + sampling [s].
        times: (T,) sample times [s] starting at 0, every 0.01 s (last one = duration).
        positions: (T, 7) joint positions [rad].
        velocities: (T, 7) [rad/s].
        accelerations: (T, 7) [rad/s^2].
        jerks: (T, 7) [rad/s^3] (central differences of the accelerations).
        claims_jerk_limits: True only if the peer limits jerk (neither peer does: TOPP-RA
            limits velocity and acceleration).
        setup_time_s: untimed per-problem set-up (adding obstacles, building the checker) [s].
        stage_times_s: per-stage wall times [s], e.g. {"ik": .., "plan": .., "shortcut": ..,
            "time_parameterization": ..}.
        goal_configuration: (7,) the joint goal actually planned to (the IK solution for
            pose goals), or None.
        n_waypoints: number of waypoints of the geometric path after shortcutting (0 if none).
    """

    success: bool
    status: str
    plan_time_s: float
    times: np.ndarray | None = None
    positions: np.ndarray | None = None
    velocities: np.ndarray | None = None
    accelerations: np.ndarray | None = None
    jerks: np.ndarray | None = None
    claims_jerk_limits: bool = False
    setup_time_s: float = 0.0
    stage_times_s: dict[str, float] = field(default_factory=dict)
    goal_configuration: np.ndarray | None = None
    n_waypoints: int = 0


class Peer(Protocol):
    """A peer planner: built once, then `plan` per problem."""

    name: str

    def plan(self, problem: Any, goal_kind: str = "joint", seed: int = 0) -> PlannerOutput:
        """Plan from `problem.start` to its joint goal or its pose goal (see `PlannerOutput`)."""
        ...


class PeerUnavailableError(ManipError):
    """A peer that exists but cannot run here (package not installed, cannot be installed)."""


#: Every peer the benchmark knows, in report order.
PEER_NAMES: tuple[str, ...] = ("roboplan", "ompl", "vamp", "mplib")

# name -> (module of this package, class, modules that must import)
_RUNNABLE: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "roboplan": ("roboplan_peer", "RoboPlanPeer", ("roboplan.core", "roboplan.rrt", "roboplan.toppra", "roboplan.simple_ik")),
    "ompl": ("ompl_peer", "OMPLPeer", ("ompl.base", "ompl.geometric", "ompl.util", "toppra")),
}

_NOT_HERE: dict[str, str] = {
    "vamp": (
        "not installable here: VAMP is published only as a source package (vamp-planner) whose "
        "build downloads its C++ dependencies at build time, and this machine reaches only the "
        "package registries; its published figures are quoted in BENCHMARKS.md instead"
    ),
    "mplib": (
        "not included: mplib 0.2.1 needs numpy < 2 (manip uses numpy 2), so it cannot share "
        "manip's process; it installs and plans in a separate venv, but its Python API exposes "
        "no edge collision-check resolution (OMPL's default, 1 % of the joint-space extent, "
        "about 0.13 rad), so it cannot be run under the 0.01 rad rule of the other planners; "
        "see benchmarks/peers/README.md"
    ),
}


def _import_reason(modules: tuple[str, ...]) -> str:
    for m in modules:
        try:
            importlib.import_module(m)
        except Exception as exc:  # ImportError, or a broken binary wheel
            return f"not installed: `pip install -e .[bench]` ({m}: {type(exc).__name__}: {exc})"
    return "ok"


def available_peers() -> dict[str, str]:
    """Every known peer and whether it can run here.

    Returns:
        {name: "ok" or the reason it cannot run}, in `PEER_NAMES` order.
    """
    out: dict[str, str] = {}
    for name in PEER_NAMES:
        if name in _RUNNABLE:
            out[name] = _import_reason(_RUNNABLE[name][2])
        else:
            out[name] = _NOT_HERE[name]
    return out


def get_peer(name: str, **options: Any) -> Peer:
    """Build a peer (loads its robot model; not part of any timed section).

    Args:
        name: one of `PEER_NAMES` that `available_peers()` reports "ok".
        **options: keyword options of the peer's constructor (e.g. `timeout_s`).

    Raises:
        UnknownNameError: `name` is not a known peer.
        PeerUnavailableError: the peer cannot run here (the message says why).
    """
    if name not in PEER_NAMES:
        raise UnknownNameError("peer", name, PEER_NAMES)
    if name not in _RUNNABLE:
        raise PeerUnavailableError(f"peer '{name}' {_NOT_HERE[name]}")
    module_name, cls_name, deps = _RUNNABLE[name]
    reason = _import_reason(deps)
    if reason != "ok":
        raise PeerUnavailableError(f"peer '{name}' {reason}")
    module = importlib.import_module(f"{__name__}.{module_name}")
    return getattr(module, cls_name)(**options)
