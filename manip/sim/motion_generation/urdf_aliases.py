"""URDF file names of Isaac Sim's motion-generation extension, mapped to manip's robots.

Isaac's scripts pass `<extension>/motion_policy_configs/franka/lula_franka_gen.urdf` to
`LulaKinematicsSolver`; manip does not ship that file. `resolve_urdf` maps the name (in
any folder, when no file exists at the path) to a bundled robot's URDF plus the frames
Isaac's file has and manip's lacks (`URDF_ALIASES`), written once per process to a
temporary folder with every mesh path made absolute.

The Franka's `right_gripper` (Isaac's Lula end-effector frame): a link fixed to
`panda_hand`, 0.1 m along panda_hand's z axis, with panda_hand's orientation (identity
rotation). Isaac's lula_franka_gen.urdf was not available to check this against: the
0.1 m along the hand's z is Isaac's frame as its tutorial describes it, and the rotation about
that axis is unverified. If Isaac's frame is turned about z (the parallel jaw is symmetric
under a half turn), an orientation target is reached with the hand turned by that angle
about the approach axis.
"""

from __future__ import annotations

import tempfile
import threading
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from manip import package_uri
from manip.errors import RobotConfigError
from manip.robot_config import load_robot_config


@dataclass(frozen=True)
class ExtraFrame:
    """A frame added to a URDF as a massless link on a fixed joint.

    Attributes:
        name: the new link's name.
        parent: the link it is fixed to.
        xyz: (3,) its origin in the parent link's frame [m].
        rpy: (3,) its roll, pitch, yaw in the parent link's frame [rad] (URDF convention).
    """

    name: str
    parent: str
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class UrdfAlias:
    """An Isaac URDF file name standing for a bundled robot (`robots/<robot>`) plus frames."""

    robot: str
    frames: tuple[ExtraFrame, ...] = ()


#: Isaac URDF file name -> the bundled robot it stands for (see the module docstring).
URDF_ALIASES: dict[str, UrdfAlias] = {
    "lula_franka_gen.urdf": UrdfAlias("franka", (ExtraFrame("right_gripper", "panda_hand", (0.0, 0.0, 0.1)),)),
}

_lock = threading.Lock()
_written: dict[str, Path] = {}
_folder: tempfile.TemporaryDirectory | None = None


def _with_frames(source: Path, frames: tuple[ExtraFrame, ...], target: Path) -> None:
    """Write `source` to `target` with `frames` added and mesh paths made absolute."""
    tree = ET.parse(source)
    root = tree.getroot()
    for mesh in root.iter("mesh"):
        uri = mesh.get("filename", "")
        try:
            mesh.set("filename", str(package_uri.resolve(uri, source)))
        except RobotConfigError:
            pass  # a missing visual mesh stays as written (kinematics does not read it)
    links = {el.get("name") for el in root.findall("link")}
    for f in frames:
        if f.parent not in links:
            raise RobotConfigError(f"{source}: no link {f.parent!r} to fix frame {f.name!r} to")
        ET.SubElement(root, "link", name=f.name)
        joint = ET.SubElement(root, "joint", name=f"{f.name}_joint", type="fixed")
        ET.SubElement(joint, "origin", xyz=" ".join(map(repr, f.xyz)), rpy=" ".join(map(repr, f.rpy)))
        ET.SubElement(joint, "parent", link=f.parent)
        ET.SubElement(joint, "child", link=f.name)
    tree.write(target, encoding="unicode")


def alias_urdf(name: str) -> Path:
    """The URDF standing for Isaac's file `name` (a key of `URDF_ALIASES`), written on first use.

    Raises:
        KeyError: `name` is not an alias.
    """
    global _folder
    alias = URDF_ALIASES[name]
    with _lock:
        if name not in _written:
            if _folder is None:
                _folder = tempfile.TemporaryDirectory(prefix="manip-lula-")  # removed at exit
            target = Path(_folder.name) / name
            _with_frames(load_robot_config(alias.robot).urdf_path, alias.frames, target)
            _written[name] = target
        return _written[name]


def resolve_urdf(urdf_path: str | Path) -> Path:
    """The URDF to load for `urdf_path`: the file itself when it exists, else the alias of
    its file name (`URDF_ALIASES`).

    Raises:
        FileNotFoundError: neither; the message lists the aliases.
    """
    path = Path(urdf_path).expanduser()
    if path.is_file():
        return path.resolve()
    if path.name in URDF_ALIASES:
        return alias_urdf(path.name)
    known = ", ".join(f"{k} (manip's {v.robot})" for k, v in URDF_ALIASES.items())
    raise FileNotFoundError(f"urdf_path: no file at {urdf_path}; manip maps these Isaac URDF names in any folder: "
                            f"{known}")
