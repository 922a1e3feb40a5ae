"""Robots of several arms: each arm's URDF and SRDF composed into one robot with prefixed names.

A multi-arm robot is written, not coded: a `robot.yaml` with an `arms:` list (see
`robots/dual_franka/`), or `MotionGenerator.from_robots({"left": ("franka", Pose(...)), ...})`.
Each arm is a shipped robot's name or a robot folder, a base pose in the combined base frame
and a name prefix. This module writes the combined URDF (every link, joint and material of
arm "left" renamed `left_<name>`, its root fixed to the combined base link at its base pose,
mesh file names made absolute) and the combined SRDF (each arm's disabled self-collision pairs,
prefixed; no pair between two arms is disabled, so every one of them is checked on the exact
meshes). Everything downstream (Pinocchio kinematics, sphere covers, self-pair proofs, the
certificate, the independent verifier) reads these files as it reads one arm's.

The files are written once into the user's cache folder (`manip.disk_cache.user_folder`,
`robots/`; a temporary folder when the cache is off), named by a digest of what they are made
from, so a file is either right or absent.
"""

from __future__ import annotations

import hashlib
import re
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from manip import package_uri
from manip.disk_cache import DiskCache, user_folder
from manip.errors import InvalidInputError, RobotConfigError
from manip.pose import Pose
from manip.urdf import UrdfTree, build_model

__all__ = ["Arm", "ArmSpec", "arm_specs", "compose_files", "state_columns", "DEFAULT_BASE_LINK"]

#: The combined robot's root link (its base frame) unless the robot.yaml names another.
DEFAULT_BASE_LINK = "base"
#: Keys of one entry of a robot.yaml's `arms:` list.
ARM_KEYS = ("robot", "prefix", "base_pose")
_VERSION = "arms-v1"
_PREFIX = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class ArmSpec:
    """One arm as the user gives it.

    Attributes:
        prefix: the name prefix of its links and joints, ending in "_" ("left_").
        robot: a shipped robot's name, the path of a robot folder or robot.yaml, or a RobotConfig.
        base_pose: the pose of the arm's `base_link` in the combined base frame [m].
    """

    prefix: str
    robot: object
    base_pose: Pose


@dataclass(frozen=True)
class Arm:
    """One arm of a composed robot (`RobotConfig.arms`).

    Attributes:
        name: the prefix without its "_" ("left").
        prefix: "left_".
        robot: the arm's own robot name ("franka").
        base_pose: its base link's pose in the combined base frame [m].
        joints: its arm joints, prefixed, in order; the combined configuration holds them at `columns`.
        columns: (start, stop): its joints' slice of the combined configuration.
        ee_link, tcp_link: its end-effector (and tool centre point) link, prefixed.
        gripper_joints: its gripper joints, prefixed (empty without a gripper).
    """

    name: str
    prefix: str
    robot: str
    base_pose: Pose
    joints: tuple[str, ...]
    columns: tuple[int, int]
    ee_link: str
    tcp_link: str | None
    gripper_joints: tuple[str, ...]

    def owns(self, name: str) -> bool:
        """Whether a link or joint name is this arm's (it starts with the prefix)."""
        return name.startswith(self.prefix)


def state_columns(arms: tuple[Arm, ...]) -> np.ndarray:
    """Where the arm joints lie in a full state of a multi-arm robot: each arm's joints then its
    gripper's, arm after arm (`np.concatenate([left.get_joint_positions(), right.get_joint_positions()])`).
    """
    out, k = [], 0
    for arm in arms:
        out.extend(range(k, k + len(arm.joints)))
        k += len(arm.joints) + len(arm.gripper_joints)
    return np.asarray(out, dtype=np.int64)


def _prefix(key: object, what: str) -> str:
    if not isinstance(key, str) or not _PREFIX.match(key.rstrip("_") or "-"):
        raise InvalidInputError(f"{what}: an arm's prefix must be a name of letters, digits and '_' starting with a "
                                f"letter (e.g. 'left'); got {key!r}")
    return key.rstrip("_") + "_"


def _pose(value: object, what: str) -> Pose:
    if isinstance(value, Pose):
        if value.is_batch:
            raise InvalidInputError(f"{what}: the base pose must be a single Pose; got a batch of {len(value)}")
        return value
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        a = np.zeros(0)
    if a.shape == (3,):
        return Pose(a)
    if a.shape == (7,):
        return Pose(a[:3], a[3:])
    raise InvalidInputError(f"{what}: the base pose must be a manip.Pose, [x, y, z] or [x, y, z, qw, qx, qy, qz] "
                            f"[m]; got {value!r}")


def arm_specs(arms: object, what: str = "arms") -> list[ArmSpec]:
    """The arms of `MotionGenerator.from_robots` or of a robot.yaml's `arms:` list, checked.

    Args:
        arms: a mapping prefix -> (robot, base pose) (`from_robots`), or a list of mappings
            with keys `robot`, `prefix`, `base_pose` (a robot.yaml). A robot is a shipped
            robot's name, a robot folder or robot.yaml, or a RobotConfig; a base pose a Pose,
            [x, y, z] or [x, y, z, qw, qx, qy, qz] [m].
        what: the argument's name in messages.

    Raises:
        InvalidInputError: not a mapping / list, no arm, a malformed entry, a bad prefix or
            pose, or two arms with the same prefix.
    """
    entries: list[tuple[str, object, object]] = []
    if isinstance(arms, Mapping):
        for key, value in arms.items():
            if isinstance(value, (tuple, list)) and len(value) == 2:
                entries.append((key, value[0], value[1]))
            else:
                raise InvalidInputError(f"{what}[{key!r}] must be (robot, base_pose), e.g. ('franka', Pose([0, 0.35, "
                                        f"0])); got {value!r}")
    elif isinstance(arms, (list, tuple)):
        for i, entry in enumerate(arms):
            if not isinstance(entry, Mapping):
                raise InvalidInputError(f"{what}[{i}] must be a mapping of {', '.join(ARM_KEYS)}; got {entry!r}")
            unknown = sorted(str(k) for k in entry if k not in ARM_KEYS)
            missing = [k for k in ARM_KEYS if k not in entry]
            if unknown or missing:
                raise InvalidInputError(f"{what}[{i}]: unknown keys {unknown}, missing keys {missing}; an arm has "
                                        f"{', '.join(ARM_KEYS)}")
            entries.append((entry["prefix"], entry["robot"], entry["base_pose"]))
    else:
        raise InvalidInputError(f"{what} must be a dict prefix -> (robot, base_pose) or a list of arms; got "
                                f"{type(arms).__name__}")
    if not entries:
        raise InvalidInputError(f"{what}: give at least one arm")
    specs, seen = [], {}
    for key, robot, pose in entries:
        prefix = _prefix(key, f"{what}[{key!r}]")
        if prefix in seen:
            raise InvalidInputError(f"{what}: duplicate prefix '{prefix}' ({seen[prefix]!r} and {key!r}); each arm "
                                    "needs its own")
        seen[prefix] = key
        for other in seen:
            if other != prefix and (prefix.startswith(other) or other.startswith(prefix)):
                raise InvalidInputError(f"{what}: the prefixes '{other}' and '{prefix}' overlap (one begins the other), "
                                        "so a name would not say its arm; choose prefixes apart, such as 'left' and "
                                        "'right'")
        if not isinstance(robot, (str, Path)) and type(robot).__name__ != "RobotConfig":
            raise InvalidInputError(f"{what}[{key!r}]: the robot must be a robot name, a robot folder or a "
                                    f"RobotConfig; got {robot!r}")
        specs.append(ArmSpec(prefix, robot, _pose(pose, f"{what}[{key!r}]")))
    return specs


def _root_to_base(urdf: Path, tree: UrdfTree, base_link: str) -> pin.SE3:
    """The fixed placement of `base_link` in the URDF's root link (no movable joint between)."""
    if tree.chain_joints(tree.root_link, base_link):
        raise RobotConfigError(f"{urdf}: base_link '{base_link}' is moved by joints below the root "
                               f"'{tree.root_link}'; an arm's base must be fixed to its root")
    model = build_model(urdf)
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    return data.oMf[model.getFrameId(base_link)].copy()


def _renamed_arm(tree: UrdfTree, prefix: str) -> list[ET.Element]:
    """The arm's links, joints and materials, renamed with `prefix`, meshes made absolute."""
    out = []
    for el in tree.root:
        if el.tag not in ("link", "joint", "material"):
            continue  # transmissions, gazebo tags: not read by manip
        el = ET.fromstring(ET.tostring(el))
        el.set("name", prefix + el.get("name", ""))
        for tag in ("parent", "child"):
            for sub in el.findall(tag):
                sub.set("link", prefix + sub.get("link", ""))
        for sub in el.findall("mimic"):
            sub.set("joint", prefix + sub.get("joint", ""))
        for mat in el.iter("material"):
            if mat is not el and mat.get("name"):
                mat.set("name", prefix + mat.get("name"))
        for mesh in el.iter("mesh"):
            mesh.set("filename", str(package_uri.resolve(mesh.get("filename", ""), tree.path, f"mesh of {prefix}")))
        out.append(el)
    return out


def _origin(T: pin.SE3) -> ET.Element:
    rpy = pin.rpy.matrixToRpy(T.rotation)
    return ET.Element("origin", xyz=" ".join(repr(float(v)) for v in T.translation),
                      rpy=" ".join(repr(float(v)) for v in rpy))


def compose_files(name: str, base_link: str, arms: list[tuple[str, Path, str, Pose, tuple[tuple[str, str], ...]]]
                  ) -> tuple[Path, Path]:
    """Write (once) and return the combined URDF and SRDF of several arms.

    Args:
        name: the combined robot's name.
        base_link: the combined root link (the base frame).
        arms: per arm (prefix, its URDF, its base_link, its base pose in the combined frame,
            its disabled self-collision pairs).

    Raises:
        RobotConfigError: two arms give the same link or joint name, or the base link's name
            is an arm's; an arm's base is moved by a joint.
    """
    robot = ET.Element("robot", name=name)
    ET.SubElement(robot, "link", name=base_link)
    srdf = ET.Element("robot", name=name)
    seen: dict[tuple[str, str], str] = {("link", base_link): "the base link"}
    for prefix, urdf, arm_base, pose, pairs in arms:
        tree = UrdfTree(urdf)
        elements = _renamed_arm(tree, prefix)
        mount = ET.Element("joint", name=f"{prefix}mount_joint", type="fixed")
        ET.SubElement(mount, "parent", link=base_link)
        ET.SubElement(mount, "child", link=prefix + tree.root_link)
        T = pin.SE3(pose.rotation, pose.position) * _root_to_base(Path(urdf), tree, arm_base).inverse()
        mount.append(_origin(T))
        for el in [mount] + elements:
            key = (el.tag, el.get("name"))
            if key in seen:
                raise RobotConfigError(f"arms: the {el.tag} name '{key[1]}' is given twice ({seen[key]} and arm "
                                       f"'{prefix}'); choose prefixes that keep the names apart")
            seen[key] = f"arm '{prefix}'"
            robot.append(el)
        for a, b in pairs:
            ET.SubElement(srdf, "disable_collisions", link1=prefix + a, link2=prefix + b, reason="Arm")
    urdf_text = ET.tostring(robot, encoding="unicode")
    srdf_text = ET.tostring(srdf, encoding="unicode")
    digest = hashlib.sha1(f"{_VERSION}\n{urdf_text}\n{srdf_text}".encode()).hexdigest()[:16]
    folder = user_folder()
    folder = (folder / "robots") if folder is not None else Path(tempfile.gettempdir()) / "manip-robots"
    cache = DiskCache(folder, None)
    paths = []
    for suffix, text in ((".urdf", urdf_text), (".srdf", srdf_text)):
        file_name = f"{re.sub(r'[^A-Za-z0-9_.-]', '_', name)[:60]}-{digest}{suffix}"
        if cache.find(file_name) is None:
            cache.write(file_name, lambda path, text=text: path.write_text(text))
        if cache.find(file_name) is None:
            raise RobotConfigError(f"arms: could not write the combined robot's {suffix} file into {folder} "
                                   "(set MANIP_CACHE_DIR to a writable folder)")
        paths.append(folder / file_name)
    return paths[0], paths[1]
