"""`Problem`: one planning problem of a batch, and its validation before any worker starts.

A batch is validated whole in the calling process (`prepare`): a bad robot name (or
robot.yaml path), a malformed world, a wrong shape, a NaN or an unknown option raises a
`ManipError` naming the problem, before a single worker is started. What goes to the workers is a `Task`:
the validated problem with its id, its derived seed and a key of its world (workers
reuse a warm generator's world when the key repeats).
"""

from __future__ import annotations

import hashlib
import json
import pickle
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from manip.collision import WorldConfig
from manip.errors import InvalidInputError, ManipError, UnknownNameError
from manip.planning.options import PlanOptions
from manip.pose import Pose
from manip.robot_config import CONFIG_FILE, RobotConfig, available_robots, load_robot_config
from manip.robot_arms import state_columns
from manip.validation import as_real_array, integer, vec

#: A problem id: an int (default: the problem's index in the batch) or a string.
ProblemId = int | str

#: RRT iterations of a batch plan's main search (`PlanOptions.search_iterations`): a count, so a
#: batch plans the same on any machine. The seeded problems of `benchmarks/batch.py` (200, batch
#: seeds 0-5) and of `manip.datagen` (2,200, seeds 0-1), a 120 s budget: all solved but 5 datagen
#: pairs (20,000 iterations without a path, 5.6-8.7 s each), every solved one within 4,100
#: iterations except cage/28, whose search needs 1,600-14,600 (median 2,000, 46 seeds); at
#: 10,000 it is solved with 44 of 46 seeds, every other problem is unchanged, and a search that
#: finds nothing stops after 2.1-2.9 s (measured: datagen 2,000 pairs planned in 40.6 s, against
#: 56.4 s with a single call's 5 s budget, whose 5 TIMEOUTs depend on the machine). 5,000:
#: cage/28 34 of 46. BENCHMARKS.md, "Batch planning", run K.
BATCH_SEARCH_ITERATIONS = 10_000
#: Time budget of a batch plan [s]: only a safety net (the counts bound every stage; a plan cut
#: short by it says so in its message, `planning.context.SAFETY_NET`); the slowest seeded batch
#: plan takes about 3 s on one core of the 2-core VM.
BATCH_TIME_BUDGET = 60.0
#: A batch's planning options where a problem gives none.
BATCH_OPTIONS = {"search_iterations": BATCH_SEARCH_ITERATIONS, "time_budget": BATCH_TIME_BUDGET}


@dataclass(frozen=True)
class Problem:
    """One planning problem: plan `robot` from `start` to `goal` in `world`.

    Attributes:
        world: the obstacles, a cuRobo-style dict ({"cuboid": {name: {"dims": [x, y, z],
            "pose": [x, y, z, qw, qx, qy, qz]}}, ...}) or a `WorldConfig`, in the robot's
            base frame [m].
        start: (dof,) start configuration [rad]; a full robot state (dof + G,), the gripper's
            joints last (`franka.get_joint_positions()`), is taken as its arm joints, as
            `MotionGenerator.plan_joints` takes it.
        goal: (dof,) joint goal [rad] (or a full state, as `start`), or a `Pose` of the
            end-effector link (`plan_pose`).
        robot: robot name (one of `manip.available_robots()`), the path of a robot's
            `robot.yaml` or of its folder, or a `RobotConfig` (e.g. the `config` of a
            `MotionGenerator.from_urdf`), as `MotionGenerator` takes (with backend="ray" the
            model files must exist at the same paths on every node).
        options: planning options: a dict of `PlanOptions` fields except `seed`, or a
            `PlanOptions` whose seed is left at its default (`plan_many` derives each
            problem's seed from its own seed and the problem id). Options not given (in a
            `PlanOptions`: left at their defaults) take the batch's defaults, `BATCH_OPTIONS`
            (a count budget for the search, the clock only a safety net) before the single
            call's; `{"search_iterations": None}` plans until the time budget, as one call does.
        id: an int or a string unique in the batch; None = the problem's index in it.
    """

    world: dict | WorldConfig = field(repr=False)
    start: Any = field(repr=False)
    goal: Any = field(repr=False)
    robot: str | Path | RobotConfig = "franka"
    options: Mapping[str, Any] | PlanOptions | None = None
    id: ProblemId | None = None


@dataclass(frozen=True)
class RobotSpec:
    """A robot given as a `RobotConfig`, as tasks carry it: equal and hashed by `key` alone.

    Attributes:
        key: "<name>#<digest of the configuration>" (equal configurations, equal keys).
        config: the configuration.
    """

    key: str
    config: RobotConfig = field(compare=False, repr=False)

    def __str__(self) -> str:
        return self.key


@dataclass(frozen=True)
class Task:
    """A validated problem as a worker receives it (picklable).

    Attributes:
        id: the problem id.
        robot: robot name, the resolved path of a robot.yaml, or a `RobotSpec`.
        world: the world as given (dict or WorldConfig); validated.
        world_key: digest of the world's content (equal worlds, equal keys).
        start: (dof,) start [rad].
        goal: (dof,) joint goal [rad] or a Pose.
        options: planning options: the problem's, `BATCH_OPTIONS` where it gives none, and the
            derived `seed`.
    """

    id: ProblemId
    robot: str | RobotSpec
    world: dict | WorldConfig = field(repr=False)
    world_key: str
    start: np.ndarray = field(repr=False)
    goal: np.ndarray | Pose = field(repr=False)
    options: dict[str, Any]


def problem_seed(seed: int, problem_id: ProblemId) -> int:
    """The planning seed of one problem, derived from the batch seed and the problem id.

    It depends on nothing else (not on the backend, the worker count or the order of
    completion), so a problem plans the same wherever it runs.

    Args:
        seed: the batch seed (>= 0).
        problem_id: an int or a string.

    Returns:
        A seed in [0, 2**32).
    """
    seed = integer(seed, "seed", 0)
    if isinstance(problem_id, str):
        digest = hashlib.sha256(problem_id.encode()).digest()
        key = (1, int.from_bytes(digest[:8], "little"))
    else:
        key = (0, integer(problem_id, "problem id", 0))
    return int(np.random.SeedSequence(seed, spawn_key=key).generate_state(1)[0])


@lru_cache(maxsize=None)
def _config(robot: str) -> RobotConfig:
    return load_robot_config(robot)


def _arm_values(value: Any, config: RobotConfig, what: str) -> Any:
    """A full robot state (dof + G,), the gripper's G joints last (each arm's state in turn on a
    multi-arm robot), as its arm joints (dof,), as `MotionGenerator` takes it; anything else as
    given (`vec` checks it)."""
    a = as_real_array(value, what)
    g = len(config.gripper.joints) if config.gripper is not None else 0
    if not g or a.shape != (config.dof + g,):
        return value
    return a[state_columns(config.arms)] if config.arms else a[:config.dof]


def _robot(robot: Any, robots: list[str], where: str) -> str | RobotSpec:
    """A problem's robot as a task carries it: a shipped robot's name, a robot.yaml's resolved
    path, or a `RobotSpec` of a RobotConfig."""
    if isinstance(robot, RobotConfig):
        return RobotSpec(f"{robot.name}#{hashlib.sha1(pickle.dumps(robot, protocol=5)).hexdigest()[:12]}", robot)
    if isinstance(robot, str) and robot in robots:
        return robot
    if isinstance(robot, (str, Path)) and str(robot):
        path = Path(robot).expanduser()
        looks_like_path = isinstance(robot, Path) or "/" in str(robot) or path.suffix in (".yaml", ".yml")
        if path.is_dir() and (path / CONFIG_FILE).is_file():
            return str((path / CONFIG_FILE).resolve())
        if path.suffix in (".yaml", ".yml") and path.is_file():
            return str(path.resolve())
        if looks_like_path:
            raise InvalidInputError(f"{where}: robot {str(robot)!r} is neither a robot.yaml file nor a folder holding "
                                    f"one; shipped robots: {', '.join(robots)}")
    raise UnknownNameError("robot", str(robot), robots)


def _world_key(world: dict | WorldConfig) -> str:
    if isinstance(world, dict):
        text = json.dumps(world, sort_keys=True, default=lambda o: np.asarray(o).tolist()).encode()
    else:
        text = pickle.dumps(world, protocol=5)
    return hashlib.sha1(text).hexdigest()


def _check_world(world: Any, where: str) -> None:
    if isinstance(world, WorldConfig):
        return
    if not isinstance(world, dict):
        raise InvalidInputError(f"{where}: world must be a cuRobo-style dict or a WorldConfig; "
                                f"got {type(world).__name__}")
    try:
        WorldConfig.from_dict(world)
    except ManipError as exc:
        raise InvalidInputError(f"{where}: malformed world: {exc}") from exc
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
        raise InvalidInputError(f"{where}: malformed world ({type(exc).__name__}: {exc})") from exc


def _check_options(options: Any, where: str) -> dict[str, Any]:
    """A problem's options as a dict with BATCH_OPTIONS where it gives none (without `seed`)."""
    if options is None:
        return dict(BATCH_OPTIONS)
    if isinstance(options, PlanOptions):
        if options.seed != PlanOptions.seed:
            raise InvalidInputError(
                f"{where}: options.seed must stay at its default ({PlanOptions.seed}); got {options.seed}: each "
                "problem's seed is derived from plan_many's seed and the problem id (manip.batch.problem_seed)"
            )
        default = PlanOptions()
        return {**BATCH_OPTIONS, **{f.name: getattr(options, f.name) for f in fields(PlanOptions)
                                    if getattr(options, f.name) != getattr(default, f.name)}}
    if not isinstance(options, Mapping):
        raise InvalidInputError(f"{where}: options must be a dict of PlanOptions fields or a PlanOptions; "
                                f"got {type(options).__name__}")
    options = dict(options)
    if "seed" in options:
        raise InvalidInputError(
            f"{where}: options may not hold 'seed': each problem's seed is derived from plan_many's seed and the "
            "problem id (manip.batch.problem_seed)"
        )
    try:
        PlanOptions().updated(options)
    except ManipError as exc:
        raise InvalidInputError(f"{where}: {exc}") from exc
    return {**BATCH_OPTIONS, **options}


def prepare(problems: Iterable[Problem], seed: int) -> list[Task]:
    """Validate a batch and turn it into tasks (in input order).

    Args:
        problems: the problems.
        seed: the batch seed (>= 0).

    Returns:
        One `Task` per problem.

    Raises:
        UnknownNameError: an unknown robot (the message lists the valid ones).
        RobotConfigError: a robot.yaml given by path is malformed.
        InvalidInputError: anything else wrong (a robot path without a robot.yaml, not a
            Problem, malformed world, wrong shapes, NaN, bad or forbidden options, a
            duplicate or bad id); the message names the problem.
    """
    seed = integer(seed, "seed", 0)
    if isinstance(problems, (Problem, dict, str)) or not isinstance(problems, Iterable):
        raise InvalidInputError(f"problems must be an iterable of manip.batch.Problem; got {type(problems).__name__}")
    tasks: list[Task] = []
    seen: dict[ProblemId, int] = {}
    world_keys: dict[int, str] = {}  # id(world) -> key: a shared world object is hashed once
    robots = available_robots()
    for index, p in enumerate(problems):
        if not isinstance(p, Problem):
            raise InvalidInputError(f"problems[{index}] must be a manip.batch.Problem; got {type(p).__name__}")
        pid = index if p.id is None else p.id
        if isinstance(pid, bool) or not isinstance(pid, (int, np.integer, str)):
            raise InvalidInputError(f"problems[{index}].id must be an int, a str or None; got {pid!r}")
        pid = pid if isinstance(pid, str) else integer(pid, f"problems[{index}].id", 0)
        if pid in seen:
            raise InvalidInputError(f"problems[{index}]: id {pid!r} is also the id of problems[{seen[pid]}]; "
                                    "ids must be unique")
        seen[pid] = index
        where = f"problem {pid!r} (problems[{index}])"
        robot = _robot(p.robot, robots, where)
        config = robot.config if isinstance(robot, RobotSpec) else _config(robot)
        dof = config.dof
        _check_world(p.world, where)
        start = vec(_arm_values(p.start, config, f"{where}: start"), dof, f"{where}: start")
        if isinstance(p.goal, Pose):
            if p.goal.is_batch:
                raise InvalidInputError(f"{where}: goal must be a single Pose; got a batch of {len(p.goal)}")
            goal: np.ndarray | Pose = p.goal
        else:
            try:
                goal = vec(_arm_values(p.goal, config, f"{where}: goal"), dof, f"{where}: goal")
            except InvalidInputError as exc:
                raise InvalidInputError(
                    f"{exc} (a joint goal is ({dof},) [rad]; a pose goal is a manip.Pose)") from None
        options = _check_options(p.options, where)
        options["seed"] = problem_seed(seed, pid)
        key = world_keys.get(id(p.world))
        if key is None:
            key = world_keys[id(p.world)] = _world_key(p.world)
        tasks.append(Task(pid, robot, p.world, key, start, goal, options))
    return tasks
