"""The RMPflow configuration YAML (`rmpflow_config_path` of `RmpFlow`), read for manip's controller.

Isaac's file tunes Lula's Riemannian motion policies (`joint_limit_buffers`, `rmp_params`
with `cspace_target_rmp`, `target_rmp`, `collision_rmp`, ..., `canonical_resolve`,
`body_cylinders`, `body_collision_controllers`). manip has no RMPflow: `RmpFlow` runs
manip's QP controller (`manip.control.ReactiveController`), whose settings have no
counterpart among those keys. So manip reads one section of its own, `manip` (`READ_KEYS`),
and ignores every other key (logged at INFO once per file, naming them): an Isaac file
loads, with the controller's defaults.

    manip:
      robot: franka            # the manip robot configuration (MuJoCo model) the controller uses
      safety_margin: 0.02      # and any keyword of ReactiveController in CONTROLLER_KEYS

`robot` may be left out when the URDF is one manip maps (`lula_franka_gen.urdf` -> "franka",
`manip.sim.motion_generation.urdf_aliases`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from manip.errors import InvalidInputError
from manip.sim.motion_generation.robot_description import read_yaml_file

logger = logging.getLogger(__name__)

#: The section of the file manip reads.
SECTION = "manip"
#: `ReactiveController` keywords the section may set (validated by the controller).
CONTROLLER_KEYS = ("safety_margin", "detection_distance", "collision_gain", "limit_gain", "velocity_scale",
                   "acceleration_scale", "max_speed", "max_angular_speed", "self_collision", "solver")
#: Every key of the section.
READ_KEYS = ("robot",) + CONTROLLER_KEYS

_logged: set[Path] = set()


@dataclass(frozen=True)
class RmpFlowConfig:
    """What manip reads from an RMPflow configuration file.

    Attributes:
        path: the file.
        robot: the manip robot configuration name, or None (then the URDF decides).
        controller_options: `ReactiveController` keywords (a subset of `CONTROLLER_KEYS`).
        ignored_keys: the file's top-level keys other than `manip` (Lula's tuning).
    """

    path: Path
    robot: str | None = None
    controller_options: dict[str, Any] = field(default_factory=dict)
    ignored_keys: tuple[str, ...] = ()


def load_rmpflow_config(path: str | Path) -> RmpFlowConfig:
    """Read an RMPflow configuration YAML (see the module docstring).

    Raises:
        FileNotFoundError: no such file.
        InvalidInputError: not a YAML mapping, or a malformed `manip` section (an unknown key:
            the message lists `READ_KEYS`).
    """
    p, d = read_yaml_file(path, "rmpflow_config_path")
    if d is None:
        d = {}
    if not isinstance(d, dict):
        raise InvalidInputError(f"{p}: an RMPflow configuration must be a YAML mapping")
    section = d.get(SECTION) or {}
    if not isinstance(section, dict):
        raise InvalidInputError(f"{p}: `{SECTION}` must be a mapping of {', '.join(READ_KEYS)}")
    unknown = sorted(set(section) - set(READ_KEYS))
    if unknown:
        raise InvalidInputError(f"{p}: `{SECTION}.{unknown[0]}` is not a key manip reads; valid: {', '.join(READ_KEYS)}")
    robot = section.get("robot")
    if robot is not None and (not isinstance(robot, str) or not robot):
        raise InvalidInputError(f"{p}: `{SECTION}.robot` must be a robot configuration name; got {robot!r}")
    ignored = tuple(sorted(str(k) for k in d if k != SECTION))
    resolved = p.resolve()
    if ignored and resolved not in _logged:
        _logged.add(resolved)
        logger.info("%s: Lula's RMPflow keys %s are not used (manip runs its QP controller, tuned by the `%s` "
                    "section)", p.name, ", ".join(ignored), SECTION)
    options = {k: v for k, v in section.items() if k in CONTROLLER_KEYS}
    return RmpFlowConfig(path=resolved, robot=robot, controller_options=options, ignored_keys=ignored)


__all__ = ["CONTROLLER_KEYS", "READ_KEYS", "SECTION", "RmpFlowConfig", "load_rmpflow_config"]
