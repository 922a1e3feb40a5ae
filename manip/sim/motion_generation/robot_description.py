"""A Lula robot description file (the YAML of Isaac Sim's `LulaKinematicsSolver`), read.

Lula describes a robot by its URDF plus a YAML naming the solver's joints. manip reads
these keys (`READ_KEYS`):

- `cspace` (required): the solver's joints, in the order of its joint vectors; each a
  movable joint of the URDF.
- `root_link`: the link poses are relative to (the robot base that `set_robot_base_pose`
  places); default the URDF's root link.
- `default_q`: the default configuration [rad or m], one value per cspace joint.
- `cspace_to_urdf_rules`: URDF joints outside the cspace held at a value, each
  `{name: <joint>, rule: fixed, value: <position>}` (only the `fixed` rule exists here).

Every other key of Lula's format (`api_version`, `acceleration_limits`, `jerk_limits`,
`composite_task_spaces`, `collision_spheres`, `self_collision_ignore`, ...) is ignored:
kinematics does not use it. URDF joints neither in the cspace nor in a rule are held at 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from manip.errors import InvalidInputError

#: The keys of a robot description manip reads; the others are ignored.
READ_KEYS = ("cspace", "root_link", "default_q", "cspace_to_urdf_rules")


@dataclass(frozen=True)
class LulaRobotDescription:
    """What manip reads of a Lula robot description YAML.

    Attributes:
        path: the file.
        cspace: the solver's joint names, in joint-vector order.
        root_link: the base link of poses, or None for the URDF's root link.
        default_q: (len(cspace),) default configuration, or None when the file has none.
        fixed_joints: URDF joint -> the position it is held at (`cspace_to_urdf_rules`).
    """

    path: Path
    cspace: tuple[str, ...]
    root_link: str | None = None
    default_q: np.ndarray | None = None
    fixed_joints: dict[str, float] = field(default_factory=dict)


def _where(path: Path, key: str) -> str:
    return f"{path}: {key}"


def _cspace(d: dict, path: Path) -> tuple[str, ...]:
    cspace = d.get("cspace")
    if not isinstance(cspace, list) or not cspace or not all(isinstance(j, str) and j for j in cspace):
        raise InvalidInputError(f"{_where(path, 'cspace')} must be a non-empty list of joint names; got {cspace!r}")
    if len(set(cspace)) != len(cspace):
        raise InvalidInputError(f"{_where(path, 'cspace')} names a joint twice: {cspace}")
    return tuple(cspace)


def _default_q(d: dict, n: int, path: Path) -> np.ndarray | None:
    value = d.get("default_q")
    if value is None:
        return None
    ok = isinstance(value, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    if not ok or len(value) != n or not all(math.isfinite(v) for v in value):
        raise InvalidInputError(f"{_where(path, 'default_q')} must be {n} finite numbers (one per cspace joint); "
                                f"got {value!r}")
    q = np.array(value, dtype=float)
    q.setflags(write=False)
    return q


def _rules(d: dict, cspace: tuple[str, ...], path: Path) -> dict[str, float]:
    rules = d.get("cspace_to_urdf_rules") or []
    where = _where(path, "cspace_to_urdf_rules")
    if not isinstance(rules, list):
        raise InvalidInputError(f"{where} must be a list of {{name, rule: fixed, value}}; got {rules!r}")
    out: dict[str, float] = {}
    for rule in rules:
        if not isinstance(rule, dict) or not isinstance(rule.get("name"), str):
            raise InvalidInputError(f"{where}: each rule must be a mapping with a joint `name`; got {rule!r}")
        name, kind, value = rule["name"], rule.get("rule"), rule.get("value")
        if kind != "fixed":
            raise InvalidInputError(f"{where}: rule of {name} is {kind!r}; manip supports only 'fixed'")
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            raise InvalidInputError(f"{where}: the fixed value of {name} must be a finite number; got {value!r}")
        if name in cspace:
            raise InvalidInputError(f"{where}: {name} is a cspace joint; a fixed rule is for the other URDF joints")
        if name in out:
            raise InvalidInputError(f"{where}: {name} has two rules")
        out[name] = float(value)
    return out


def read_yaml_file(path, argument: str) -> tuple[Path, Any]:
    """(the path, the parsed YAML) of one of Isaac's configuration files, given as `argument`.

    Raises:
        FileNotFoundError: no such file.
        InvalidInputError: `path` is not a path, or the file is not valid YAML.
    """
    if not isinstance(path, (str, Path)):
        raise InvalidInputError(f"{argument} must be a path (str); got {type(path).__name__}")
    p = Path(path).expanduser()
    if not p.is_file():
        raise FileNotFoundError(f"{argument}: no file at {p}")
    try:
        return p, yaml.safe_load(p.read_text())
    except yaml.YAMLError as exc:
        raise InvalidInputError(f"{p}: not valid YAML: {exc}") from exc


def load_robot_description(path: str | Path) -> LulaRobotDescription:
    """Read a Lula robot description YAML (see the module docstring for the keys read).

    Raises:
        FileNotFoundError: no such file.
        InvalidInputError: not a YAML mapping, or a read key is malformed (the message names
            the file and the key).
    """
    p, d = read_yaml_file(path, "robot_description_path")
    if not isinstance(d, dict):
        raise InvalidInputError(f"{p}: a robot description must be a YAML mapping with a `cspace` list")
    cspace = _cspace(d, p)
    root = d.get("root_link")
    if root is not None and (not isinstance(root, str) or not root):
        raise InvalidInputError(f"{_where(p, 'root_link')} must be a link name; got {root!r}")
    return LulaRobotDescription(path=p.resolve(), cspace=cspace, root_link=root,
                                default_q=_default_q(d, len(cspace), p), fixed_joints=_rules(d, cspace, p))
