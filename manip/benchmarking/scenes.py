"""The project's own seeded planning problems: tables, shelves, boxes, cages and clutter.

`make_problems(kind, n, seed)` builds `n` randomised scenes around the Franka, or around any
robot with `robot=` (scenes scaled by the robot's reach relative to the Franka's; goals for
its `tcp_link`, or `ee_link`, whose z axis, or the yaml's `approach_axis`, is the approach) (in cuRobo's
world format, so every planner and the verifier read them like MotionBenchMaker problems)
with a start and a goal configuration each. Goals are placed where planning is interesting:
the hand inside a shelf compartment, down in an open box, between the bars of a cage,
between objects on a table, among random clutter. Every start and goal is checked by the
independent verifier (limits, self and world collision), and a goal inside a structure is
kept only if the hand can back out of it along its approach direction (a collision-free
straight joint-space retreat of 12 cm), so the problems are solvable.

Generation is deterministic: problem `i` of `(kind, seed)` depends only on `(kind, seed, i)`
(not on `n`), so `make_problems(k, 5, s)[:3] == make_problems(k, 3, s)`.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from functools import lru_cache

import numpy as np
import pinocchio as pin

from manip.benchmarking.mbm_problems import MBMProblem
from manip.benchmarking.verify import Verifier, default_verifier
from manip.errors import InvalidInputError
from manip.kinematics import Kinematics
from manip.robot_config import RobotConfig, load_robot_config

log = logging.getLogger(__name__)

#: Kinds of seeded scenes.
SCENE_KINDS: tuple[str, ...] = ("table", "shelf", "box", "cage", "clutter")

RETREAT = 0.12  # [m] a goal inside a structure must allow backing out this far
_MAX_SCENE_TRIES = 30
_MAX_CONFIG_TRIES = 25
#: Fraction of problems whose straight start-goal line is in collision (when one can be found).
OBSTRUCTED_FRACTION = 0.75


# ---------------------------------------------------------------------------- geometry helpers
def _yaw_quat(yaw: float) -> list[float]:
    return [float(np.cos(yaw / 2)), 0.0, 0.0, float(np.sin(yaw / 2))]


def _rot_z(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class _World:
    """Accumulates cuboids and cylinders in cuRobo's world format."""

    def __init__(self) -> None:
        self.d: dict[str, dict] = {"cuboid": {}, "cylinder": {}}

    def box(self, name: str, center, dims, yaw: float = 0.0) -> None:
        self.d["cuboid"][name] = {
            "dims": [float(v) for v in dims],
            "pose": [float(v) for v in center] + _yaw_quat(yaw),
        }

    def cylinder(self, name: str, center, radius: float, height: float, quat_wxyz=(1.0, 0.0, 0.0, 0.0)) -> None:
        self.d["cylinder"][name] = {
            "radius": float(radius),
            "height": float(height),
            "pose": [float(v) for v in center] + [float(v) for v in quat_wxyz],
        }

    def world(self) -> dict:
        return {k: v for k, v in self.d.items() if v}


def _hand_rotation(approach: np.ndarray, finger_axis: np.ndarray) -> np.ndarray:
    """Rotation of panda_hand whose z axis is `approach` and y axis (finger opening) ~ `finger_axis`."""
    z = approach / np.linalg.norm(approach)
    y = finger_axis - z * (finger_axis @ z)
    y /= np.linalg.norm(y)
    x = np.cross(y, z)
    return np.column_stack([x, y, z])


# ---------------------------------------------------------------------------- IK (local, DLS)
def _reach(kin: Kinematics, tool: str) -> float:
    """Length [m] of the chain from the first joint to the tool frame (sum of the joint offsets)."""
    model = kin.model
    total = sum(float(np.linalg.norm(model.jointPlacements[j].translation)) for j in range(2, model.njoints))
    fid = kin.frame_id(tool)
    return total + float(np.linalg.norm(model.frames[fid].placement.translation))


class _IK:
    """Damped least squares IK for the robot's ee_link with random restarts (generation only).

    Targets are tool (tcp_link, else ee_link) poses; `ee_pose` turns one into the ee_link's.
    """

    def __init__(self, config: RobotConfig):
        kin = Kinematics(config)
        self.config = config
        self.kin = kin
        self.fid = kin.frame_id(config.ee_link)
        tool = config.tcp_link or config.ee_link
        q = config.default_joint_positions
        T = kin.frame_transform(q, self.fid).inverse() * kin.frame_transform(q, kin.frame_id(tool))
        # snapped to 1e-12: a tool frame offset along an axis stays exactly that
        self.R_ee_tool = np.round(T.rotation, 12) + 0.0
        self.p_ee_tool = np.round(T.translation, 12) + 0.0
        axis = config.raw.get("approach_axis")  # the tool axis in the tool frame, if not z
        if axis is not None:
            z = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
            y = np.array([0.0, 1.0, 0.0]) if abs(z[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
            y -= z * (y @ z)
            y /= np.linalg.norm(y)
            self.R_ee_tool = self.R_ee_tool @ np.column_stack([np.cross(y, z), y, z])
        self.ready = np.asarray(config.default_joint_positions, dtype=float)
        self.reach = _reach(kin, tool)

    def ee_pose(self, R_tool: np.ndarray, p_tool: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(R (3, 3), p (3,)) of ee_link for a tool pose."""
        R = R_tool @ self.R_ee_tool.T
        return R, p_tool - R @ self.p_ee_tool

    def solve(self, R_goal: np.ndarray, p_goal: np.ndarray, q_init: np.ndarray, iters: int = 80) -> np.ndarray | None:
        kin, q = self.kin, q_init.copy()
        for _ in range(iters):
            M = kin.frame_transform(q, self.fid)
            e = np.concatenate([p_goal - M.translation, pin.log3(R_goal @ M.rotation.T)])
            if np.linalg.norm(e[:3]) < 1e-6 and np.linalg.norm(e[3:]) < 1e-5:
                return q
            J = kin.frame_jacobian(q, self.fid)
            dq = J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(6), e)
            n = np.abs(dq).max()
            if n > 0.4:
                dq *= 0.4 / n
            q = np.clip(q + dq, kin.lower, kin.upper)
        return None


@lru_cache(maxsize=8)
def _ik(robot: str = "franka") -> _IK:
    return _IK(load_robot_config(robot))


def _scale(ik: _IK) -> float:
    """Scene scale: the robot's reach over the Franka's (exactly 1.0 for the Franka)."""
    return ik.reach / _ik("franka").reach


# ---------------------------------------------------------------------------- scene builders
# A builder draws a world scaled by s (the robot's reach over the Franka's) and returns
# (world dict, target sampler). A target sampler draws (R (3, 3), p (3,), retreat direction
# (3,) or None, is_tool) for one goal or start: a pose of the tool frame (tcp_link, z axis the
# approach) if is_tool, else of ee_link.
Target = tuple[np.ndarray, np.ndarray, np.ndarray | None, bool]
Builder = Callable[[np.random.Generator, float], tuple[dict, Callable[[np.random.Generator], Target]]]


def _down_target(rng: np.random.Generator, xy_lo, xy_hi, z_tcp_lo: float, z_tcp_hi: float, frame=None) -> Target:
    """Top-down hand pose with the fingertips at a random point of a (possibly rotated) box."""
    local = np.array([rng.uniform(xy_lo[0], xy_hi[0]), rng.uniform(xy_lo[1], xy_hi[1]), rng.uniform(z_tcp_lo, z_tcp_hi)])
    Rw, pw = frame if frame is not None else (np.eye(3), np.zeros(3))
    tcp = pw + Rw @ local
    yaw = rng.uniform(-np.pi, np.pi)
    R = _hand_rotation(np.array([0.0, 0.0, -1.0]), np.array([np.cos(yaw), np.sin(yaw), 0.0]))
    return R, tcp, np.array([0.0, 0.0, 1.0]), True


def _table(rng: np.random.Generator, s: float):
    w = _World()
    x0 = s * rng.uniform(0.25, 0.4)
    depth, width = s * rng.uniform(0.5, 0.75), s * rng.uniform(0.9, 1.3)
    yc = s * rng.uniform(-0.2, 0.2)
    z_top = s * rng.uniform(-0.15, 0.1)
    w.box("table", [x0 + depth / 2, yc, z_top - 0.02], [depth, width, 0.04])
    k = int(rng.integers(3, 8))
    for i in range(k):
        x = rng.uniform(x0 + 0.08, x0 + depth - 0.08)
        y = rng.uniform(yc - width / 2 + 0.08, yc + width / 2 - 0.08)
        h = rng.uniform(0.06, 0.3)
        if rng.random() < 0.5:
            w.box(f"obj{i}", [x, y, z_top + h / 2], [rng.uniform(0.04, 0.12), rng.uniform(0.04, 0.12), h], rng.uniform(-np.pi, np.pi))
        else:
            w.cylinder(f"obj{i}", [x, y, z_top + h / 2], rng.uniform(0.02, 0.06), h)

    def target(r: np.random.Generator) -> Target:
        return _down_target(r, (x0 + 0.1, yc - width / 2 + 0.1), (x0 + depth - 0.1, yc + width / 2 - 0.1),
                            z_top + 0.03, z_top + 0.3)

    return w.world(), target


def _shelf(rng: np.random.Generator, s: float):
    w = _World()
    yaw = rng.uniform(-0.7, 0.7)
    front = s * rng.uniform(0.45, 0.6)
    depth, width = rng.uniform(0.28, 0.38), s * rng.uniform(0.6, 0.9)
    z_bottom = s * rng.uniform(-0.35, -0.05)
    n_levels = int(rng.integers(3, 5))
    gaps = rng.uniform(0.26, 0.36, size=n_levels)
    t = 0.02
    Rz = _rot_z(yaw)
    c = Rz @ np.array([front + depth / 2, 0.0, 0.0])  # shelf centre in the base plane

    def place(local) -> list[float]:
        return list(c + Rz @ np.asarray(local, dtype=float))

    boards = [z_bottom]
    for g in gaps:
        boards.append(boards[-1] + g)
    height = boards[-1] - z_bottom
    for i, zb in enumerate(boards):
        w.box(f"board{i}", place([0.0, 0.0, zb]), [depth, width, t], yaw)
    zc = z_bottom + height / 2
    w.box("back", place([depth / 2 + t / 2, 0.0, zc]), [t, width, height + t], yaw)
    w.box("left", place([0.0, width / 2 + t / 2, zc]), [depth, t, height + t], yaw)
    w.box("right", place([0.0, -width / 2 - t / 2, zc]), [depth, t, height + t], yaw)
    if rng.random() < 0.5:  # a divider in one compartment
        k = int(rng.integers(0, n_levels))
        yd = rng.uniform(-width / 4, width / 4)
        w.box("divider", place([0.0, yd, (boards[k] + boards[k + 1]) / 2]), [depth, t, gaps[k]], yaw)

    into = Rz @ np.array([1.0, 0.0, 0.0])

    def target(r: np.random.Generator) -> Target:
        k = int(r.integers(0, n_levels))
        zmid = (boards[k] + boards[k + 1]) / 2 + r.uniform(-0.03, 0.03)
        y = r.uniform(-width / 2 + 0.12, width / 2 - 0.12)
        x = -depth / 2 + r.uniform(0.06, depth - 0.08)  # fingertips inside the compartment
        tcp = np.asarray(place([x, y, 0.0])) + np.array([0.0, 0.0, zmid])
        finger_axis = Rz @ np.array([0.0, 1.0, 0.0])  # fingers open horizontally
        R = _hand_rotation(into, finger_axis)
        return R, tcp, -into, True

    return w.world(), target


def _box(rng: np.random.Generator, s: float):
    w = _World()
    yaw = rng.uniform(-np.pi / 4, np.pi / 4)
    cx, cy = s * rng.uniform(0.4, 0.6), s * rng.uniform(-0.35, 0.35)
    lx, ly = rng.uniform(0.3, 0.45), rng.uniform(0.3, 0.45)
    z_bottom = s * rng.uniform(-0.35, -0.05)
    h = rng.uniform(0.15, 0.3)
    t = 0.02
    Rz = _rot_z(yaw)
    c = np.array([cx, cy, 0.0])

    def place(local) -> list[float]:
        return list(c + Rz @ np.asarray(local, dtype=float))

    w.box("base", place([0.0, 0.0, z_bottom - t / 2]), [lx + 2 * t, ly + 2 * t, t], yaw)
    w.box("side_front", place([-lx / 2 - t / 2, 0.0, z_bottom + h / 2]), [t, ly + 2 * t, h], yaw)
    w.box("side_back", place([lx / 2 + t / 2, 0.0, z_bottom + h / 2]), [t, ly + 2 * t, h], yaw)
    w.box("side_left", place([0.0, ly / 2 + t / 2, z_bottom + h / 2]), [lx, t, h], yaw)
    w.box("side_right", place([0.0, -ly / 2 - t / 2, z_bottom + h / 2]), [lx, t, h], yaw)
    if rng.random() < 0.7:
        ch = rng.uniform(0.08, 0.16)
        w.cylinder("can", place([rng.uniform(-lx / 4, lx / 4), rng.uniform(-ly / 4, ly / 4), z_bottom + ch / 2]),
                   rng.uniform(0.025, 0.04), ch)

    def target(r: np.random.Generator) -> Target:
        return _down_target(r, (-lx / 2 + 0.1, -ly / 2 + 0.1), (lx / 2 - 0.1, ly / 2 - 0.1),
                            z_bottom + 0.03, z_bottom + h * 0.8, frame=(Rz, c))

    return w.world(), target


def _cage(rng: np.random.Generator, scale: float):
    w = _World()
    yaw = rng.uniform(-0.6, 0.6)
    cx, cy = scale * rng.uniform(0.45, 0.6), scale * rng.uniform(-0.25, 0.25)
    s = rng.uniform(0.42, 0.55)
    hz = rng.uniform(0.4, 0.55)
    z_bottom = scale * rng.uniform(-0.3, -0.05)
    r_bar = rng.uniform(0.008, 0.015)
    Rz = _rot_z(yaw)
    c = np.array([cx, cy, 0.0])

    def place(local) -> list[float]:
        return list(c + Rz @ np.asarray(local, dtype=float))

    w.box("floor", place([0.0, 0.0, z_bottom - 0.01]), [s + 0.1, s + 0.1, 0.02], yaw)
    corners = [(-1, -1), (-1, 1), (1, -1), (1, 1)]
    for i, (a, b) in enumerate(corners):
        w.cylinder(f"post{i}", place([a * s / 2, b * s / 2, z_bottom + hz / 2]), r_bar, hz)
    # top frame: four horizontal bars (boxes) around the top
    zt = z_bottom + hz
    w.box("top_front", place([-s / 2, 0.0, zt]), [2 * r_bar, s, 2 * r_bar], yaw)
    w.box("top_back", place([s / 2, 0.0, zt]), [2 * r_bar, s, 2 * r_bar], yaw)
    w.box("top_left", place([0.0, s / 2, zt]), [s, 2 * r_bar, 2 * r_bar], yaw)
    w.box("top_right", place([0.0, -s / 2, zt]), [s, 2 * r_bar, 2 * r_bar], yaw)
    # a few horizontal rails on random sides at random heights, and a cross bar on top
    for i in range(int(rng.integers(1, 4))):
        side = int(rng.integers(0, 4))
        z = z_bottom + rng.uniform(0.15, 0.75) * hz
        if side < 2:
            w.box(f"rail{i}", place([(-1) ** side * s / 2, 0.0, z]), [2 * r_bar, s, 2 * r_bar], yaw)
        else:
            w.box(f"rail{i}", place([0.0, (-1) ** side * s / 2, z]), [s, 2 * r_bar, 2 * r_bar], yaw)
    if rng.random() < 0.6:
        off = rng.uniform(-s / 4, s / 4)
        w.box("cross", place([off, 0.0, zt]), [2 * r_bar, s, 2 * r_bar], yaw)
    ch = rng.uniform(0.06, 0.12)
    w.box("block", place([rng.uniform(-s / 5, s / 5), rng.uniform(-s / 5, s / 5), z_bottom + ch / 2]),
          [0.05, 0.05, ch], rng.uniform(-np.pi, np.pi))

    def target(r: np.random.Generator) -> Target:
        return _down_target(r, (-s / 2 + 0.1, -s / 2 + 0.1), (s / 2 - 0.1, s / 2 - 0.1),
                            z_bottom + 0.05, z_bottom + hz * 0.7, frame=(Rz, c))

    return w.world(), target


def _clutter(rng: np.random.Generator, s: float):
    w = _World()
    k = int(rng.integers(8, 15))
    for i in range(k):
        rad = s * rng.uniform(0.35, 0.8)
        th = rng.uniform(-np.pi * 0.75, np.pi * 0.75)
        z = s * rng.uniform(-0.3, 0.8)
        p = [rad * np.cos(th), rad * np.sin(th), z]
        if rng.random() < 0.6:
            w.box(f"obj{i}", p, rng.uniform(0.04, 0.16, size=3), rng.uniform(-np.pi, np.pi))
        else:
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
            ang = rng.uniform(0, np.pi)
            w.cylinder(f"obj{i}", p, rng.uniform(0.02, 0.06), rng.uniform(0.08, 0.3),
                       [np.cos(ang / 2), *(np.sin(ang / 2) * axis)])

    def target(r: np.random.Generator) -> Target:
        # a hand pose in the cluttered shell, random orientation with the fingers facing outwards-ish
        rad = s * r.uniform(0.35, 0.75)
        th = r.uniform(-np.pi * 0.75, np.pi * 0.75)
        p = np.array([rad * np.cos(th), rad * np.sin(th), s * r.uniform(-0.2, 0.7)])
        a = np.array([np.cos(th), np.sin(th), 0.0]) + 0.8 * r.normal(size=3)
        R = _hand_rotation(a, r.normal(size=3))
        return R, p, None, False

    return w.world(), target


_BUILDERS: dict[str, Builder] = {"table": _table, "shelf": _shelf, "box": _box, "cage": _cage, "clutter": _clutter}


# ---------------------------------------------------------------------------- sampling configurations
def _solve_target(ik: _IK, verifier: Verifier, world: dict, target: Target,
                  rng: np.random.Generator) -> np.ndarray | None:
    R, p, retreat, is_tool = target
    if is_tool:
        R, p = ik.ee_pose(R, p)
    kin = ik.kin
    for k in range(4):
        q_init = ik.ready + (rng.normal(scale=0.4, size=kin.dof) if k else 0.0)
        q_init = np.clip(q_init, kin.lower, kin.upper)
        q = ik.solve(R, p, q_init)
        if q is None or verifier.check_configuration(q, world, "q")[0]:
            continue
        if retreat is not None:
            q_out = ik.solve(R, p + RETREAT * retreat, q)
            if q_out is None or np.abs(q_out - q).max() > 0.6:
                continue
            hit = verifier.first_collision(verifier.densify(np.array([0.0, 1.0]), np.stack([q, q_out]))[1], world)
            if hit is not None:
                continue
        return q
    return None


def _line_obstructed(verifier: Verifier, world: dict, a: np.ndarray, b: np.ndarray) -> bool:
    Q = verifier.densify(np.array([0.0, 1.0]), np.stack([a, b]))[1]
    return verifier.first_collision(Q, world) is not None


def _make_one(kind: str, seed: int, index: int, verifier: Verifier, ik: _IK) -> MBMProblem:
    kind_id = SCENE_KINDS.index(kind)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(kind_id, index)))
    build = _BUILDERS[kind]
    for _ in range(_MAX_SCENE_TRIES):
        world, target = build(rng, _scale(ik))
        # goal: a target inside the structure; start: the ready pose (perturbed) or another target
        goal = None
        for _ in range(_MAX_CONFIG_TRIES):
            goal = _solve_target(ik, verifier, world, target(rng), rng)
            if goal is not None:
                break
        if goal is None:
            continue
        # Three problems in four must not be solvable by the straight joint-space line.
        want_obstructed = rng.random() < OBSTRUCTED_FRACTION
        start = fallback = None
        for _ in range(_MAX_CONFIG_TRIES):
            if rng.random() < 0.4:
                cand = np.clip(ik.ready + rng.normal(scale=0.15, size=ik.kin.dof), verifier.lower, verifier.upper)
                if verifier.check_configuration(cand, world, "q")[0]:
                    continue
            else:
                cand = _solve_target(ik, verifier, world, target(rng), rng)
                if cand is None:
                    continue
            if np.abs(cand - goal).max() < 0.3:
                continue
            if want_obstructed and not _line_obstructed(verifier, world, cand, goal):
                fallback = cand if fallback is None else fallback
                continue
            start = cand
            break
        if start is None:
            start = fallback
        if start is None:
            continue
        # random order: half the problems go into the structure, half come out of it
        if rng.random() < 0.5:
            start, goal = goal, start
        start.setflags(write=False)
        goal.setflags(write=False)
        return MBMProblem(scene=f"seeded_{kind}", index=index, world=world, start=start, goal=goal,
                          joint_names=tuple(ik.config.arm_joints))
    raise RuntimeError(f"could not generate a valid {kind} problem (seed {seed}, index {index})")  # pragma: no cover


def make_problems(kind: str, n: int, seed: int = 0, verifier: Verifier | None = None, *,
                  robot: str | RobotConfig = "franka") -> list[MBMProblem]:
    """Generate `n` seeded planning problems of one kind.

    Args:
        kind: one of `SCENE_KINDS`: "table", "shelf", "box", "cage", "clutter".
        n: number of problems (>= 0).
        seed: random seed; problem i depends only on (kind, seed, i).
        verifier: the checker of starts and goals (default: the shared Franka verifier, or
            a new Verifier of `robot`).
        robot: the robot (name or config); its scenes are the Franka's scaled by its reach.

    Returns:
        Problems named "seeded_<kind>/<i>" (i = 0..n-1) whose start and goal pass
        `check_problem` (within limits, free of self and world collision).

    Raises:
        InvalidInputError: unknown kind or negative n.
    """
    if kind not in _BUILDERS:
        raise InvalidInputError(f"scene kind '{kind}' not known; valid: {list(SCENE_KINDS)}")
    if n < 0:
        raise InvalidInputError(f"n must be >= 0; got {n}")
    ik = _ik(robot) if isinstance(robot, str) else _IK(robot)
    if verifier is None:
        verifier = default_verifier() if robot == "franka" else Verifier(ik.config)
    return [_make_one(kind, int(seed), i, verifier, ik) for i in range(n)]
