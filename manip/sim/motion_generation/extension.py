"""`get_extension_path_from_name`: Isaac's extension folders, for the motion-generation extension.

Isaac scripts find the motion-generation configuration files through the extension's
folder (`get_extension_path_from_name("omni.isaac.motion_generation") +
"/motion_policy_configs/..."`). manip has no Kit extensions: the two names of that extension
(`EXTENSION_NAMES`) give manip's folder `extension/` beside this module, which holds
manip's own Franka robot description (its README lists the files).
"""

from __future__ import annotations

from pathlib import Path

from manip.errors import InvalidInputError, UnknownNameError

#: The motion-generation extension's names: Isaac Sim 4 and Isaac Sim 5.
EXTENSION_NAMES = ("omni.isaac.motion_generation", "isaacsim.robot_motion.motion_generation")


def extension_folder() -> Path:
    """manip's stand-in for the motion-generation extension's folder."""
    return Path(__file__).resolve().parent / "extension"


def get_extension_path_from_name(extension_name: str) -> str:
    """The folder of a Kit extension (Isaac's `omni.isaac.core.utils.extensions`).

    Args:
        extension_name: one of `EXTENSION_NAMES`.

    Returns:
        The folder, as a string without a trailing separator (scripts append "/...").

    Raises:
        UnknownNameError: any other extension (manip has no other; the message lists these).
    """
    if not isinstance(extension_name, str):
        raise InvalidInputError(f"extension_name must be a str; got {type(extension_name).__name__}")
    if extension_name not in EXTENSION_NAMES:
        raise UnknownNameError("extension", extension_name, EXTENSION_NAMES)
    return str(extension_folder())
