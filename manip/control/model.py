"""`ControlModel`: the controller's own MuJoCo model of the robot and its obstacles.

Built from the robot configuration's MJCF (`robots/<name>/<name>.xml`, the model
`manip.sim` simulates): the arm joints stay, every other joint (the fingers) is frozen at
its planning position (`gripper.planning_positions` in robot.yaml, else 0) by folding it
into its body's pose, and actuators, keyframes and equality constraints are dropped. The
arm joints' ranges are the configuration's `lower_limits` / `upper_limits`. The robot's
base sits at the model's origin, so everything is expressed in the robot base frame, the
frame of the planner's `WorldConfig`. Each obstacle is a geom on its own mocap body
(`manip.control.obstacles`).
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip import quaternion as quat
from manip.collision.world import WorldConfig
from manip.control.obstacles import OBSTACLE_PREFIX, GeomShape, add_obstacle_body, geom_shape
from manip.errors import InvalidInputError, RobotConfigError, UnknownNameError
from manip.pose import Pose
from manip.robot_config import RobotConfig


class UnknownFrameError(UnknownNameError, InvalidInputError):
    """A frame name that the controller's model does not have (an UnknownNameError and an
    InvalidInputError; the message names the argument and lists the valid frames)."""


def _fold_joint(body: mujoco.MjsBody, joint: mujoco.MjsJoint, value: float) -> None:
    """Move `body` to where `joint` at `value` puts it, so the joint can be removed."""
    R = quat.to_matrix(np.asarray(body.quat, dtype=float))
    axis = np.asarray(joint.axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    if joint.type == mujoco.mjtJoint.mjJNT_SLIDE:
        body.pos = np.asarray(body.pos, dtype=float) + R @ (axis * value)
    elif joint.type == mujoco.mjtJoint.mjJNT_HINGE:
        r = quat.from_axis_angle(axis, value)
        anchor = np.asarray(joint.pos, dtype=float)
        body.pos = np.asarray(body.pos, dtype=float) + R @ (anchor - quat.to_matrix(r) @ anchor)
        body.quat = quat.multiply(np.asarray(body.quat, dtype=float), r)
    else:
        raise RobotConfigError(f"joint {joint.name!r}: only hinge and slide joints outside the arm can be frozen")


class ControlModel:
    """The robot (arm joints only) and the obstacles as one compiled MuJoCo model.

    Args:
        config: the robot configuration (needs an `mjcf`).
        world: obstacles in the robot base frame (None: none).

    Raises:
        RobotConfigError: the configuration has no MJCF, or it lacks an arm joint.
        InvalidInputError: an obstacle cannot be built (e.g. a flat mesh has no hull).
    """

    def __init__(self, config: RobotConfig, world: WorldConfig | None = None):
        if config.mjcf_path is None or not config.mjcf_path.is_file():
            raise RobotConfigError(f"robot {config.name!r}: the reactive controller needs its MuJoCo model (robot.yaml "
                                   f"'mjcf'); got {config.mjcf_path}")
        self.config = config
        self.shapes: dict[str, GeomShape] = {}
        world = world if world is not None else WorldConfig()
        spec = mujoco.MjSpec.from_file(str(config.mjcf_path))
        frozen = {}
        if config.gripper is not None:
            frozen = dict(zip(config.gripper.joints, np.asarray(config.gripper.planning_positions, dtype=float)))
        names = [j.name for j in spec.joints]
        missing = [j for j in config.arm_joints if j not in names]
        if missing:
            raise RobotConfigError(f"robot {config.name!r}: arm joint {missing[0]!r} is not in {config.mjcf_path}")
        for j in list(spec.joints):
            if j.name in config.arm_joints:
                k = config.arm_joints.index(j.name)
                j.range = [float(config.lower_limits[k]), float(config.upper_limits[k])]
                j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
                continue
            _fold_joint(j.parent, j, float(frozen.get(j.name, 0.0)))
            spec.delete(j)
        for group in (spec.actuators, spec.keys, spec.equalities, spec.tendons, spec.sensors):
            for item in list(group):
                spec.delete(item)
        self.robot_body_names = [b.name for b in spec.bodies if b.name and b.name != "world"]
        self.site_names = [s.name for s in spec.sites if s.name]
        for ob in world:
            shape = geom_shape(ob)
            add_obstacle_body(spec, ob.name, shape)
            self.shapes[ob.name] = shape
        try:
            self.model = spec.compile()
        except ValueError as exc:
            raise InvalidInputError(f"the controller's model does not compile (an obstacle mesh without volume?): {exc}") from exc
        m = self.model
        self.dof = len(config.arm_joints)
        self.qpos_index = np.array([m.jnt_qposadr[m.joint(j).id] for j in config.arm_joints], dtype=int)
        self.robot_bodies = {m.body(n).id for n in self.robot_body_names}
        self.obstacle_names = list(self.shapes)
        self.obstacle_geoms = {n: m.geom(OBSTACLE_PREFIX + n).id for n in self.obstacle_names}
        self.obstacle_mocap = {n: int(m.body_mocapid[m.body(OBSTACLE_PREFIX + n).id]) for n in self.obstacle_names}
        self._poses = {ob.name: ob.pose for ob in world}

    def pose_of(self, name: str) -> Pose:
        """The pose (base frame) the obstacle `name` was last given."""
        if name not in self._poses:
            raise UnknownNameError("obstacle", name, self._poses)
        return self._poses[name]

    def set_obstacle_pose(self, data: mujoco.MjData, name: str, pose: Pose) -> None:
        """Place obstacle `name` at `pose` (base frame) in `data` (no recompilation)."""
        i = self.obstacle_mocap.get(name)
        if i is None:
            raise UnknownNameError("obstacle", name, self.obstacle_names)
        data.mocap_pos[i] = pose.position
        data.mocap_quat[i] = pose.quaternion
        self._poses[name] = pose

    def write_obstacle_poses(self, data: mujoco.MjData) -> None:
        """Write every obstacle's current pose into `data`'s mocap arrays."""
        for name, i in self.obstacle_mocap.items():
            p = self._poses[name]
            data.mocap_pos[i] = p.position
            data.mocap_quat[i] = p.quaternion

    def frame(self, name: str, what: str = "frame") -> tuple[str, int]:
        """(mink frame type, id) of a site or body of the robot; sites first.

        Raises:
            UnknownFrameError: neither a site nor a robot body; lists the valid names.
        """
        if not isinstance(name, str):
            raise InvalidInputError(f"{what} must be a site or body name (str); got {name!r}")
        if name in self.site_names:
            return "site", self.model.site(name).id
        if name in self.robot_body_names:
            return "body", self.model.body(name).id
        raise UnknownFrameError(f"{what} (site or body)", name, self.site_names + self.robot_body_names)

    def q_to_qpos(self, q: np.ndarray) -> np.ndarray:
        """The model's qpos for arm joints `q` (configuration order)."""
        qpos = np.zeros(self.model.nq)
        qpos[self.qpos_index] = q
        return qpos
