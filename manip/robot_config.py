"""Robot configurations: `robots/<name>/robot.yaml` files, resolved to model paths.

A second robot is added by writing a folder with a `robot.yaml` like `robots/franka/`;
no code changes. A robot without a folder is configured from its URDF (and SRDF) alone
with `config_from_urdf`. A key a robot.yaml does not know (`colision:`, `collision:
paddign:`) raises RobotConfigError listing the valid keys; keys starting with `x_` are
extension keys, kept in `RobotConfig.raw` and ignored.

Self-collision pairs: the SRDF's `<disable_collisions>` pairs are never checked; the yaml's
`collision: disabled_pairs` only adds pairs, and `collision: disable_adjacent_links: true`
adds the pairs of adjacent links. Without an SRDF, or with an SRDF that lists no pair, the
adjacent links are skipped and every other pair is checked (logged).
"""

from __future__ import annotations

import difflib
import logging
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np
import yaml

from manip import package_uri
from manip.errors import InvalidInputError, RobotConfigError, UnknownNameError
from manip.limits import JointLimits
from manip.robot_arms import DEFAULT_BASE_LINK, Arm, ArmSpec, arm_specs, compose_files
from manip.urdf import MOVABLE_TYPES, UrdfTree, default_configuration, default_ee_link, disabled_pairs

logger = logging.getLogger(__name__)

#: Defaults of `config_from_urdf` where a URDF says nothing.
DEFAULT_VELOCITY_LIMIT = 2.0       # [rad/s] (or m/s) for joints without a URDF velocity limit
DEFAULT_ACCELERATION_LIMIT = 10.0  # [rad/s^2] on every joint
DEFAULT_JERK_LIMIT = 500.0         # [rad/s^3] on every joint (cuRobo's Franka value)

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
    """Folders where Pinocchio finds the URDF's meshes (`package_uri.package_dirs`)."""
    return list(package_uri.package_dirs(path))


def _check_meshes(tree: UrdfTree) -> None:
    """Raise RobotConfigError naming a collision mesh of `tree` that resolves to no file (its
    URI and the folders searched, `package_uri.resolve`), or that Pinocchio would not find."""
    for _, uri in tree.collision_meshes():
        package_uri.resolve(uri, tree.path, "collision mesh")
    package_uri.check_pinocchio_can_read(tree.path, package_uri.package_dirs(tree.path))


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

    Array fields have one entry per arm joint, in `arm_joints` order, in SI units; the five
    limit arrays are read-only and are also `limits`, one `JointLimits` built from them.
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
    #: The arms of a multi-arm robot (`manip.robot_arms`), in configuration order; () for one arm.
    arms: tuple[Arm, ...] = ()
    limits: JointLimits = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        limits = JointLimits(velocity=self.velocity_limits, acceleration=self.acceleration_limits,
                             jerk=self.jerk_limits, lower=self.lower_limits, upper=self.upper_limits,
                             joint_names=tuple(self.arm_joints))
        object.__setattr__(self, "limits", limits)
        for name, value in (("lower_limits", limits.lower), ("upper_limits", limits.upper),
                            ("velocity_limits", limits.velocity), ("acceleration_limits", limits.acceleration),
                            ("jerk_limits", limits.jerk)):
            object.__setattr__(self, name, value)

    @property
    def dof(self) -> int:
        """Number of arm joints."""
        return len(self.arm_joints)


#: The keys of a robot.yaml. Any other key raises RobotConfigError (a misspelt optional key,
#: such as `colision:`, would otherwise be dropped with its safety margin), except extension
#: keys: a key starting with `x_` (at the top level or in any section) is kept in
#: `RobotConfig.raw` and never read by manip.
CONFIG_KEYS = ("name", "urdf", "srdf", "mjcf", "base_link", "ee_link", "tcp_link", "approach_axis", "arm_joints",
               "default_joint_positions", "lower_limits", "upper_limits", "velocity_limits", "acceleration_limits",
               "jerk_limits", "gripper", "collision", "sim")
#: The keys of a multi-arm robot's robot.yaml (its arms give the rest).
ARMS_CONFIG_KEYS = ("name", "arms", "base_link", "ee_link", "default_joint_positions", "collision")
COLLISION_KEYS = ("padding", "disabled_pairs", "disable_adjacent_links")
#: Keys of `urdf:` / `srdf:` given as a mapping.
FILE_KEYS = ("package", "package_root", "path")
GRIPPER_KEYS = ("joints", "open_positions", "closed_positions", "planning_positions")
#: Keys of `sim:`, read by `manip.sim.mjcf_builder` (drives, armature, gravity, fingers).
SIM_KEYS = ("kp", "kv", "armature", "gravity_compensation", "finger_kp", "finger_kv", "finger_force",
            "finger_armature", "finger_contact")
FINGER_CONTACT_KEYS = ("friction", "condim", "priority", "solref", "solimp")
#: Prefix of extension keys: accepted anywhere in a robot.yaml and ignored by manip.
EXTENSION_PREFIX = "x_"


def _array(d: dict, key: str, n: int, folder: Path, positive: bool = False) -> np.ndarray:
    where = f"{folder / CONFIG_FILE}: '{key}'"
    if key not in d:
        raise RobotConfigError(f"{folder / CONFIG_FILE}: missing '{key}'")
    try:
        a = np.asarray(d[key], dtype=float)
    except (TypeError, ValueError) as exc:
        raise RobotConfigError(f"{where} must be {n} numbers (one per arm joint); got {d[key]!r}") from exc
    if a.shape != (n,):
        raise RobotConfigError(f"{where} must have {n} entries (one per arm joint); got {a.shape}")
    if not np.all(np.isfinite(a)) or (positive and np.any(a <= 0)):
        raise RobotConfigError(f"{where} must be {n} finite{' positive' if positive else ''} numbers; got {a.tolist()}")
    return a


def _names(d: dict, key: str, where: Path) -> tuple[str, ...]:
    value = d.get(key)
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise RobotConfigError(f"{where}: '{key}' must be a list of joint names; got {value!r}")
    if len(set(value)) != len(value):
        raise RobotConfigError(f"{where}: '{key}' must be distinct; got {value}")
    return tuple(value)


def _check_keys(d: dict, valid: tuple[str, ...], where: str) -> None:
    """Raise RobotConfigError naming the keys of `d` that are not in `valid` (nor extension keys)."""
    unknown = sorted(str(k) for k in d if k not in valid and not str(k).startswith(EXTENSION_PREFIX))
    if unknown:
        close = {k: difflib.get_close_matches(k, valid, n=1) for k in unknown}
        hint = "".join(f" ('{k}': did you mean '{m[0]}'?)" for k, m in close.items() if m)
        raise RobotConfigError(
            f"{where}: unknown key(s) {unknown}{hint}; valid: {', '.join(valid)} (a key starting with "
            f"'{EXTENSION_PREFIX}' is an extension key, kept and ignored)")


def _check_sections(d: dict, cfg_file: Path) -> None:
    """Unknown keys at the top level and in every section of a robot.yaml raise (see CONFIG_KEYS)."""
    _check_keys(d, CONFIG_KEYS, str(cfg_file))
    for key in ("urdf", "srdf"):
        if isinstance(d.get(key), dict):
            _check_keys(d[key], FILE_KEYS, f"{cfg_file}: {key}")
    sections = (("gripper", GRIPPER_KEYS), ("collision", COLLISION_KEYS), ("sim", SIM_KEYS))
    for key, valid in sections:
        value = d.get(key)
        if value is None:
            continue
        if not isinstance(value, dict):
            raise RobotConfigError(f"{cfg_file}: '{key}' must be a mapping of {', '.join(valid)}; got {value!r}")
        _check_keys(value, valid, f"{cfg_file}: {key}")
    contact = (d.get("sim") or {}).get("finger_contact")
    if contact is not None:
        if not isinstance(contact, dict):
            raise RobotConfigError(f"{cfg_file}: sim: 'finger_contact' must be a mapping of "
                                   f"{', '.join(FINGER_CONTACT_KEYS)}; got {contact!r}")
        _check_keys(contact, FINGER_CONTACT_KEYS, f"{cfg_file}: sim: finger_contact")


def _check_within_urdf(tree: UrdfTree, joints: tuple[str, ...], lower: np.ndarray, upper: np.ndarray,
                       where: Path) -> None:
    """Raise if a joint is unknown, not movable, or given limits beyond the URDF's."""
    for i, name in enumerate(joints):
        if name not in tree.joints:
            raise UnknownNameError("joint (arm_joints)", name, list(tree.joints))
        j = tree.joints[name]
        if j.type not in MOVABLE_TYPES:
            raise RobotConfigError(f"{where}: arm joint '{name}' is {j.type}; arm joints must be movable")
        if j.lower is not None and j.upper is not None and (lower[i] < j.lower - 1e-9 or upper[i] > j.upper + 1e-9):
            raise RobotConfigError(f"{where}: limits of '{name}' [{lower[i]}, {upper[i]}] exceed the URDF's "
                                   f"[{j.lower}, {j.upper}]")


def load_robot_config(name_or_path: str | Path) -> RobotConfig:
    """Load a robot configuration by name ("franka"; any case) or by the path of a robot.yaml/folder.

    Raises:
        UnknownNameError: no robot of that name, or a link or joint the URDF does not have;
            the message lists the available ones.
        InvalidInputError: `name_or_path` is an object holding a RobotConfig (a MotionGenerator:
            the message says to pass its `.config`).
        RobotConfigError: the file is malformed (missing keys, wrong types, non-finite or
            non-positive limits, limits beyond the URDF's, `ee_link` not below `base_link`)
            or names missing model files, or has a key it does not know, at the top level or
            in a section (`colision`, `collision: paddign`, ...; the message lists the valid
            keys; keys starting with `x_` are extension keys, accepted and ignored).
    """
    if isinstance(getattr(name_or_path, "config", None), RobotConfig):  # a MotionGenerator, say
        raise InvalidInputError(f"robot must be a robot name ({', '.join(available_robots())}), the path of a "
                                f"robot.yaml or its folder, or a RobotConfig; got a {type(name_or_path).__name__}, "
                                "which holds one: pass its .config")
    if not isinstance(name_or_path, (str, Path)) or not str(name_or_path):
        raise UnknownNameError("robot", repr(name_or_path), available_robots())
    candidate = Path(name_or_path)
    if candidate.suffix in (".yaml", ".yml") and candidate.is_file():
        cfg_file = candidate
    elif candidate.is_dir() and (candidate / CONFIG_FILE).is_file():
        cfg_file = candidate / CONFIG_FILE
    else:
        # a shipped robot's name, in any case ("Franka" is "franka")
        names = {n.lower(): n for n in available_robots()}
        name = names.get(str(name_or_path).lower(), str(name_or_path))
        cfg_file = robots_root() / name / CONFIG_FILE
        if not cfg_file.is_file():
            raise UnknownNameError("robot", str(name_or_path), available_robots())
    folder = cfg_file.parent.resolve()
    try:
        with open(cfg_file) as f:
            d = yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as exc:
        raise RobotConfigError(f"{cfg_file}: not a readable YAML file ({exc})") from exc
    if not isinstance(d, dict):
        raise RobotConfigError(f"{cfg_file}: expected a mapping at the top level")
    if "arms" in d:
        return _load_arms_yaml(d, cfg_file, folder)
    _check_sections(d, cfg_file)

    urdf = _resolve_file(d.get("urdf"), folder, "urdf")
    if urdf is None:
        raise RobotConfigError(f"{cfg_file}: 'urdf' is required")
    srdf = _resolve_file(d.get("srdf"), folder, "srdf")
    # The MuJoCo model is only needed by manip.sim, which checks that it exists.
    mjcf = (folder / d["mjcf"]).resolve() if d.get("mjcf") else None

    joints = _names(d, "arm_joints", cfg_file)
    n = len(joints)
    tree = UrdfTree(urdf)
    _check_meshes(tree)
    for key in ("base_link", "ee_link"):
        if not isinstance(d.get(key), str):
            raise RobotConfigError(f"{cfg_file}: '{key}' must name a link of the URDF; got {d.get(key)!r}")
        tree.check_link(d[key], key)
    if d.get("tcp_link") is not None:
        tree.check_link(str(d["tcp_link"]), "tcp_link")
    tree.chain_joints(d["base_link"], d["ee_link"])  # raises if ee_link is not below base_link
    g = d.get("gripper")
    gripper = None
    if g:
        gj = _names(g, "joints", cfg_file)
        for j in gj:
            if j not in tree.joints:
                raise UnknownNameError("joint (gripper: joints)", j, list(tree.joints))
        def _g(key: str, default=None) -> np.ndarray:
            try:
                v = np.asarray(g.get(key, default), dtype=float)
            except (TypeError, ValueError):
                v = np.zeros(0)
            if v.shape != (len(gj),) or not np.all(np.isfinite(v)):
                raise RobotConfigError(f"{cfg_file}: gripper '{key}' needs {len(gj)} finite numbers [m]")
            return v
        gripper = GripperConfig(gj, _g("open_positions"), _g("closed_positions"),
                                _g("planning_positions", g.get("open_positions")))
    col = d.get("collision", {}) or {}
    try:
        padding = float(col.get("padding", 0.0))
        extra = [(str(a), str(b)) for a, b in col.get("disabled_pairs", []) or []]
    except (TypeError, ValueError) as exc:
        raise RobotConfigError(f"{cfg_file}: collision: 'padding' must be a number [m] and 'disabled_pairs' a list "
                               f"of [link, link] pairs ({exc})") from exc
    unknown = sorted({name for pair in extra for name in pair} - set(tree.links))
    if unknown:
        raise UnknownNameError("link (collision: disabled_pairs)", unknown[0], tree.links)
    pairs = disabled_pairs(tree, srdf, extra, bool(col.get("disable_adjacent_links", False)))
    lower = _array(d, "lower_limits", n, folder)
    upper = _array(d, "upper_limits", n, folder)
    if np.any(lower >= upper):
        raise RobotConfigError(f"{cfg_file}: every lower limit must be below its upper limit")
    _check_within_urdf(tree, joints, lower, upper, cfg_file)
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
        velocity_limits=_array(d, "velocity_limits", n, folder, positive=True),
        acceleration_limits=_array(d, "acceleration_limits", n, folder, positive=True),
        jerk_limits=_array(d, "jerk_limits", n, folder, positive=True),
        gripper=gripper,
        collision_padding=padding,
        disabled_collision_pairs=pairs,
        raw=d,
    )


def config_from_urdf(
    urdf: str | Path,
    srdf: str | Path | None = None,
    *,
    base_link: str | None = None,
    ee_link: str | None = None,
    arm_joints: list[str] | None = None,
    default_joint_positions: np.ndarray | str | None = None,
    acceleration_limits: float | np.ndarray | None = None,
    jerk_limits: float | np.ndarray | None = None,
    name: str | None = None,
) -> RobotConfig:
    """A robot configuration from a URDF (and SRDF) alone, for a robot without a folder.

    Position and velocity limits come from the URDF (continuous joints: +-2 pi; a joint
    without a velocity limit gets DEFAULT_VELOCITY_LIMIT = 2 rad/s). Acceleration and
    jerk limits are not in a URDF: unless given they are DEFAULT_ACCELERATION_LIMIT = 10
    rad/s^2 and DEFAULT_JERK_LIMIT = 500 rad/s^3 on every joint. The default configuration
    is the SRDF's first named state (group_state) that sets every arm joint within the
    limits (a revolute joint's value may be turned by whole turns, 2 pi, to get there: the
    same pose), else the middle of the limits. Each assumed default is logged as a warning.
    A misspelt SRDF raises instead of falling back to the middle: a group_state that sets
    some arm joints and names a joint the URDF does not have, or group_states setting
    every arm joint of which none lies within the limits.
    Joints not in the arm (fingers, ...) are locked at zero; there is no gripper.

    Args:
        urdf: the .urdf file; `package://` mesh URIs are resolved as ROS tools do (its own
            package's folder, ROS_PACKAGE_PATH, AMENT_PREFIX_PATH, the Python environment's
            prefixes: `manip.package_uri`).
        srdf: the .srdf file whose disabled collision pairs are skipped; None (or an SRDF
            that lists no pair): the adjacent links are skipped and every other pair is checked.
        base_link: root of the planned chain; default the URDF's root link.
        ee_link: the link pose goals are given for; default the `parent_link` of the SRDF's
            first `<end_effector>`, else the deepest link below `base_link` (the one with
            the most movable joints above it).
        arm_joints: the planned joints (movable, distinct); default the movable joints from
            `base_link` to `ee_link`.
        default_joint_positions: (dof,) [rad], or the name of an SRDF group_state; see
            above for the default.
        acceleration_limits: one value or (dof,) [rad/s^2].
        jerk_limits: one value or (dof,) [rad/s^3].
        name: the robot's name; default the URDF's robot name.

    Raises:
        RobotConfigError: unreadable files, collision meshes not found, no movable joint, bad
            limits, a default configuration that is not finite or not within the limits, a
            misspelt SRDF group_state (see above).
        UnknownNameError: an unknown link, joint or group_state, or an SRDF
            `<disable_collisions>` pair naming a link the URDF does not have (the message
            lists the valid ones).
    """
    urdf_path = Path(urdf).resolve()
    if not urdf_path.is_file():
        raise RobotConfigError(f"urdf: file not found: {urdf_path}")
    srdf_path = None if srdf is None else Path(srdf).resolve()
    if srdf_path is not None and not srdf_path.is_file():
        raise RobotConfigError(f"srdf: file not found: {srdf_path}")
    tree = UrdfTree(urdf_path)
    _check_meshes(tree)
    base = base_link or tree.root_link
    tree.check_link(base)
    ee = ee_link or default_ee_link(tree, base, srdf_path)
    tree.check_link(ee)
    if arm_joints is None:
        joints = tuple(j.name for j in tree.chain_joints(base, ee))
    else:
        joints = tuple(arm_joints)
        for j in joints:
            if j not in tree.joints:
                raise UnknownNameError("joint", j, list(tree.joints))
        fixed = [j for j in joints if tree.joints[j].type not in MOVABLE_TYPES]
        if fixed:
            raise RobotConfigError(f"{urdf_path}: arm joints {fixed} are not movable ({tree.joints[fixed[0]].type}); "
                                   f"arm joints must be {', '.join(MOVABLE_TYPES)}")
        if len(set(joints)) != len(joints):
            raise RobotConfigError(f"arm_joints must be distinct; got {list(joints)}")
    if not joints:
        raise RobotConfigError(f"{urdf_path}: no movable joint between '{base}' and '{ee}'")
    n = len(joints)
    spec = [tree.joints[j] for j in joints]
    missing = [j.name for j in spec if j.lower is None or j.upper is None]
    if missing:
        raise RobotConfigError(f"{urdf_path}: joints {missing} have no position limits in the URDF")
    lower = np.array([j.lower for j in spec], dtype=float)
    upper = np.array([j.upper for j in spec], dtype=float)
    if np.any(lower >= upper):
        raise RobotConfigError(f"{urdf_path}: every lower limit must be below its upper limit")
    no_vel = [j.name for j in spec if not j.velocity]
    if no_vel:
        logger.warning("%s: no velocity limit for %s; assuming %g rad/s", urdf_path.name, no_vel,
                       DEFAULT_VELOCITY_LIMIT)
    velocity = np.array([j.velocity or DEFAULT_VELOCITY_LIMIT for j in spec], dtype=float)

    def per_joint(value, default: float, what: str, unit: str) -> np.ndarray:
        if value is None:
            logger.warning("%s: %s not given; assuming %g %s on every joint", urdf_path.name, what, default, unit)
            value = default
        a = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy() if np.ndim(value) == 0 \
            else np.asarray(value, dtype=float)
        if a.shape != (n,) or not np.all(np.isfinite(a)) or np.any(a <= 0):
            raise RobotConfigError(f"{what} must be one positive value or {n} (one per joint); got {value!r}")
        return a

    acc = per_joint(acceleration_limits, DEFAULT_ACCELERATION_LIMIT, "acceleration_limits", "rad/s^2")
    jerk = per_joint(jerk_limits, DEFAULT_JERK_LIMIT, "jerk_limits", "rad/s^3")
    default = default_configuration(default_joint_positions, spec, lower, upper, srdf_path, urdf_path.name,
                                     set(tree.joints))
    return RobotConfig(
        name=name or tree.name,
        folder=urdf_path.parent,
        urdf_path=urdf_path,
        srdf_path=srdf_path,
        mjcf_path=None,
        package_dirs=tuple(_package_dirs(urdf_path)),
        base_link=base,
        ee_link=ee,
        tcp_link=None,
        arm_joints=joints,
        default_joint_positions=default,
        lower_limits=lower,
        upper_limits=upper,
        velocity_limits=velocity,
        acceleration_limits=acc,
        jerk_limits=jerk,
        gripper=None,
        collision_padding=0.0,
        disabled_collision_pairs=disabled_pairs(tree, srdf_path, []),
        raw={},
    )


def _load_arms_yaml(d: dict, cfg_file: Path, folder: Path) -> RobotConfig:
    """A multi-arm robot.yaml (`arms:`, see `compose_robot_config`); an arm's relative folder is
    taken from this file's folder."""
    _check_keys(d, ARMS_CONFIG_KEYS, str(cfg_file))
    col = d.get("collision") or {}
    if not isinstance(col, dict):
        raise RobotConfigError(f"{cfg_file}: 'collision' must be a mapping of {', '.join(COLLISION_KEYS)}")
    _check_keys(col, COLLISION_KEYS, f"{cfg_file}: collision")
    try:
        specs = arm_specs(d["arms"], f"{cfg_file}: arms")
    except InvalidInputError as exc:
        raise RobotConfigError(str(exc)) from exc
    specs = [ArmSpec(s.prefix, folder / s.robot if isinstance(s.robot, str) and (folder / s.robot).is_dir() else s.robot,
                     s.base_pose) for s in specs]
    return compose_robot_config(specs, name=str(d.get("name", folder.name)), base_link=d.get("base_link"),
                                ee_link=d.get("ee_link"), default_joint_positions=d.get("default_joint_positions"),
                                padding=col.get("padding"), disabled_pairs=col.get("disabled_pairs") or (),
                                folder=folder, raw=d)


def compose_robot_config(arms: list[ArmSpec], *, name: str, base_link: str | None = None, ee_link: str | None = None,
                         default_joint_positions=None, padding: float | None = None, disabled_pairs=(),
                         folder: Path | None = None, raw: dict | None = None) -> RobotConfig:
    """One RobotConfig of several arms (`manip.robot_arms`): the combined URDF and SRDF, each
    arm's joints in turn (prefixed), their limits, defaults and grippers concatenated.

    Args:
        arms: the arms (`robot_arms.arm_specs`).
        name: the robot's name.
        base_link: the combined base link (default "base").
        ee_link: the default link of pose goals (default the first arm's `ee_link`).
        default_joint_positions: (dof,) [rad] (default: the arms' defaults in turn).
        padding: clearance from the world [m] (default: the largest of the arms').
        disabled_pairs: more [link, link] pairs (prefixed names) never checked.

    Raises:
        UnknownNameError: an arm's robot is not found (the message names the arm and lists the robots).
        RobotConfigError: a name given twice, a bad default, an unknown link in `disabled_pairs`.
    """
    configs = []
    for spec in arms:
        if isinstance(spec.robot, RobotConfig):
            configs.append(spec.robot)
            continue
        try:
            configs.append(load_robot_config(spec.robot))
        except UnknownNameError as exc:
            raise UnknownNameError(f"robot (arm '{spec.prefix.rstrip('_')}')", exc.name, exc.available) from None
    base = base_link or DEFAULT_BASE_LINK
    urdf, srdf = compose_files(name, base, [(s.prefix, c.urdf_path, c.base_link, s.base_pose, c.disabled_collision_pairs)
                                            for s, c in zip(arms, configs)])
    tree = UrdfTree(urdf)
    extra = [(str(a), str(b)) for a, b in disabled_pairs]
    unknown = sorted({n for pair in extra for n in pair} - set(tree.links))
    if unknown:
        raise UnknownNameError("link (collision: disabled_pairs)", unknown[0], tree.links)
    out, start = [], 0
    for s, c in zip(arms, configs):
        p = s.prefix
        out.append(Arm(p.rstrip("_"), p, c.name, s.base_pose, tuple(p + j for j in c.arm_joints), (start, start + c.dof),
                       p + c.ee_link, None if c.tcp_link is None else p + c.tcp_link,
                       tuple(p + j for j in c.gripper.joints) if c.gripper is not None else ()))
        start += c.dof
    cat = lambda key: np.concatenate([getattr(c, key) for c in configs])  # noqa: E731
    grippers = [(s.prefix, c.gripper) for s, c in zip(arms, configs) if c.gripper is not None]
    gripper = GripperConfig(tuple(p + j for p, g in grippers for j in g.joints),
                            *(np.concatenate([getattr(g, k) for _, g in grippers]) for k in GRIPPER_KEYS[1:])
                            ) if grippers else None
    ee = ee_link or out[0].ee_link
    tree.check_link(ee, "ee_link")
    try:
        default = cat("default_joint_positions") if default_joint_positions is None else \
            np.asarray(default_joint_positions, dtype=float)
    except (TypeError, ValueError) as exc:
        raise RobotConfigError(f"{name}: default_joint_positions must be numbers [rad]; got "
                               f"{default_joint_positions!r}") from exc
    config = RobotConfig(
        name=name, folder=folder or urdf.parent, urdf_path=urdf, srdf_path=srdf, mjcf_path=None,
        package_dirs=tuple(dict.fromkeys(d for c in configs for d in c.package_dirs)), base_link=base, ee_link=ee,
        tcp_link=out[0].tcp_link if ee == out[0].ee_link else None, arm_joints=tuple(j for a in out for j in a.joints),
        default_joint_positions=np.asarray(default, dtype=float), lower_limits=cat("lower_limits"),
        upper_limits=cat("upper_limits"), velocity_limits=cat("velocity_limits"),
        acceleration_limits=cat("acceleration_limits"), jerk_limits=cat("jerk_limits"), gripper=gripper,
        collision_padding=float(max(c.collision_padding for c in configs) if padding is None else padding),
        disabled_collision_pairs=tuple(sorted({tuple(sorted(p)) for p in
                                               [(p + a, p + b) for s, c in zip(arms, configs)
                                                for p in [s.prefix] for a, b in c.disabled_collision_pairs] + extra})),
        raw=dict(raw or {}), arms=tuple(out))
    q = config.default_joint_positions
    if q.shape != (config.dof,) or not np.all(np.isfinite(q)) or np.any(q < config.lower_limits) \
            or np.any(q > config.upper_limits):
        raise RobotConfigError(f"{name}: default_joint_positions must be {config.dof} finite values within the "
                               f"limits; got {default_joint_positions!r}")
    return config
