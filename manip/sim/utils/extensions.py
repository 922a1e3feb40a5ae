"""Isaac's `enable_extension` / `disable_extension` (`omni.isaac.core.utils.extensions`,
`isaacsim.core.utils.extensions`): standalone scripts enable the extensions they import from.

manip has no Kit extensions: those whose Python names manip.sim mirrors (`MIRRORED`, by name
prefix) are there already (True); any other (a ROS bridge, replicator, ...) is not (False, with
a warning naming it, as Isaac's extension manager returns False for one it cannot load).
"""

from __future__ import annotations

import logging

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)

#: Extension names (and their sub-extensions) whose tutorial names manip.sim provides.
MIRRORED = (
    "omni.isaac.core", "omni.isaac.franka", "omni.isaac.manipulators", "omni.isaac.wheeled_robots",
    "omni.isaac.motion_generation", "omni.isaac.sensor", "omni.isaac.examples", "omni.isaac.kit",
    "omni.isaac.nucleus", "isaacsim.core.api", "isaacsim.core.prims", "isaacsim.core.utils",
    "isaacsim.core.nodes", "isaacsim.robot.manipulators", "isaacsim.robot.wheeled_robots",
    "isaacsim.robot_motion.motion_generation", "isaacsim.sensors.camera", "isaacsim.examples.interactive",
    "isaacsim.storage.native",
)


def _mirrored(extension_name: str) -> bool:
    if not isinstance(extension_name, str) or not extension_name:
        raise InvalidInputError(f"extension_name must be a non-empty str; got {extension_name!r}")
    return any(extension_name == m or extension_name.startswith(m + ".") for m in MIRRORED)


def enable_extension(extension_name: str) -> bool:
    """Whether the extension's Python names are available in manip.sim (True for `MIRRORED`
    ones, enabled already; False with a warning for any other)."""
    if _mirrored(extension_name):
        return True
    logger.warning("enable_extension(%r): manip.sim has no such extension (it mirrors %s); imports from it "
                   "will fail", extension_name, ", ".join(MIRRORED))
    return False


def disable_extension(extension_name: str) -> bool:
    """Nothing to unload (manip.sim's names stay importable); True, as Isaac's after unloading."""
    _mirrored(extension_name)
    return True
