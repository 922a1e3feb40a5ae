"""`LulaKinematicsSolver`: Isaac Sim's Lula kinematics interface on manip's kinematics and IK.

    solver = LulaKinematicsSolver(robot_description_path="robot_descriptor.yaml", urdf_path="robot.urdf")
    solver.set_robot_base_pose(position, orientation_wxyz)
    position, rotation = solver.compute_forward_kinematics("right_gripper", q)
    q, success = solver.compute_inverse_kinematics("right_gripper", target_position, target_orientation)

It is not Lula. The robot is the URDF (any URDF; `lula_franka_gen.urdf` maps to manip's
Franka: `manip.sim.motion_generation.urdf_aliases`) with the joints the Lula YAML names
(`manip.sim.motion_generation.robot_description` lists the keys read). Forward kinematics
is `manip.kinematics.Kinematics` (Pinocchio); pose inverse kinematics is
`manip.ik.IKSolver` (damped least squares with joint limits: the warm start first, then the
default cspace seeds, one attempt each, then up to `max_attempts` random restarts, seeded:
the same call gives the same answer); position-only IK (no target orientation) is the same
iteration on the position rows (`manip.ik.position`).

Frames: every link of the URDF (`get_all_frame_names`). Poses are in the world (stage)
frame: the robot's root link (`root_link` of the YAML, default the URDF's root) is placed by
`set_robot_base_pose` (identity until then), as in Isaac. Tolerances: position [m], the
Euclidean distance; orientation [rad], the angle of the rotation between the target and the
reached orientation (Isaac defines it as the largest angle between paired axes, the same
angle to first order). Defaults are manip's IKSolver's, 1e-3 m and 0.01 rad (Lula's own
defaults were not checked). Lula's solver tuning properties (bfgs_*, ccd_*) do not exist here.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pinocchio as pin

from manip.errors import InvalidInputError, UnknownNameError
from manip.ik import IKSolver
from manip.kinematics import Kinematics
from manip.pose import Pose
from manip.robot_config import GripperConfig, config_from_urdf
from manip.ik.position import solve_position
from manip.sim.motion_generation.robot_description import LulaRobotDescription, load_robot_description
from manip.sim.motion_generation.urdf_aliases import resolve_urdf
from manip.urdf import MOVABLE_TYPES, UrdfTree, build_model
from manip.validation import as_real_array, integer, positive, unit_quat, vec

#: Default IK tolerances: position [m], orientation [rad] (manip's IKSolver defaults).
DEFAULT_POSITION_TOLERANCE = 1e-3
DEFAULT_ORIENTATION_TOLERANCE = 0.01
#: Random restarts after the seeds, per IK call.
MAX_ATTEMPTS = 100


def _tree_order(desc: LulaRobotDescription, urdf) -> tuple[tuple[str, ...], str]:
    """The cspace joints in the URDF's tree order (manip.Kinematics's joint order), and the
    child link of the last one (the configuration's ee_link; no frame is privileged here)."""
    tree = UrdfTree(urdf)
    movable = [n for n, j in tree.joints.items() if j.type in MOVABLE_TYPES]
    for j in list(desc.cspace) + list(desc.fixed_joints):
        if j not in movable:
            what = "cspace joint" if j in desc.cspace else "cspace_to_urdf_rules joint"
            raise UnknownNameError(f"{desc.path.name}: {what}", j, movable)
    root = desc.root_link or tree.root_link
    tree.check_link(root, "root_link")
    above = [j.name for j in tree.chain_joints(tree.root_link, root) if j.name in desc.cspace]
    if above:
        raise InvalidInputError(f"{desc.path.name}: root_link {root} moves with cspace joints {above}; "
                                "the root link must be fixed to the URDF's root")
    names = list(build_model(urdf).names)
    order = tuple(sorted(desc.cspace, key=names.index))
    return order, tree.joints[order[-1]].child


class LulaKinematicsSolver:
    """Forward and inverse kinematics of a robot described by a Lula YAML and a URDF.

    Args:
        robot_description_path: the Lula robot description YAML.
        urdf_path: the robot's URDF (or an Isaac file name manip maps, such as
            `.../lula_franka_gen.urdf`).
        robot_description: Lula's `RobotDescription` object; not available (manip has no
            Lula), must be None.

    Raises:
        FileNotFoundError: no robot description, or no URDF (the message lists the mapped names).
        InvalidInputError: a malformed robot description.
        UnknownNameError: a cspace or rule joint, or the root link, the URDF does not have.
        RobotConfigError: a URDF manip cannot use (unreadable, meshes not found, limits).
    """

    def __init__(self, robot_description_path: str, urdf_path: str, robot_description: object | None = None):
        if robot_description is not None:
            raise InvalidInputError("robot_description (a lula.RobotDescription) is not available in manip: "
                                    "give robot_description_path and urdf_path")
        desc = load_robot_description(robot_description_path)
        if not isinstance(urdf_path, (str, Path)):
            raise InvalidInputError(f"urdf_path must be a path (str); got {type(urdf_path).__name__}")
        urdf = resolve_urdf(urdf_path)
        order, tip = _tree_order(desc, urdf)
        self._to_model = np.array([desc.cspace.index(n) for n in order])
        self._to_cspace = np.array([order.index(n) for n in desc.cspace])
        default = None if desc.default_q is None else desc.default_q[self._to_model]
        config = config_from_urdf(urdf, base_link=desc.root_link, ee_link=tip, arm_joints=list(order),
                                  default_joint_positions=default, acceleration_limits=10.0, jerk_limits=500.0)
        if desc.fixed_joints:  # held at their rule values (Kinematics holds a gripper's joints there)
            v = np.array(list(desc.fixed_joints.values()))
            config = dataclasses.replace(config, gripper=GripperConfig(tuple(desc.fixed_joints), v, v, v))
        self.description = desc
        self.kinematics = Kinematics(config)
        kin = self.kinematics
        self._frames = [f.name for f in kin.model.frames if f.type == pin.FrameType.BODY]
        self._joint_names = list(desc.cspace)
        self._T_model_root = kin.fk(config.default_joint_positions, config.base_link)
        self._T_world_root = Pose(np.zeros(3))
        self._position_tolerance = DEFAULT_POSITION_TOLERANCE
        self._orientation_tolerance = DEFAULT_ORIENTATION_TOLERANCE
        self._cspace_seeds: list[np.ndarray] = []
        self._solvers: dict[tuple[float, float, int], IKSolver] = {}
        self.sampling_seed = 0

    # ------------------------------------------------------------------ description
    def get_joint_names(self) -> list[str]:
        """The cspace joints, in the order of every joint vector of this solver."""
        return list(self._joint_names)

    def get_all_frame_names(self) -> list[str]:
        """Every link of the URDF (the frames FK and IK accept)."""
        return list(self._frames)

    def get_cspace_position_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower (dof,), upper (dof,)) position limits of the cspace joints [rad or m]."""
        return self.kinematics.lower[self._to_cspace].copy(), self.kinematics.upper[self._to_cspace].copy()

    def get_cspace_velocity_limits(self) -> np.ndarray:
        """(dof,) velocity limits of the cspace joints [rad/s or m/s] (the URDF's)."""
        return self.kinematics.limits.velocity[self._to_cspace].copy()

    def supports_collision_avoidance(self) -> bool:
        """False: this IK ignores obstacles (as Lula's)."""
        return False

    # ------------------------------------------------------------------ settings
    @property
    def sampling_seed(self) -> int:
        """Seed of the random restarts of IK (Lula's name)."""
        return self._seed

    @sampling_seed.setter
    def sampling_seed(self, value: int) -> None:
        self._seed = integer(value, "sampling_seed", 0)
        self._solvers.clear()

    def set_robot_base_pose(self, robot_position, robot_orientation) -> None:
        """Place the root link in the world: position (3,) [m], orientation (4,) (w, x, y, z)."""
        self._T_world_root = Pose(vec(robot_position, 3, "robot_position"),
                                  unit_quat(robot_orientation, "robot_orientation"))

    def set_default_position_tolerance(self, tolerance: float) -> None:
        """IK position tolerance [m] when a call gives none."""
        self._position_tolerance = positive(tolerance, "tolerance", "m")

    def get_default_position_tolerance(self) -> float:
        return self._position_tolerance

    def set_default_orientation_tolerance(self, tolerance: float) -> None:
        """IK orientation tolerance [rad] when a call gives none."""
        self._orientation_tolerance = positive(tolerance, "tolerance", "rad")

    def get_default_orientation_tolerance(self) -> float:
        return self._orientation_tolerance

    def set_default_cspace_seeds(self, seeds) -> None:
        """Configurations IK starts from after the warm start: (N, dof) [rad or m]."""
        a = as_real_array(seeds, "seeds")
        dof = len(self._joint_names)
        if a.ndim == 1 and a.size == dof:
            a = a[None]
        if a.ndim != 2 or a.shape[1] != dof or not np.all(np.isfinite(a)):
            raise InvalidInputError(f"seeds must be finite, shape (N, {dof}) for joints {self._joint_names}; "
                                    f"got shape {a.shape}")
        self._cspace_seeds = [row.copy() for row in a]

    def get_default_cspace_seeds(self) -> list[np.ndarray]:
        return [s.copy() for s in self._cspace_seeds]

    # ------------------------------------------------------------------ kinematics
    def _frame(self, frame_name: str) -> str:
        if not isinstance(frame_name, str) or frame_name not in self._frames:
            raise UnknownNameError("frame_name: frame", str(frame_name), self._frames)
        return frame_name

    def _q(self, q, what: str) -> np.ndarray:
        """A cspace joint vector, validated, in the kinematics' joint order."""
        try:
            q = vec(q, len(self._joint_names), what)
        except InvalidInputError as exc:
            raise InvalidInputError(f"{exc} (joints {self._joint_names})") from None
        return q[self._to_model]

    def compute_forward_kinematics(self, frame_name: str, joint_positions, position_only: bool = False
                                   ) -> tuple[np.ndarray, np.ndarray]:
        """The world pose of a frame.

        Args:
            frame_name: a frame of `get_all_frame_names()`.
            joint_positions: (dof,) positions of `get_joint_names()` [rad or m].
            position_only: accepted for Isaac's interface; the rotation is always computed.

        Returns:
            (position (3,) [m], rotation (3, 3)) of the frame in the world frame.
        """
        frame = self._frame(frame_name)
        T_model_frame = self.kinematics.fk(self._q(joint_positions, "joint_positions"), frame)
        T = self._T_world_root @ self._T_model_root.inverse() @ T_model_frame
        return np.array(T.position), T.rotation

    def _solver(self, tol_p: float, tol_r: float, attempts: int) -> IKSolver:
        key = (tol_p, tol_r, attempts)
        if key not in self._solvers:
            if len(self._solvers) >= 16:  # a script sweeping tolerances keeps a bounded cache
                self._solvers.clear()
            self._solvers[key] = IKSolver(self.kinematics, position_tolerance=tol_p, rotation_tolerance=tol_r,
                                          max_attempts=attempts, seed=self._seed)
        return self._solvers[key]

    def compute_inverse_kinematics(self, frame_name: str, target_position, target_orientation=None, warm_start=None,
                                   position_tolerance: float | None = None,
                                   orientation_tolerance: float | None = None) -> tuple[np.ndarray, bool]:
        """Joint positions placing a frame at a world pose (or a world position).

        Args:
            frame_name: a frame of `get_all_frame_names()`.
            target_position: (3,) [m], world frame.
            target_orientation: (4,) (w, x, y, z), world frame; None: position only.
            warm_start: (dof,) the first start [rad or m]; then the default cspace seeds,
                then random restarts.
            position_tolerance: [m]; None: the default.
            orientation_tolerance: [rad]; None: the default.

        Returns:
            (joint_positions (dof,) in `get_joint_names()` order, success). On failure the
            positions are the best found (within the joint limits).

        Raises:
            UnknownNameError: unknown frame (the message lists the frames).
            InvalidInputError: a wrong shape, a non-finite value, a quaternion whose norm is
                not 1 (within 1e-3), a tolerance that is not positive.
        """
        frame = self._frame(frame_name)
        p = vec(target_position, 3, "target_position")
        q_goal = None if target_orientation is None else unit_quat(target_orientation, "target_orientation")
        tol_p = self._position_tolerance if position_tolerance is None else positive(position_tolerance,
                                                                                      "position_tolerance", "m")
        tol_r = self._orientation_tolerance if orientation_tolerance is None else positive(
            orientation_tolerance, "orientation_tolerance", "rad")
        seeds = [] if warm_start is None else [self._q(warm_start, "warm_start")]
        seeds += [s[self._to_model] for s in self._cspace_seeds]
        T_model_world = self._T_model_root @ self._T_world_root.inverse()
        if q_goal is None:
            goal = T_model_world.transform_points(p)
            fid = self.kinematics.frame_id(frame)
            r = solve_position(self.kinematics, fid, goal, seeds or [self.kinematics.config.default_joint_positions],
                               tolerance=tol_p, max_attempts=len(seeds) + MAX_ATTEMPTS, seed=self._seed)
            return r.q[self._to_cspace], bool(r.success)
        goal = T_model_world @ Pose(p, q_goal)
        if len(seeds) > 1:  # each seed once, in order, before the restarts
            for s in seeds:
                result = self._solver(tol_p, tol_r, 1).solve(goal, frame, seed_q=s)
                if result.success:
                    return np.array(result.q)[self._to_cspace], True
        result = self._solver(tol_p, tol_r, MAX_ATTEMPTS).solve(goal, frame, seed_q=seeds[0] if seeds else None)
        return np.array(result.q)[self._to_cspace], bool(result.success)
