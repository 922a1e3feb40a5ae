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
from manip.errors import RobotConfigError, UnknownNameError
from manip.limits import JointLimits
from manip.urdf import (MOVABLE_TYPES, UrdfJoint, UrdfTree, default_ee_link, disabled_pairs, srdf_group_states,
                        srdf_virtual_joints, within_limits)

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
        RobotConfigError: the file is malformed (missing keys, wrong types, non-finite or
            non-positive limits, limits beyond the URDF's, `ee_link` not below `base_link`)
            or names missing model files, or has a key it does not know, at the top level or
            in a section (`colision`, `collision: paddign`, ...; the message lists the valid
            keys; keys starting with `x_` are extension keys, accepted and ignored).
    """
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
    default = _default_configuration(default_joint_positions, spec, lower, upper, srdf_path, urdf_path.name,
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


#: The free-flyer joint's name in Pinocchio's convention: SRDF states may set it (not a URDF joint).
_FREE_FLYER = "root_joint"


def _default_configuration(given: np.ndarray | str | None, spec: list[UrdfJoint], lower: np.ndarray, upper: np.ndarray,
                           srdf_path: Path | None, where: str, urdf_joints: set[str] = frozenset()) -> np.ndarray:
    """The default configuration of `config_from_urdf` (see its docstring); `urdf_joints`: the
    URDF's joint names (a state naming others has a misspelt joint)."""
    n = len(spec)
    names = [j.name for j in spec]
    states = srdf_group_states(srdf_path) if srdf_path is not None and (given is None or isinstance(given, str)) else {}

    def fit(state: dict[str, float]) -> np.ndarray | None:
        return within_limits([state[j] for j in names], spec, lower, upper)

    if isinstance(given, str):
        if given not in states:
            raise UnknownNameError("group_state (default_joint_positions)", given, states)
        missing = [j for j in names if j not in states[given]]
        if missing:
            raise RobotConfigError(f"group_state '{given}' does not set the arm joints {missing}")
        q = fit(states[given])
        if q is None:
            raise RobotConfigError(f"group_state '{given}' is outside the joint limits "
                                   f"[{lower.tolist()}, {upper.tolist()}]: {states[given]}")
        return q
    if given is None:
        known = set(urdf_joints) | {_FREE_FLYER} | (set(srdf_virtual_joints(srdf_path)) if states else set())
        problems = []   # why each state setting arm joints was not used
        partial = []
        for state, values in states.items():
            unset = [j for j in names if j not in values]
            if len(unset) == len(names):
                continue  # a state of another group (the hand, ...)
            unknown = [j for j in values if urdf_joints and j not in known]
            if unset and unknown:  # a misspelt arm joint: never fall back silently
                raise RobotConfigError(
                    f"{srdf_path}: group_state '{state}' sets no value for the arm joint(s) {unset} and names "
                    f"joint(s) {unknown} that the URDF ({where}) does not have (misspelt?); the arm joints: "
                    f"{', '.join(names)}. Fix the SRDF, or give default_joint_positions.")
            if unset:
                partial.append(f"'{state}' sets no value for {unset}")
                continue
            q = fit(values)
            if q is not None:
                if unknown:
                    logger.warning("%s: the SRDF's group_state '%s' names joints not in the URDF (ignored): %s",
                                   where, state, unknown)
                if not np.array_equal(q, [values[j] for j in names]):
                    logger.warning("%s: default configuration: the SRDF's group_state '%s' turned by whole "
                                   "turns into the joint limits: %s", where, state, np.round(q, 6).tolist())
                return q
            out = [f"{j} = {values[j]} outside [{lo:g}, {hi:g}]" for j, lo, hi in zip(names, lower, upper)
                   if within_limits([values[j]], [spec[names.index(j)]], np.array([lo]), np.array([hi])) is None]
            problems.append(f"group_state '{state}': {'; '.join(out)}")
        if problems:  # a value typo (15.7 for 1.57) must not become the middle of the limits
            raise RobotConfigError(
                f"{srdf_path}: no group_state gives a default configuration within the joint limits: "
                f"{'; '.join(problems)}. Fix the SRDF, or give default_joint_positions.")
        if partial:
            logger.warning("%s: no default configuration: no SRDF group_state sets every arm joint (%s); using "
                           "the middle of the limits", where, "; ".join(partial))
        else:
            logger.warning("%s: no default configuration (%s); using the middle of the limits", where,
                           "the SRDF has no group_state of the arm joints" if srdf_path is not None else "no SRDF")
        return (lower + upper) / 2.0
    try:
        default = np.asarray(given, dtype=float)
    except (TypeError, ValueError) as exc:
        raise RobotConfigError(f"default_joint_positions must be {n} numbers [rad] or a group_state name; "
                               f"got {given!r}") from exc
    if default.shape != (n,) or not np.all(np.isfinite(default)) or np.any(default < lower) \
            or np.any(default > upper):
        raise RobotConfigError(f"default_joint_positions must be {n} finite values within the limits "
                               f"[{lower.tolist()}, {upper.tolist()}]; got {given!r}")
    return default.copy()
