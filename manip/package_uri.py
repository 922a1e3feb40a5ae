"""Mesh file names of a URDF as ROS tools resolve them: `package://PKG/rest`, `file://`, paths.

Used by the planner (`robot_config`: the URDF's `package_dirs` for Pinocchio, and the check
that every collision mesh exists) and by `manip.sim` (a URDF referenced on the stage is
given to MuJoCo with every mesh as an absolute path), so both accept the same files.

`package://PKG/rest` is `ROOT/rest`, ROOT being the first of:

1. the URDF's own package: walking up from the URDF's folder, a folder named PKG or whose
   `package.xml` names PKG, or a folder PKG (with a `package.xml`, or not) beside one of the
   URDF's parent folders (a package of the same workspace);
2. the packages under each folder of `ROS_PACKAGE_PATH` (as rospack: the folder itself, or a
   folder below it whose `package.xml` names PKG; folders holding CATKIN_IGNORE,
   COLCON_IGNORE or AMENT_IGNORE are skipped);
3. `PREFIX/share/PKG` for each prefix of `AMENT_PREFIX_PATH` (ROS 2), then of the Python
   environment: `cmeel.prefix` beside each `sys.path` entry (where pip installs
   example-robot-data, Pinocchio and their ROS packages), `sys.prefix` and `CONDA_PREFIX`.

When the package is found nowhere, ROS would fail: here too, with a `RobotConfigError` naming
the URI and every folder searched. A last resort that ROS does not have, kept from manip's
earlier behaviour: a URDF's parent folder in which `rest` exists (a package copied under
another name, without its package.xml). `file:///abs` is `/abs`; any other path is taken
relative to the URDF's folder.
"""

from __future__ import annotations

import logging
import os
import sys
import xml.etree.ElementTree as ET
from functools import lru_cache
from pathlib import Path

from manip.errors import RobotConfigError

log = logging.getLogger(__name__)

PACKAGE = "package://"
#: Files whose presence makes rospack / colcon skip a folder.
IGNORE_MARKERS = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE")
#: How deep below a `ROS_PACKAGE_PATH` folder packages are looked for.
CRAWL_DEPTH = 6


def split(uri: str) -> tuple[str, str]:
    """(package name, path inside the package) of `package://PKG/rest`."""
    body = uri[len(PACKAGE):]
    name, _, rest = body.partition("/")
    return name, rest


def _manifest_name(folder: Path) -> str | None:
    """The <name> of `folder/package.xml`, or None (no file, or unreadable)."""
    return _read_manifest_name(str(folder / "package.xml"))


@lru_cache(maxsize=4096)
def _read_manifest_name(path: str) -> str | None:
    try:
        el = ET.parse(path).getroot().find("name")
    except (OSError, ET.ParseError):
        return None
    return el.text.strip() if el is not None and el.text else None


def _ros_packages(entry: str) -> dict[str, Path]:
    """{package name: folder} of the packages at or below one `ROS_PACKAGE_PATH` folder."""
    return _crawl(str(Path(entry).expanduser()))


@lru_cache(maxsize=64)
def _crawl(root: str) -> dict[str, Path]:
    found: dict[str, Path] = {}
    stack = [(Path(root), 0)]
    while stack:
        folder, depth = stack.pop()
        try:
            names = set(os.listdir(folder))
        except OSError:
            continue
        if any(m in names for m in IGNORE_MARKERS):
            continue
        if "package.xml" in names:  # a package: packages do not nest
            name = _manifest_name(folder) or folder.name
            found.setdefault(name, folder)
            continue
        if depth < CRAWL_DEPTH:
            stack.extend((folder / n, depth + 1) for n in sorted(names, reverse=True)
                         if not n.startswith(".") and (folder / n).is_dir())
    return found


def prefixes() -> list[Path]:
    """Install prefixes whose `share/PKG` holds packages: `AMENT_PREFIX_PATH`'s, then the Python
    environment's (`cmeel.prefix` beside each `sys.path` entry, `sys.prefix`, `CONDA_PREFIX`)."""
    out = [Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    out += [Path(p) / "cmeel.prefix" for p in sys.path if p and (Path(p) / "cmeel.prefix").is_dir()]
    out.append(Path(sys.prefix))
    if os.environ.get("CONDA_PREFIX"):
        out.append(Path(os.environ["CONDA_PREFIX"]))
    return list(dict.fromkeys(out))


# Packages found, by (name, URDF folder, environment): a robot's URDF names a few packages
# for many meshes, and the simulator reloads it at each compile. Only found packages are kept.
_found: dict[tuple, tuple[Path, list[str]]] = {}


def find_package(name: str, urdf: str | Path) -> tuple[Path | None, list[str]]:
    """The folder of ROS package `name` as seen from the URDF file `urdf` (see the module
    docstring for the order), and the places searched (for an error message).

    Returns:
        (the package's folder, or None; the folders searched, in order).
    """
    urdf = Path(urdf).resolve()
    if not name:  # package:///rest names no package (`resolve` still tries the URDF's parent folders)
        return None, ["no package named in the URI (package:///...)"]
    key = (name, str(urdf.parent), os.environ.get("ROS_PACKAGE_PATH"), os.environ.get("AMENT_PREFIX_PATH"),
           os.environ.get("CONDA_PREFIX"), tuple(sys.path))
    if key in _found and _found[key][0].is_dir():
        return _found[key]
    folder, searched = _find_package(name, urdf)
    if folder is not None:
        if len(_found) > 1024:
            _found.clear()
        _found[key] = (folder, searched)
    return folder, searched


def _find_package(name: str, urdf: Path) -> tuple[Path | None, list[str]]:
    searched = [f"{urdf.parent} and its parent folders"]
    for folder in urdf.parents:
        if folder.name == name or _manifest_name(folder) == name:
            return folder, searched
        if (folder / name).is_dir():
            return folder / name, searched
    for entry in [p for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]:
        searched.append(f"{entry} (ROS_PACKAGE_PATH)")
        found = _ros_packages(entry).get(name)
        if found is not None:
            return found, searched
    for prefix in prefixes():
        searched.append(str(prefix / "share"))
        if (prefix / "share" / name).is_dir():
            return prefix / "share" / name, searched
    return None, searched


def resolve(uri: str, urdf: str | Path, what: str = "mesh") -> Path:
    """The file a URDF's `filename` attribute names (see the module docstring).

    Args:
        uri: the attribute as written (`package://PKG/rest`, `file:///abs`, or a path).
        urdf: the URDF file that holds it.
        what: what the file is, for the error message.

    Returns:
        The absolute path of an existing file.

    Raises:
        RobotConfigError: no such file (the message names the URI and the folders searched).
    """
    urdf = Path(urdf).resolve()
    if uri.startswith(PACKAGE):
        name, rest = split(uri)
        root, searched = find_package(name, urdf)
        if root is not None and (root / rest).is_file():
            return root / rest
        for folder in urdf.parents:  # a package copied under another name (not ROS's rule)
            if rest and (folder / rest).is_file():
                return folder / rest
        where = "; ".join(searched)
        found = f"package '{name}' is {root}, which has no {rest}" if root is not None else \
            f"package '{name}' not found"
        raise RobotConfigError(
            f"{urdf}: {what} {uri}: {found}. Searched: {where}. Keep the URDF inside its package's folder tree, or "
            "add the folder holding the package to ROS_PACKAGE_PATH (ROS 1) or its install prefix to "
            "AMENT_PREFIX_PATH (ROS 2)")
    path = Path(uri.removeprefix("file://")).expanduser()
    path = path if path.is_absolute() else urdf.parent / path
    if not path.is_file():
        raise RobotConfigError(f"{urdf}: {what} {uri}: no such file ({path})")
    return path.resolve()


def mesh_uris(root: ET.Element, collision_only: bool = False) -> list[ET.Element]:
    """The `<mesh>` elements of a parsed URDF (of `<collision>` only, or of every link)."""
    path = "link/collision/geometry/mesh" if collision_only else ".//mesh"
    return list(root.findall(path))


def package_dirs(urdf: str | Path) -> tuple[str, ...]:
    """The folders Pinocchio searches for the URDF's meshes (`package_dirs`): Pinocchio reads
    `package://PKG/rest` as `D/PKG/rest` and a relative path as `D/path`, for each folder D in
    turn. The URDF's folder first (relative paths), then the folder holding each package the
    URDF's meshes name (as `find_package` finds them), then the URDF's other parent folders.
    """
    urdf = Path(urdf).resolve()
    out = [urdf.parent]
    try:
        root = ET.parse(urdf).getroot()
    except (OSError, ET.ParseError):
        root = None
    names = [] if root is None else list(dict.fromkeys(
        split(m.get("filename", ""))[0] for m in mesh_uris(root) if m.get("filename", "").startswith(PACKAGE)))
    for name in names:
        folder, _ = find_package(name, urdf)
        if folder is not None and folder.name == name:
            out.append(folder.parent)
    out += list(urdf.parents)[1:]
    return tuple(str(p) for p in dict.fromkeys(out))


def check_pinocchio_can_read(urdf: str | Path, dirs: tuple[str, ...], collision_only: bool = True) -> None:
    """Raise when a mesh of the URDF resolves (`resolve`) to a file that Pinocchio, given `dirs`
    as its `package_dirs`, would not find: a package whose folder is not named after it.

    Raises:
        RobotConfigError: the URI, where the package is and what to do.
    """
    urdf = Path(urdf).resolve()
    root = ET.parse(urdf).getroot()
    for mesh in mesh_uris(root, collision_only):
        uri = mesh.get("filename", "")
        if not uri.startswith(PACKAGE):
            continue
        target = resolve(uri, urdf)
        if not any(Path(f"{d}/{uri[len(PACKAGE):]}").is_file() for d in dirs):  # Pinocchio's concatenation
            raise RobotConfigError(
                f"{urdf}: mesh {uri} is {target}, but the planner's collision model (Pinocchio) finds a "
                f"package:// file only in a folder named after its package ('{split(uri)[0]}'): rename or link "
                f"the package's folder to that name")
