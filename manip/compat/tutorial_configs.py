"""The configuration FILE NAMES the tutorial's cuRobo wrapper is constructed with, as manip settings.

The Isaac Sim pick-and-place tutorial builds its wrapper as
`CuroboMotionGenerator(robot_config_file_name="my_franka_robot_config.yml",
world_config_file_name="collision_base.yml", user_config_file_name="isaac_sim_user_config.toml")`:
three files of the wrapper's own folders. manip reads no cuRobo files; each known name maps
to the equivalent manip settings below (facts of those files: see the wrapper contract).

- Robot configs (`ROBOT_CONFIGS`): the robot, its cuRobo c-space (the 7 arm joints then the
  2 locked fingers), the retract configuration, and the wrapper's `ee_link` as a fixed frame
  on the planner's end-effector link. The tutorial's `my_franka_robot_config.yml` and
  cuRobo's own `franka.yml` (whose `ee_link` is panda_hand) are known; for cuRobo's files of
  arms manip ships in another version (`ur5e.yml`, ...) the error says what to use.
- World configs (`WORLD_CONFIGS`): obstacles in the robot base frame (cuRobo dict form).
- User configs (`USER_CONFIGS`): the planner settings that change behaviour
  (`interpolation_dt` [s], planning `time_budget` [s]); cuRobo's IK thresholds and seed
  counts have no manip equivalent (manip's IK converges to 1e-4 m / 1e-3 rad) and are left out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from manip.errors import UnknownNameError
from manip.pose import Pose


@dataclass(frozen=True)
class TutorialRobotConfig:
    """A cuRobo robot config file's content, in manip terms.

    Attributes:
        file_name: the file name the tutorial passes.
        robot: manip robot name (`robots/<robot>`) planned for.
        joint_names: cuRobo's c-space joint names: the planned joints then the locked ones.
        retract_config: (len(joint_names),) the retract configuration [rad or m].
        locked_joints: joint name -> position held during planning [rad or m].
        ee_link: name of the wrapper's end-effector frame.
        T_link_ee: pose of `ee_link` in the planner's end-effector link frame.
        base_link: the base frame poses are given in.
    """

    file_name: str
    robot: str
    joint_names: tuple[str, ...]
    retract_config: tuple[float, ...]
    locked_joints: dict[str, float] = field(default_factory=dict)
    ee_link: str = "ee_link"
    T_link_ee: Pose = field(default_factory=Pose.identity)
    base_link: str = "panda_link0"


_FRANKA_ARM = tuple(f"panda_joint{i}" for i in range(1, 8))
_FINGERS = ("panda_finger_joint1", "panda_finger_joint2")

#: ee_link of my_franka_robot_config.yml: on panda_hand at xyz (0, 0, 0.1), rpy (0, pi, 0),
#: so that the identity orientation points the gripper down. Quaternion of Ry(pi) (w, x, y, z).
FRANKA_T_HAND_EE = Pose(np.array([0.0, 0.0, 0.1]), np.array([math.cos(math.pi / 2), 0.0, math.sin(math.pi / 2), 0.0]))

ROBOT_CONFIGS: dict[str, TutorialRobotConfig] = {
    "my_franka_robot_config.yml": TutorialRobotConfig(
        file_name="my_franka_robot_config.yml",
        robot="franka",
        joint_names=_FRANKA_ARM + _FINGERS,
        retract_config=(0.0, -1.3, 0.0, -2.5, 0.0, 1.0, 0.0, 0.04, 0.04),
        locked_joints={"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04},
        ee_link="ee_link",
        T_link_ee=FRANKA_T_HAND_EE,
        base_link="panda_link0",
    ),
    # cuRobo's own Franka file (content/configs/robot/franka.yml): the same c-space and
    # retract configuration, its ee_link is panda_hand itself (cuRobo writes the second
    # finger's 0.04 m as -0.04 for its USD's flipped joint; manip's finger limits are [0, 0.04])
    "franka.yml": TutorialRobotConfig(
        file_name="franka.yml",
        robot="franka",
        joint_names=_FRANKA_ARM + _FINGERS,
        retract_config=(0.0, -1.3, 0.0, -2.5, 0.0, 1.0, 0.0, 0.04, 0.04),
        locked_joints={"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04},
        ee_link="panda_hand",
        base_link="panda_link0",
    ),
}

#: cuRobo's robot files of arms manip does not ship in that form: what to use instead.
OTHER_ROBOT_FILES: dict[str, str] = {
    "ur5e.yml": "manip ships the UR5 (CB-series), whose link lengths differ from the UR5e's: give robot='ur5' to plan "
                "for it, or the folder of your own UR5e robot.yaml (README, \"Robots\")",
    "ur10e.yml": "manip ships the UR10 (CB-series), whose link lengths differ from the UR10e's: give robot='ur10' to "
                 "plan for it, or the folder of your own UR10e robot.yaml (README, \"Robots\")",
    "kinova_gen3.yml": "manip ships the Kinova Jaco2 j2s6s200 (6 joints) as robot='kinova', no Gen3: give the folder "
                       "of your own Gen3 robot.yaml (README, \"Robots\")",
    "jaco7.yml": "manip ships the 6-joint Kinova Jaco2 j2s6s200 as robot='kinova', not the 7-joint Jaco: give the "
                 "folder of your own robot.yaml (README, \"Robots\")",
}

#: cuRobo's collision_base.yml: a post under the robot base (the base frame's z = 0 is the
#: robot's mounting plane; the post's top is 5 cm below it).
WORLD_CONFIGS: dict[str, dict] = {
    "collision_base.yml": {"cuboid": {"table": {"dims": [0.1, 0.1, 0.8], "pose": [0.0, 0.0, -0.45, 1.0, 0.0, 0.0, 0.0]}}},
}

#: MotionGenerator keyword arguments of each user config file (None: the wrapper's default file).
USER_CONFIGS: dict[str | None, dict] = {
    None: {},
    "default_user_config.toml": {},
    "isaac_sim_user_config.toml": {"interpolation_dt": 0.004, "time_budget": 10.0},
}


def is_config_file_name(name: object) -> bool:
    """Whether `name` looks like a config file name (a .yml/.yaml/.toml string) rather than a manip robot name."""
    return isinstance(name, str) and name.lower().endswith((".yml", ".yaml", ".toml"))


def robot_config(file_name: str) -> TutorialRobotConfig:
    """The settings of a known robot config file name.

    Raises:
        UnknownNameError: not a known name (the message lists them; for cuRobo's file of an
            arm manip ships in another version, it says what to use instead).
    """
    if file_name not in ROBOT_CONFIGS:
        error = UnknownNameError("robot config file", file_name, ROBOT_CONFIGS)
        if file_name in OTHER_ROBOT_FILES:
            error.args = (f"{error.args[0]}. {OTHER_ROBOT_FILES[file_name]}",)
        raise error
    return ROBOT_CONFIGS[file_name]


def world_config(file_name: str) -> dict:
    """The obstacles (cuRobo dict form, robot base frame) of a known world config file name.

    Raises:
        UnknownNameError: not a known name (the message lists them).
    """
    if file_name not in WORLD_CONFIGS:
        raise UnknownNameError("world config file", file_name, WORLD_CONFIGS)
    return WORLD_CONFIGS[file_name]


def user_config(file_name: str | None) -> dict:
    """MotionGenerator keyword arguments of a known user config file name (None: defaults).

    Raises:
        UnknownNameError: not a known name (the message lists them).
    """
    if file_name not in USER_CONFIGS:
        raise UnknownNameError("user config file", str(file_name), [k for k in USER_CONFIGS if k is not None])
    return dict(USER_CONFIGS[file_name])
