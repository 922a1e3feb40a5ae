"""MotionBenchMaker (MBM) Panda problems, read straight from the published `.tar.bz2`.

The archive holds `problems/<scene>/sceneNNNN.yaml` (a MoveIt PlanningScene: boxes and
cylinders) and `problems/<scene>/requestNNNN.yaml` (a MoveIt MotionPlanRequest: start state
and joint goal). This module turns each pair into an `MBMProblem` whose world is in cuRobo's
world format, the format `manip.WorldConfig.from_dict` reads:

    {"cuboid":   {name: {"dims": [x, y, z], "pose": [x, y, z, qw, qx, qy, qz]}},
     "cylinder": {name: {"radius": r, "height": h, "pose": [x, y, z, qw, qx, qy, qz]}}}

Two conversions matter (Chamzas et al., RA-L 2022; see the dataset's README):
MBM orientations are ROS order (x, y, z, w) and become (w, x, y, z) here; MBM cylinder
dimensions are [height, radius].

The archive ships with the repository (`benchmarks/data/mbm/`, Apache-2.0 from VAMP; not in
the wheel) and is read without unpacking it to disk; `MANIP_MBM_DATASET` or a path argument
points at another copy.
"""

from __future__ import annotations

import logging
import os
import re
import tarfile
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
import yaml

from manip.errors import InvalidInputError, UnknownNameError
from manip.pose import Pose

log = logging.getLogger(__name__)

ENV_VAR = "MANIP_MBM_DATASET"

#: The seven scenes of the Panda problem set, 100 problems each.
MBM_SCENES: tuple[str, ...] = (
    "bookshelf_small_panda",
    "bookshelf_tall_panda",
    "bookshelf_thin_panda",
    "box_panda",
    "cage_panda",
    "table_pick_panda",
    "table_under_pick_panda",
)

ARM_JOINTS: tuple[str, ...] = tuple(f"panda_joint{i}" for i in range(1, 8))

_MEMBER = re.compile(r"(?:^|/)problems/([^/]+)/(scene|request)(\d+)\.ya?ml$")

try:  # libyaml is ~10x faster on the 1400 files; fall back to the pure-Python loader.
    _Loader = yaml.CSafeLoader
except AttributeError:  # pragma: no cover
    _Loader = yaml.SafeLoader


@dataclass(frozen=True)
class MBMProblem:
    """One motion planning problem: a world, a start and a joint-space goal.

    Attributes:
        scene: scene family, e.g. "box_panda" (or a seeded kind such as "seeded_table").
        index: problem number within the scene (1-based for MBM).
        world: obstacles in cuRobo's world format (poses [x, y, z, qw, qx, qy, qz] in the
            robot base frame `panda_link0`, sizes in m).
        start: (7,) start configuration of the arm joints [rad]; fingers are open (0.04 m).
        goal: (7,) goal configuration of the arm joints [rad].
        joint_names: names of the 7 arm joints, in the order of `start` and `goal`.
    """

    scene: str
    index: int
    world: dict = field(repr=False)
    start: np.ndarray = field(repr=False)
    goal: np.ndarray = field(repr=False)
    joint_names: tuple[str, ...] = ARM_JOINTS

    @property
    def name(self) -> str:
        """"<scene>/<index>", e.g. "box_panda/1"."""
        return f"{self.scene}/{self.index}"


def repo_root() -> Path:
    """The source checkout this module lives in (two folders above `manip/benchmarking`)."""
    return Path(__file__).resolve().parents[2]


def default_dataset_path() -> Path:
    """Where the dataset is looked for when no path is given.

    `$MANIP_MBM_DATASET` if set, else the copy shipped in the repository,
    `<repo root>/benchmarks/data/mbm/panda_problems.tar.bz2` (not in the wheel). The path may
    not exist (an installed wheel); `dataset_available()` says whether it does.
    """
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env).expanduser()
    return repo_root() / "benchmarks" / "data" / "mbm" / "panda_problems.tar.bz2"


def dataset_available(path: str | Path | None = None) -> bool:
    """True when the archive (or unpacked folder) at `path` (default location if None) exists."""
    p = Path(path) if path is not None else default_dataset_path()
    return p.exists()


def _xyzw_pose_to_wxyz(pose: dict) -> list[float]:
    pos = [float(v) for v in pose["position"]]
    x, y, z, w = (float(v) for v in pose["orientation"])
    n = float(np.sqrt(w * w + x * x + y * y + z * z))
    if n < 1e-9:
        raise InvalidInputError(f"MBM pose has a zero quaternion: {pose}")
    return pos + [w / n, x / n, y / n, z / n]


def scene_to_world(scene: dict) -> dict:
    """Convert a MoveIt PlanningScene (as parsed YAML) to cuRobo's world format.

    Each primitive becomes one entry named after its collision object's `id` (with `_<k>`
    appended when an object has several primitives). Box dimensions are full edge lengths;
    cylinder dimensions are [height, radius]; orientations go from (x, y, z, w) to (w, x, y, z).

    Raises:
        InvalidInputError: a primitive type other than box/cylinder, or malformed fields.
    """
    world: dict[str, dict] = {"cuboid": {}, "cylinder": {}}
    objects = (scene.get("world") or {}).get("collision_objects") or []
    for obj in objects:
        oid = str(obj.get("id", "object"))
        prims = obj.get("primitives") or []
        poses = obj.get("primitive_poses") or []
        if len(prims) != len(poses):
            raise InvalidInputError(f"collision object '{oid}': {len(prims)} primitives but {len(poses)} poses")
        for k, (prim, pose) in enumerate(zip(prims, poses)):
            name = oid if len(prims) == 1 else f"{oid}_{k}"
            if name in world["cuboid"] or name in world["cylinder"]:
                name = f"{name}_{k}"
            kind = prim.get("type")
            dims = [float(v) for v in prim.get("dimensions", [])]
            p = _xyzw_pose_to_wxyz(pose)
            if kind == "box":
                if len(dims) != 3:
                    raise InvalidInputError(f"box '{name}' needs 3 dimensions, got {dims}")
                world["cuboid"][name] = {"dims": dims, "pose": p}
            elif kind == "cylinder":
                if len(dims) != 2:
                    raise InvalidInputError(f"cylinder '{name}' needs [height, radius], got {dims}")
                world["cylinder"][name] = {"radius": dims[1], "height": dims[0], "pose": p}
            else:
                raise InvalidInputError(f"primitive '{name}' has type '{kind}'; MBM loader supports: box, cylinder")
    return {k: v for k, v in world.items() if v}


def _request_states(request: dict) -> tuple[np.ndarray, np.ndarray]:
    js = request["start_state"]["joint_state"]
    start_map = dict(zip(js["name"], js["position"]))
    goal_map = {c["joint_name"]: c["position"] for c in request["goal_constraints"][0]["joint_constraints"]}
    try:
        start = np.array([float(start_map[j]) for j in ARM_JOINTS])
        goal = np.array([float(goal_map[j]) for j in ARM_JOINTS])
    except KeyError as exc:
        raise InvalidInputError(f"MBM request lacks joint {exc}; expected {list(ARM_JOINTS)}") from None
    return start, goal


def _read_members(path: Path) -> dict[tuple[str, str, int], bytes]:
    """Raw bytes of every scene/request file, keyed by (scene, kind, index)."""
    out: dict[tuple[str, str, int], bytes] = {}
    if path.is_dir():
        for f in path.rglob("*.yaml"):
            m = _MEMBER.search(f.as_posix())
            if m:
                out[(m.group(1), m.group(2), int(m.group(3)))] = f.read_bytes()
        return out
    with tarfile.open(path, "r:*") as tar:
        for member in tar:
            if not member.isfile():
                continue
            m = _MEMBER.search(member.name)
            if m:
                fh = tar.extractfile(member)
                if fh is not None:
                    out[(m.group(1), m.group(2), int(m.group(3)))] = fh.read()
    return out


@lru_cache(maxsize=4)
def _load_all(path: str, mtime: float) -> tuple[MBMProblem, ...]:
    raw = _read_members(Path(path))
    problems = []
    keys = sorted(k for k in raw if k[1] == "request")
    for scene, _, idx in keys:
        scene_bytes = raw.get((scene, "scene", idx))
        if scene_bytes is None:
            log.warning("MBM %s/request%04d has no scene file; skipped", scene, idx)
            continue
        request = yaml.load(raw[(scene, "request", idx)], Loader=_Loader)
        world = scene_to_world(yaml.load(scene_bytes, Loader=_Loader))
        start, goal = _request_states(request)
        start.setflags(write=False)
        goal.setflags(write=False)
        problems.append(MBMProblem(scene=scene, index=idx, world=world, start=start, goal=goal))
    return tuple(problems)


def load_mbm_problems(
    path: str | Path | None = None,
    scenes: list[str] | tuple[str, ...] | None = None,
    limit_per_scene: int | None = None,
) -> list[MBMProblem]:
    """Load the MotionBenchMaker Panda problems.

    Args:
        path: the `panda_problems.tar.bz2` archive (or a folder it was unpacked to). Default:
            `default_dataset_path()` (`$MANIP_MBM_DATASET`, else the repository's
            `benchmarks/data/mbm/`).
        scenes: scene names to keep (default: all, sorted); see `MBM_SCENES`.
        limit_per_scene: keep only the first N problems (by index) of each scene.

    Returns:
        Problems sorted by scene then index. Arrays are read-only; the world dicts are
        shared between calls, so copy them before modifying.

    Raises:
        FileNotFoundError: the dataset is not at `path`.
        UnknownNameError: a scene name that is not in the dataset.
        InvalidInputError: a negative `limit_per_scene`.
    """
    p = Path(path).expanduser() if path is not None else default_dataset_path()
    if not p.exists():
        raise FileNotFoundError(
            f"MotionBenchMaker dataset not found at {p}; pass its path or set ${ENV_VAR} (the "
            "archive ships in manip's repository under benchmarks/data/mbm/, not in the wheel)"
        )
    if limit_per_scene is not None and limit_per_scene < 0:
        raise InvalidInputError(f"limit_per_scene must be >= 0 or None; got {limit_per_scene}")
    allp = _load_all(str(p.resolve()), p.stat().st_mtime)
    available = sorted({q.scene for q in allp})
    if scenes is not None:
        for s in scenes:
            if s not in available:
                raise UnknownNameError("MBM scene", s, available)
        keep = set(scenes)
    else:
        keep = set(available)
    out: list[MBMProblem] = []
    count: dict[str, int] = {}
    for q in allp:
        if q.scene not in keep:
            continue
        if limit_per_scene is not None and count.get(q.scene, 0) >= limit_per_scene:
            continue
        count[q.scene] = count.get(q.scene, 0) + 1
        out.append(q)
    return out


@lru_cache(maxsize=1)
def _franka_kinematics():
    from manip.kinematics import Kinematics
    from manip.robot_config import load_robot_config

    return Kinematics(load_robot_config("franka"))


def goal_pose(problem: MBMProblem, link: str = "panda_hand") -> Pose:
    """The pose goal of a problem: forward kinematics of its goal configuration at `link`.

    This is how cuRobo's benchmark poses pose-goal problems (fingers open, 0.04 m).

    Returns:
        Pose of `link` in the robot base frame (position [m], quaternion wxyz).
    """
    return _franka_kinematics().fk(np.asarray(problem.goal, dtype=float), link)
