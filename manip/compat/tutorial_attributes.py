"""The cuRobo wrapper's other attributes (`user_config`, `robot_config`, `kinematics_model`,
`motion_gen_plan_config`, `tensor_args`), as `TutorialMotionGen` provides them.

Auromix's wrapper keeps cuRobo objects there; manip has no cuRobo, so each attribute is the
manip equivalent with the fields a script reads, and a clear AttributeError naming anything
cuRobo-specific (`TutorialAttributeError`):

- `user_config`: the user config file's settings (a dict, as the wrapper's loaded TOML);
- `robot_config`: the robot config as cuRobo's `robot_cfg` dict (`kinematics`: base_link,
  ee_link, cspace joint_names and retract_config, lock_joints);
- `kinematics_model`: forward kinematics, `get_state(q)` -> `.ee_position` (3,),
  `.ee_quaternion` (4,) (w, x, y, z, as cuRobo), `.joint_names`, `.get_joint_limits()`;
- `motion_gen_plan_config`: the planning settings (max_attempts, timeout, enable_graph,
  time_dilation_factor, ...), read-only: pass MotionGenerator options instead;
- `tensor_args`: device "cpu", dtype float64 (`to_device(x)` gives a NumPy array).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, Callable

import numpy as np


class TutorialAttributeError(AttributeError):
    """A cuRobo attribute or method manip does not provide (the message says what to use)."""


class _StandIn:
    """Named read-only fields; anything else raises TutorialAttributeError naming it."""

    _what = ""
    _use = ""

    def __init__(self, **fields: Any):
        object.__setattr__(self, "_fields", dict(fields))

    def __getattr__(self, name: str):
        fields = object.__getattribute__(self, "_fields")
        if name in fields:
            return fields[name]
        raise TutorialAttributeError(f"{self._what}.{name} is cuRobo's and manip does not provide it; available: "
                                     f"{sorted(fields)}. {self._use}")

    def __setattr__(self, name: str, value) -> None:
        raise TutorialAttributeError(f"{self._what} is read-only in manip. {self._use}")

    def __repr__(self) -> str:
        return f"{type(self).__name__}({object.__getattribute__(self, '_fields')})"


class MotionGenPlanConfig(_StandIn):
    _what = "motion_gen_plan_config"
    _use = "Set planning options as MotionGenerator keyword arguments (TutorialMotionGen(..., time_budget=...))."


class TensorArgs(_StandIn):
    _what = "tensor_args"
    _use = "manip computes on the CPU with NumPy float64 arrays."


class KinematicsModel(_StandIn):
    _what = "kinematics_model"
    _use = "Use TutorialMotionGen.fk or motion_gen.fk / motion_gen.kinematics."


def plan_config(options: dict) -> MotionGenPlanConfig:
    """The wrapper's MotionGenPlanConfig fields from the MotionGenerator options in force."""
    return MotionGenPlanConfig(enable_graph=False, enable_opt=True, max_attempts=int(options.get("max_attempts", 4)),
                               timeout=float(options.get("time_budget", 10.0)), time_dilation_factor=1.0,
                               enable_finetune_trajopt=True, parallel_finetune=False)


def tensor_args() -> TensorArgs:
    return TensorArgs(device="cpu", dtype=np.float64, to_device=lambda x: np.asarray(x, dtype=np.float64))


def kinematics_model(ee_pose_wxyz: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], joint_names: list[str],
                     limits: np.ndarray) -> KinematicsModel:
    """`get_state(q)` from `ee_pose_wxyz(q)` -> (position (3,), quaternion (w, x, y, z))."""

    def get_state(q) -> SimpleNamespace:
        p, w = ee_pose_wxyz(np.asarray(q, dtype=float))
        return SimpleNamespace(ee_position=p, ee_quaternion=w, ee_pos_seq=p, ee_quat_seq=w)

    return KinematicsModel(get_state=get_state, joint_names=list(joint_names), get_joint_limits=lambda: limits.copy(),
                           get_dof=lambda: len(joint_names))


def robot_config_dict(base_link: str, ee_link: str, joint_names: list[str], retract: list[float],
                      locked: dict[str, float], robot: str) -> dict:
    """cuRobo's `robot_cfg` dict of the wrapper's robot."""
    return {"kinematics": {"base_link": base_link, "ee_link": ee_link, "lock_joints": dict(locked),
                           "cspace": {"joint_names": list(joint_names), "retract_config": list(retract)},
                           "manip_robot": robot}}
