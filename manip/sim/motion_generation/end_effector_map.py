"""`EndEffectorMap`: an RMPflow end-effector frame of the URDF as a frame of manip's controller.

`RmpFlow` takes its end effector from the URDF (Isaac's Franka: `right_gripper`, 0.1 m
beyond `panda_hand`). manip's controller (`manip.control.ReactiveController`) controls a
site or body of the robot's MuJoCo model, which may not have that frame. The map picks the
end effector itself if the model has it, else its nearest URDF ancestor the model has,
rigidly attached to it (only fixed joints between), and keeps the fixed transform
`T_frame_ee` between the two. A target of the end effector becomes a target of the
controlled frame:

- pose: `T_base_frame = T_base_ee @ inverse(T_frame_ee)`;
- position only: `p_frame = p_ee - R_base_frame(q) @ t_frame_ee`, with the frame's current
  rotation (exact at convergence, whatever the orientation the arm settles in);
- orientation only: `R_base_frame = R_base_ee @ R_frame_ee^T` (the position is left free by
  the caller).

Poses are in the controller's base frame; `T_base_root` places the robot description's root
link (the link `set_robot_base_pose` puts in the world) in it. The URDF and the MuJoCo model
must agree on the controlled frame and on the root link (checked at construction).
"""

from __future__ import annotations

import numpy as np

from manip.control import ReactiveController, UnknownFrameError
from manip.errors import InvalidInputError, RobotConfigError
from manip.pose import Pose
from manip.urdf import UrdfTree

#: Largest disagreement between the URDF and the MuJoCo model at a frame: [m], [rad].
POSITION_AGREEMENT = 1e-4
ROTATION_AGREEMENT = 1e-3


def _has_frame(ctrl: ReactiveController, q: np.ndarray, name: str) -> Pose | None:
    try:
        return ctrl.forward_kinematics(q, name)
    except UnknownFrameError:
        return None


class EndEffectorMap:
    """The controlled frame standing for a URDF end-effector frame.

    Args:
        controller: the controller (its `frame` is set to the controlled frame).
        urdf: the URDF's link tree.
        root_link: the robot description's root link.
        ee_frame: the end-effector link of the URDF.
        fk_root: (link, q in the controller's joint order) -> the link's pose in the root
            link's frame from the URDF's kinematics.

    Raises:
        InvalidInputError: a movable joint between the end effector and every link the
            controller's model has.
        RobotConfigError: the URDF and the model disagree (frame or root link), or the model
            has no link above the end effector, or neither the root link nor a link fixed to it.
    """

    def __init__(self, controller: ReactiveController, urdf: UrdfTree, root_link: str, ee_frame: str, fk_root):
        q0 = controller.rest_configuration
        self.T_base_root = self._root(controller, urdf, root_link, q0, fk_root)
        chain = urdf.ancestors(ee_frame)
        for k, link in enumerate(chain):
            T_base_link = _has_frame(controller, q0, link)
            if T_base_link is None:
                continue
            moving = [urdf.parent_joint[c].name for c in chain[:k] if urdf.parent_joint[c].type != "fixed"]
            if moving:
                raise InvalidInputError(f"end_effector_frame_name {ee_frame!r}: joint {moving[0]!r} moves it relative "
                                        f"to {link!r}, the nearest link of the controller's model above it")
            T_root_link = fk_root(link, q0)
            dp, dr = (self.T_base_root @ T_root_link).distance(T_base_link)
            if float(dp) > POSITION_AGREEMENT or float(dr) > ROTATION_AGREEMENT:
                raise RobotConfigError(f"the URDF and the controller's model ({controller.config.name}) disagree at "
                                       f"{link!r} by {float(dp):.2e} m, {float(dr):.2e} rad")
            self.frame = link
            self.T_frame_ee = T_root_link.inverse() @ fk_root(ee_frame, q0)
            self._T_ee_frame = self.T_frame_ee.inverse()
            controller.frame = link
            return
        raise RobotConfigError(f"end_effector_frame_name {ee_frame!r}: none of its links {chain} is a body of the "
                               f"controller's model ({controller.config.name})")

    @staticmethod
    def _root(controller: ReactiveController, urdf: UrdfTree, root_link: str, q0: np.ndarray, fk_root) -> Pose:
        """The root link in the controller's base frame: itself if the model has it, else through
        the configuration's base link when only fixed joints join the two (a URDF `world` link)."""
        T = _has_frame(controller, q0, root_link)
        if T is not None:
            return T
        base = controller.config.base_link
        chain = urdf.ancestors(base) if base in urdf.links else []
        T_base_link = _has_frame(controller, q0, base)
        if root_link in chain and T_base_link is not None and all(
                urdf.parent_joint[c].type == "fixed" for c in chain[: chain.index(root_link)]):
            return T_base_link @ fk_root(base, q0).inverse()
        raise RobotConfigError(f"root_link {root_link!r} is neither a body of the controller's model "
                               f"({controller.config.name}) nor fixed to its base link {base!r}")

    def pose_target(self, T_base_ee: Pose) -> Pose:
        """The controlled frame's target for an end-effector pose target (base frame)."""
        return T_base_ee @ self._T_ee_frame

    def position_target(self, p_base_ee: np.ndarray, R_base_frame: np.ndarray) -> np.ndarray:
        """(3,) the controlled frame's position target for an end-effector position target,
        given the frame's current rotation (3, 3)."""
        return np.asarray(p_base_ee, dtype=float) - R_base_frame @ self.T_frame_ee.position

    def rotation_target(self, R_base_ee: np.ndarray) -> np.ndarray:
        """(3, 3) the controlled frame's rotation target for an end-effector rotation target."""
        return R_base_ee @ self.T_frame_ee.rotation.T


__all__ = ["EndEffectorMap"]
