"""Robot configurations: `robots/<name>/robot.yaml` files, resolved to model paths.

A second robot is added by writing a folder with a `robot.yaml` like `robots/franka/`;
no code changes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np
import yaml

from manip.errors import RobotConfigError, UnknownNameError

CONFIG_FILE = "robot.yaml"


def robots_root() -> Path:
    """The folder holding the robot configurations and models.

    In an installed wheel it is `manip/_robots`; in a source checkout (or an editable
    install) it is the repository's top-level `robots/`.
    """
    here = Path(__file__).resolve().parent
    for candidate in (here / "_robots", here.parent / "robots"):
        if candidate.is_dir():
            return candidate
    raise RobotConfigError(f"robot folder not found next to {here} (looked for _robots/ and ../robots/)")


def available_robots() -> list[str]:
    """Names of the robots with a configuration under `robots_root()`."""
    return sorted(p.parent.name for p in robots_root().glob(f"*/{CONFIG_FILE}"))


def _resolve_file(entry: str | dict | None, folder: Path, what: str) -> Path | None:
    if entry is None:
        return None
    if isinstance(entry, str):
        path = (folder / entry).resolve()
    else:
        package = entry.get("package")
        rel = entry.get("path")
        if rel is None:
            raise RobotConfigError(f"{what}: a 'path' is required, got {entry}")
        if package is None:
            path = (folder / rel).resolve()
        else:
            try:
                dist = metadata.distribution(package)
            except metadata.PackageNotFoundError as exc:
                raise RobotConfigError(f"{what}: package '{package}' is not installed (pip install {package})") from exc
            path = Path(str(dist.locate_file(entry.get("package_root", "")))) / rel
    if not path.exists():
        raise RobotConfigError(f"{what}: file not found: {path}")
    return path


def _package_dirs(path: Path) -> list[str]:
    """Folders to resolve `package://` URIs in a URDF: each ancestor of the file."""
    return [str(p) for p in path.parents]


@dataclass(frozen=True)
class GripperConfig:
    """Finger joints and their open/closed positions [m]."""

    joints: tuple[str, ...]
    open_positions: np.ndarray
    closed_positions: np.ndarray
    planning_positions: np.ndarray


@dataclass(frozen=True)
class RobotConfig:
    """Everything manip needs to know about one robot.

    Array fields have one entry per arm joint, in `arm_joints` order, in SI units.
    """

    name: str
    folder: Path
    urdf_path: Path
    srdf_path: Path | None
    mjcf_path: Path | None
    package_dirs: tuple[str, ...]
    base_link: str
    ee_link: str
    tcp_link: str | None
    arm_joints: tuple[str, ...]
    default_joint_positions: np.ndarray
    lower_limits: np.ndarray
    upper_limits: np.ndarray
    velocity_limits: np.ndarray
    acceleration_limits: np.ndarray
    jerk_limits: np.ndarray
    gripper: GripperConfig | None
    collision_padding: float
    disabled_collision_pairs: tuple[tuple[str, str], ...]
    raw: dict = field(repr=False, default_factory=dict)

    @property
    def dof(self) -> int:
        """Number of arm joints."""
        return len(self.arm_joints)


def _array(d: dict, key: str, n: int, folder: Path) -> np.ndarray:
    if key not in d:
        raise RobotConfigError(f"{folder / CONFIG_FILE}: missing '{key}'")
    a = np.asarray(d[key], dtype=float)
    if a.shape != (n,):
        raise RobotConfigError(f"{folder / CONFIG_FILE}: '{key}' must have {n} entries (one per arm joint); got {a.shape}")
    return a


def load_robot_config(name_or_path: str | Path) -> RobotConfig:
    """Load a robot configuration by name ("franka") or by the path of a robot.yaml/folder.

    Raises:
        UnknownNameError: no robot of that name; the message lists the available ones.
        RobotConfigError: the file is malformed or names missing model files.
    """
    if not isinstance(name_or_path, (str, Path)) or not str(name_or_path):
        raise UnknownNameError("robot", repr(name_or_path), available_robots())
    candidate = Path(name_or_path)
    if candidate.suffix in (".yaml", ".yml") and candidate.is_file():
        cfg_file = candidate
    elif candidate.is_dir() and (candidate / CONFIG_FILE).is_file():
        cfg_file = candidate / CONFIG_FILE
    else:
        cfg_file = robots_root() / str(name_or_path) / CONFIG_FILE
        if not cfg_file.is_file():
            raise UnknownNameError("robot", str(name_or_path), available_robots())
    folder = cfg_file.parent.resolve()
    with open(cfg_file) as f:
        d = yaml.safe_load(f)
    if not isinstance(d, dict):
        raise RobotConfigError(f"{cfg_file}: expected a mapping at the top level")

    urdf = _resolve_file(d.get("urdf"), folder, "urdf")
    if urdf is None:
        raise RobotConfigError(f"{cfg_file}: 'urdf' is required")
    srdf = _resolve_file(d.get("srdf"), folder, "srdf")
    # The MuJoCo model is only needed by manip.sim, which checks that it exists.
    mjcf = (folder / d["mjcf"]).resolve() if d.get("mjcf") else None

    joints = tuple(d.get("arm_joints", ()))
    if not joints:
        raise RobotConfigError(f"{cfg_file}: 'arm_joints' must list the planned joints")
    n = len(joints)
    g = d.get("gripper")
    gripper = None
    if g:
        gj = tuple(g["joints"])
        def _g(key: str, default=None) -> np.ndarray:
            v = np.asarray(g.get(key, default), dtype=float)
            if v.shape != (len(gj),):
                raise RobotConfigError(f"{cfg_file}: gripper '{key}' needs {len(gj)} entries")
            return v
        gripper = GripperConfig(gj, _g("open_positions"), _g("closed_positions"),
                                _g("planning_positions", g.get("open_positions")))
    col = d.get("collision", {}) or {}
    pairs = tuple((str(a), str(b)) for a, b in col.get("disabled_pairs", []))
    lower = _array(d, "lower_limits", n, folder)
    upper = _array(d, "upper_limits", n, folder)
    if np.any(lower >= upper):
        raise RobotConfigError(f"{cfg_file}: every lower limit must be below its upper limit")
    default = _array(d, "default_joint_positions", n, folder)
    if np.any(default < lower) or np.any(default > upper):
        raise RobotConfigError(f"{cfg_file}: default_joint_positions lie outside the limits")
    return RobotConfig(
        name=str(d.get("name", folder.name)),
        folder=folder,
        urdf_path=urdf,
        srdf_path=srdf,
        mjcf_path=mjcf,
        package_dirs=tuple(_package_dirs(urdf)),
        base_link=str(d["base_link"]),
        ee_link=str(d["ee_link"]),
        tcp_link=d.get("tcp_link"),
        arm_joints=joints,
        default_joint_positions=default,
        lower_limits=lower,
        upper_limits=upper,
        velocity_limits=_array(d, "velocity_limits", n, folder),
        acceleration_limits=_array(d, "acceleration_limits", n, folder),
        jerk_limits=_array(d, "jerk_limits", n, folder),
        gripper=gripper,
        collision_padding=float(col.get("padding", 0.0)),
        disabled_collision_pairs=pairs,
        raw=d,
    )
