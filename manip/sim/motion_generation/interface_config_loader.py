"""Isaac's `interface_config_loader`: the configuration files of the supported robots.

    from manip.sim import interface_config_loader, LulaKinematicsSolver, RmpFlow
    config = interface_config_loader.load_supported_lula_kinematics_solver_config("Franka")
    solver = LulaKinematicsSolver(**config)
    rmpflow = RmpFlow(**interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow"))

As Isaac's loader, it reads `policy_map.json` in a policy configuration folder (default
`<extension>/motion_policy_configs`, `manip.sim.motion_generation.extension`): robot name ->
{policy name: configuration JSON}, each JSON holding `relative_asset_paths` resolved against
its own folder. Kinematics configurations are the `RMPflow` entries' robot description and
URDF. manip's folder supports the Franka only; a folder of one's own may list any robot.

A motion-policy configuration is the whole JSON (its other keys, such as
`end_effector_frame_name` and `maximum_substep_size`, are keyword arguments too).

Difference from Isaac: an unknown robot or policy raises UnknownNameError listing the
supported ones (Isaac logs an error and returns None, which fails later as `**None`).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim.motion_generation.extension import extension_folder

#: The policy whose configuration holds a robot's kinematics files (Isaac's choice).
KINEMATICS_POLICY = "RMPflow"


def _config_dir(policy_config_dir: str | Path | None) -> Path:
    if policy_config_dir is None:
        return extension_folder() / "motion_policy_configs"
    if not isinstance(policy_config_dir, (str, Path)):
        raise InvalidInputError(f"policy_config_dir must be a folder path; got {type(policy_config_dir).__name__}")
    return Path(policy_config_dir).expanduser()


def _policy_map(folder: Path) -> dict[str, dict[str, str]]:
    path = folder / "policy_map.json"
    if not path.is_file():
        raise FileNotFoundError(f"policy_config_dir: no policy_map.json in {folder}")
    with open(path) as f:
        data = json.load(f)
    if not isinstance(data, dict) or not all(isinstance(v, dict) for v in data.values()):
        raise InvalidInputError(f"{path}: must map robot names to {{policy name: config file}}")
    return data


def _process_policy_config(config_file: Path) -> dict:
    """The configuration with its `relative_asset_paths` joined to the file's folder."""
    with open(config_file) as f:
        config = json.load(f)
    for key, rel in config.pop("relative_asset_paths", {}).items():
        config[key] = os.path.join(os.path.dirname(config_file), rel)
    return config


def get_supported_robot_policy_pairs(policy_config_dir: str | Path | None = None) -> dict[str, list[str]]:
    """Robot name -> the policy names `policy_map.json` lists for it."""
    return {robot: list(policies) for robot, policies in _policy_map(_config_dir(policy_config_dir)).items()}


def load_supported_motion_policy_config(robot_name: str, policy_name: str,
                                        policy_config_dir: str | Path | None = None) -> dict:
    """The keyword arguments of a supported robot's motion policy (`RmpFlow(**config)`).

    Args:
        robot_name: a robot of `get_supported_robot_policy_pairs()` ("Franka").
        policy_name: one of that robot's policies ("RMPflow").
        policy_config_dir: the folder holding `policy_map.json` (default manip's).

    Returns:
        The configuration JSON with its `relative_asset_paths` joined to the file's folder;
        for the Franka's RMPflow: robot_description_path, urdf_path, rmpflow_config_path,
        end_effector_frame_name ("right_gripper"), maximum_substep_size [s],
        ignore_robot_state_updates.

    Raises:
        UnknownNameError: an unknown robot, or a policy the robot does not have (the message
            lists the supported ones).
        FileNotFoundError: a configuration file is missing.
    """
    folder = _config_dir(policy_config_dir)
    policy_map = _policy_map(folder)
    if not isinstance(robot_name, str) or robot_name not in policy_map:
        raise UnknownNameError("robot_name: robot", str(robot_name), policy_map)
    if not isinstance(policy_name, str) or policy_name not in policy_map[robot_name]:
        raise UnknownNameError(f"policy_name: policy of {robot_name}", str(policy_name), policy_map[robot_name])
    config_file = folder / policy_map[robot_name][policy_name]
    if not config_file.is_file():
        raise FileNotFoundError(f"{folder / 'policy_map.json'}: {robot_name}'s {policy_name} configuration "
                                f"{config_file} does not exist")
    return _process_policy_config(config_file)


def get_supported_robots_with_lula_kinematics(policy_config_dir: str | Path | None = None) -> list[str]:
    """The robots with a kinematics configuration (an `RMPflow` entry)."""
    return [r for r, p in get_supported_robot_policy_pairs(policy_config_dir).items() if KINEMATICS_POLICY in p]


def load_supported_lula_kinematics_solver_config(robot_name: str, policy_config_dir: str | Path | None = None) -> dict:
    """The keyword arguments of `LulaKinematicsSolver` for a supported robot.

    Args:
        robot_name: a robot of `get_supported_robots_with_lula_kinematics()` ("Franka").
        policy_config_dir: the folder holding `policy_map.json` (default manip's).

    Returns:
        {"robot_description_path": str, "urdf_path": str}.

    Raises:
        UnknownNameError: the robot has no kinematics configuration (the message lists those that do).
        FileNotFoundError: a configuration file is missing.
        InvalidInputError: the configuration has no robot_description_path or urdf_path.
    """
    folder = _config_dir(policy_config_dir)
    policy_map = _policy_map(folder)
    if not isinstance(robot_name, str) or KINEMATICS_POLICY not in policy_map.get(robot_name, {}):
        supported = [r for r, p in policy_map.items() if KINEMATICS_POLICY in p]
        raise UnknownNameError("robot with lula kinematics", str(robot_name), supported)
    config_file = folder / policy_map[robot_name][KINEMATICS_POLICY]
    if not config_file.is_file():
        raise FileNotFoundError(f"{folder / 'policy_map.json'}: {robot_name}'s {KINEMATICS_POLICY} configuration "
                                f"{config_file} does not exist")
    config = _process_policy_config(config_file)
    missing = [k for k in ("robot_description_path", "urdf_path") if k not in config]
    if missing:
        raise InvalidInputError(f"{config_file}: no {', '.join(missing)} in its relative_asset_paths")
    return {"robot_description_path": config["robot_description_path"], "urdf_path": config["urdf_path"]}
