"""`TutorialMotionGen`: the Isaac Sim tutorial's cuRobo wrapper names, holding a MotionGenerator.

Scripts written against the tutorial's wrapper (Auromix's `CuroboMotionGenerator`) keep
working with `from manip import TutorialMotionGen as CuroboMotionGenerator`: poses are lists
[x, y, z, qx, qy, qz, qw], failures return None (the reason is logged), solutions are dicts
of per-step lists. New code should use `MotionGenerator` (results with statuses that say why).

Two constructions:

- the tutorial's: `TutorialMotionGen(robot_config_file_name="my_franka_robot_config.yml",
  world_config_file_name="collision_base.yml", user_config_file_name="isaac_sim_user_config.toml")`
  (or the same three names positionally). The names map to manip settings
  (`manip.compat.tutorial_configs`); unknown names raise `UnknownNameError` listing the known
  ones. The wrapper then behaves as cuRobo's: `joint_names` and `default_joint_positions` have
  9 entries (the 7 arm joints, then the 2 fingers, locked at 0.04 m for planning), and poses
  are those of cuRobo's `ee_link`, a frame 0.1 m along panda_hand's z axis rotated pi about
  y, so the identity orientation points the gripper down. The wrapper converts between that
  frame and the MotionGenerator's panda_hand poses.
- manip's: `TutorialMotionGen("franka", world, **MotionGenerator_kwargs)`, or
  `TutorialMotionGen(motion_gen=mg)`: the MotionGenerator's joints (7) and end-effector link.

Beyond the wrapper: the ground plane stays in the planner's world when the tutorial's
`ignore_prim_paths` names it (a plan through the floor drags a held object along it), and
with a tutorial robot config a pose goal may be reached turned half a turn about the
gripper's approach axis when the wrist gets there with the shorter motion
(`symmetric_gripper`). The wrapper's other attributes (`user_config`, `robot_config`,
`kinematics_model`, `motion_gen_plan_config`, `tensor_args`) are in
`manip.compat.tutorial_attributes`.
"""

from __future__ import annotations

import copy
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.collision import WorldConfig
from manip.compat import tutorial_attributes as attrs
from manip.compat.pointcloud import voxel_mesh
from manip.compat.tutorial_configs import (
    TutorialRobotConfig,
    is_config_file_name,
    robot_config,
    user_config,
    world_config,
)
from manip.errors import InvalidInputError, UnknownNameError
from manip.motion_generator import MotionGenerator
from manip.planning.result import PlanResult
from manip.pose import Pose
from manip.sim_bridge import solution_arrays

logger = logging.getLogger(__name__)


def wxyz_to_xyzw(q: Sequence[float]) -> list[float]:
    """[w, x, y, z] -> [x, y, z, w]."""
    return quat.wxyz_to_xyzw(np.asarray(q, dtype=float)).tolist()


def xyzw_to_wxyz(q: Sequence[float]) -> list[float]:
    """[x, y, z, w] -> [w, x, y, z]."""
    return quat.xyzw_to_wxyz(np.asarray(q, dtype=float)).tolist()


@dataclass(frozen=True)
class TutorialJointState:
    """A robot's joint state in the planner's joint order (cuRobo's `JointState` fields).

    Attributes:
        position, velocity, acceleration, jerk: (dof,) each [rad, rad/s, ...]; acceleration
            and jerk are zeros (the simulator does not report them).
        joint_names: the planner's joints.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    joint_names: list[str]


class TutorialMotionGen:
    """The tutorial wrapper's API on a `MotionGenerator` it holds (`.motion_gen`).

    Args:
        robot: a manip robot name or RobotConfig (default "franka"), or a tutorial robot
            config file name (same as `robot_config_file_name`).
        world: obstacles (WorldConfig or cuRobo dict), or a world config file name.
        user_config_file_name: a tutorial user config file name (planner settings).
        robot_config_file_name, world_config_file_name: the tutorial's keyword names.
        motion_gen: an existing MotionGenerator to wrap (then give nothing else).
        **kwargs: MotionGenerator options (override those of the user config).

    Every attribute not defined here (robot facts, `plan_*`, world edits) is the held
    MotionGenerator's.

    Raises:
        UnknownNameError: an unknown config file name (the message lists the known ones).
        InvalidInputError: a robot or world given twice, or motion_gen with other arguments.
    """

    wxyz_to_xyzw = staticmethod(wxyz_to_xyzw)
    wxzy_to_xyzw = staticmethod(wxyz_to_xyzw)  # the tutorial's spelling
    xyzw_to_wxyz = staticmethod(xyzw_to_wxyz)

    def __init__(self, robot=None, world=None, user_config_file_name: str | None = None, *,
                 robot_config_file_name: str | None = None, world_config_file_name: str | None = None,
                 motion_gen: MotionGenerator | None = None, **kwargs):
        self._tutorial: TutorialRobotConfig | None = None
        self._hold_vec_weight: np.ndarray | None = None
        self._warned_ground = False
        #: Pose goals also offered turned half a turn about the end effector's approach axis
        #: (a parallel gripper's symmetry): the plan takes the one the wrist reaches with the
        #: shorter motion. True with a tutorial robot config (the Franka's gripper); set False
        #: when the object's yaw must be exactly the goal's.
        self.symmetric_gripper = False
        if motion_gen is not None:
            if not isinstance(motion_gen, MotionGenerator):
                raise InvalidInputError(f"motion_gen must be a MotionGenerator; got {type(motion_gen).__name__}")
            if any(v is not None for v in (robot, world, user_config_file_name, robot_config_file_name,
                                           world_config_file_name)) or kwargs:
                raise InvalidInputError("give either motion_gen or the MotionGenerator's arguments, not both")
            self.motion_gen = motion_gen
            self._user_options = {}
        else:
            robot = _one_of(robot, robot_config_file_name, "robot", "robot_config_file_name")
            world = _one_of(world, world_config_file_name, "world", "world_config_file_name")
            tutorial_style = is_config_file_name(robot) or is_config_file_name(world) or user_config_file_name
            if is_config_file_name(robot):
                self._tutorial = robot_config(robot)
                robot = self._tutorial.robot
            if world is None and tutorial_style:
                world = "collision_base.yml"  # the wrapper's default world file
            if is_config_file_name(world):
                world = world_config(world)
            options = user_config(user_config_file_name)
            options.update(kwargs)
            self._user_options = dict(options)
            self.motion_gen = MotionGenerator("franka" if robot is None else robot, world, **options)
        self._initial_world = copy.deepcopy(self.motion_gen.world)
        if self._tutorial is not None:
            self.symmetric_gripper = True
            missing = [n for n in self.motion_gen.joint_names if n not in self._tutorial.joint_names]
            if missing:
                raise InvalidInputError(f"robot config {self._tutorial.file_name}: planner joints {missing} not in its "
                                        f"joint_names {list(self._tutorial.joint_names)}")

    def __getattr__(self, name: str):
        if name in ("motion_gen", "_user_options"):  # not yet set (during construction)
            raise AttributeError(name)
        try:
            return getattr(self.motion_gen, name)
        except AttributeError:
            raise attrs.TutorialAttributeError(
                f"TutorialMotionGen has no attribute {name!r}: neither the cuRobo wrapper's names manip provides nor "
                "the MotionGenerator's (see manip/compat/tutorial.py and tutorial_attributes.py)") from None

    # ------------------------------------------------------------------ the wrapper's other attributes
    @property
    def user_config(self) -> dict:
        """The planner settings of the user config file (and keyword options), a dict."""
        return dict(self._user_options)

    @property
    def robot_config(self) -> dict:
        """The robot config as cuRobo's `robot_cfg` dict (`manip.compat.tutorial_attributes`)."""
        return attrs.robot_config_dict(self.base_link, self.end_effector_link, self.joint_names,
                                       list(np.asarray(self.default_joint_positions, dtype=float)),
                                       self.locked_joints, self.motion_gen.config.name)

    @property
    def kinematics_model(self) -> attrs.KinematicsModel:
        """Forward kinematics of the wrapper's end effector: `get_state(q)` (q as `fk` takes it)."""
        mg = self.motion_gen

        def ee_pose(q: np.ndarray):
            pose = self._ee_pose(mg.fk(self._q(q, "q")))
            return pose.position.copy(), pose.quaternion.copy()

        return attrs.kinematics_model(ee_pose, list(mg.joint_names), np.stack([mg.lower_limits, mg.upper_limits], 1))

    @property
    def motion_gen_plan_config(self) -> attrs.MotionGenPlanConfig:
        return attrs.plan_config(self._user_options)

    @property
    def tensor_args(self) -> attrs.TensorArgs:
        return attrs.tensor_args()

    # ------------------------------------------------------------------ robot facts (cuRobo's attributes)
    @property
    def joint_names(self) -> list[str]:
        """The c-space joints: with a tutorial robot config, the planned joints then the
        locked ones (Franka: 7 arm joints, then the 2 fingers); else the planner's joints."""
        return list(self._tutorial.joint_names) if self._tutorial else self.motion_gen.joint_names

    @property
    def default_joint_positions(self):
        """The retract configuration, one value per `joint_names` entry (a list with a
        tutorial robot config, else the MotionGenerator's (dof,) array)."""
        if self._tutorial:
            return list(self._tutorial.retract_config)
        return self.motion_gen.default_joint_positions

    initial_joint_angles = default_joint_positions

    @property
    def robot_dof(self) -> int:
        return len(self.joint_names)

    @property
    def locked_joints(self) -> dict[str, float]:
        """Joints held fixed during planning -> their position [rad or m]."""
        return dict(self._tutorial.locked_joints) if self._tutorial else {}

    @property
    def base_link(self) -> str:
        return self._tutorial.base_link if self._tutorial else self.motion_gen.base_link

    @property
    def end_effector_link(self) -> str:
        """The frame poses are given for (cuRobo's `ee_link` with a tutorial robot config)."""
        return self._tutorial.ee_link if self._tutorial else self.motion_gen.ee_link

    @property
    def world_config(self) -> WorldConfig:
        """The world loaded at construction (`reset_world()` goes back to it)."""
        return copy.deepcopy(self._initial_world)

    # ------------------------------------------------------------------ frames and joints
    def _ee_pose(self, link_pose: Pose) -> Pose:
        """The wrapper's end-effector pose from the planner's end-effector link pose."""
        return link_pose @ self._tutorial.T_link_ee if self._tutorial else link_pose

    def _link_pose(self, ee_pose: Pose) -> Pose:
        """The planner's end-effector link pose that puts the wrapper's end effector at `ee_pose`."""
        return ee_pose @ self._tutorial.T_link_ee.inverse() if self._tutorial else ee_pose

    def _q(self, values, what: str) -> np.ndarray:
        """The planned joints' values (dof,) from `values`: the planned joints, or every
        `joint_names` entry (the locked joints' values are then dropped)."""
        mg = self.motion_gen
        a = np.asarray(values, dtype=float).ravel()
        if self._tutorial and a.size == self.robot_dof and a.size != mg.robot_dof:
            a = a[[self._tutorial.joint_names.index(n) for n in mg.joint_names]]
        if a.size != mg.robot_dof:
            sizes = sorted({mg.robot_dof, self.robot_dof})
            raise InvalidInputError(f"{what} needs {' or '.join(map(str, sizes))} values "
                                    f"({self.joint_names}); got {a.size}")
        return mg.kinematics.check_q(a, what)

    # ------------------------------------------------------------------ kinematics
    def init_motion_gen(self) -> None:
        """Warm up (an IK solve and a short plan in free space, first-call costs paid here),
        then load the construction world, as the wrapper does."""
        mg = self.motion_gen
        self.reset_world()
        q0 = mg.default_joint_positions
        mg.ik(mg.fk(q0), seed_q=q0)
        step = np.where(q0 < mg.upper_limits - 0.1, 0.05, -0.05)
        if not mg.check_collision(q0) and not mg.check_collision(q0 + step):
            mg.plan_joints(q0, q0 + step)

    def fk(self, joint_angles, link: str | None = None) -> list[float]:
        """[x, y, z, qx, qy, qz, qw] of the end effector (`end_effector_link`) at the joint
        angles (planned joints, or all `joint_names`), or of another planner `link`."""
        q = self._q(joint_angles, "joint_angles")
        if link is not None:
            return self.motion_gen.fk(q, link).to_xyz_xyzw().tolist()
        return self._ee_pose(self.motion_gen.fk(q)).to_xyz_xyzw().tolist()

    def ik(self, pose_xyzw, seed_joint_angles=None) -> list[float] | None:
        """Collision-free joint angles (planned joints) placing the end effector at
        [x, y, z, qx, qy, qz, qw], or None."""
        mg = self.motion_gen
        seed = mg.default_joint_positions if seed_joint_angles is None else self._q(seed_joint_angles, "seed")
        res = mg.ik(self._link_pose(Pose.from_xyz_xyzw(pose_xyzw)), seed_q=seed, collision_free=True)
        return res.q.tolist() if res.success else None

    def ik_batch(self, poses_xyzw: Sequence[Sequence[float]]) -> list[list[float] | None]:
        """Joint angles for each [x, y, z, qx, qy, qz, qw] (collision-free); None where it fails."""
        sizes = [np.size(p) for p in poses_xyzw] if isinstance(poses_xyzw, (list, tuple)) else []
        odd = [k for k, n in enumerate(sizes) if n != 7]
        if odd:
            raise InvalidInputError(f"poses_xyzw: each pose is [x, y, z, qx, qy, qz, qw]; pose {odd[0]} has "
                                    f"{sizes[odd[0]]} values")
        return [self.ik(pose) for pose in np.atleast_2d(np.asarray(poses_xyzw, dtype=float))]

    # ------------------------------------------------------------------ constraints
    def set_constraint(self, hold_vec_weight: Sequence[float]) -> None:
        """Hold parts of the end-effector pose during pose motions of `motion_generate`.

        `hold_vec_weight` is [roll, pitch, yaw, x, y, z] in the goal frame (> 0 = hold). Pose
        goals are then reached by a straight-line motion keeping the start orientation where
        the rotation is held; a goal that changes a held position axis is refused (None).
        """
        w = np.asarray(hold_vec_weight, dtype=float)
        if w.shape != (6,) or not np.all(np.isfinite(w)):
            raise InvalidInputError(f"hold_vec_weight must be 6 finite weights [roll, pitch, yaw, x, y, z]; got {w}")
        self._hold_vec_weight = w

    def reset_constraint(self) -> None:
        """Remove the constraint set by `set_constraint` (all weights 0)."""
        self._hold_vec_weight = None

    # ------------------------------------------------------------------ planning
    def motion_generate(
        self,
        start_joint_angles: Sequence[float],
        goal_end_effector_pose: Sequence[float] | None = None,
        goal_joint_angles: Sequence[float] | None = None,
    ) -> dict | None:
        """Plan to an end-effector pose [x, y, z, qx, qy, qz, qw] (base frame) or to joint angles.

        Joint angles (start and goal) are the planned joints, or all `joint_names` (e.g. the
        robot's 9 positions, fingers included; the locked joints' values are not used). With
        `symmetric_gripper` (a tutorial robot config), a pose goal may be reached turned half
        a turn about the tool's approach axis, whichever the wrist reaches sooner.

        Returns:
            None on failure (the reason is logged), else {"success", "joint_names" (the
            planned joints), "positions", "velocities", "accelerations", "jerks" (one list
            per time step), "interpolation_dt", "raw_data" (the `Trajectory`)}.
        """
        mg = self.motion_gen
        start = self._q(start_joint_angles, "start_joint_angles")
        if (goal_end_effector_pose is None) == (goal_joint_angles is None):
            raise InvalidInputError("give exactly one of goal_end_effector_pose or goal_joint_angles")
        if goal_joint_angles is not None:
            result = mg.plan_joints(start, self._q(goal_joint_angles, "goal_joint_angles"))
        else:
            goal = Pose.from_xyz_xyzw(goal_end_effector_pose)
            if self._hold_vec_weight is not None and np.any(self._hold_vec_weight > 0):
                goal = self._constrained_goal(start, goal)
                if goal is None:
                    return None
                result = mg.plan_pose(start, self._link_pose(goal), linear=True)
            elif self.symmetric_gripper:
                twin = goal @ Pose(np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]))  # half a turn about the tool z
                result = mg.plan_goalset(start, Pose.stack([self._link_pose(goal), self._link_pose(twin)]))
            else:
                result = mg.plan_pose(start, self._link_pose(goal))
        return _solution(result)

    def _constrained_goal(self, start: np.ndarray, goal: Pose) -> Pose | None:
        """The end-effector goal with held rotation taken from the start; None if it moves a held axis."""
        w = self._hold_vec_weight
        now = self._ee_pose(self.motion_gen.fk(start))
        if np.any(w[:3] > 0):
            goal = Pose(goal.position, now.quaternion)
        delta = now.inverse() @ goal  # goal expressed in the start's end-effector frame
        held = np.flatnonzero(w[3:] > 0)
        if held.size and np.any(np.abs(delta.position[held]) > 1e-4):
            logger.warning("motion_generate: the goal moves held axes %s of the end-effector frame", held.tolist())
            return None
        return goal

    # ------------------------------------------------------------------ planner world
    def update_world_by_pointcloud(self, pointcloud_to_robot_base) -> None:
        """Replace the planner's world by one mesh made from a point cloud (N, 3) [m] in the
        robot base frame (the surface of the 2 cm voxels it occupies). A cloud that is not
        (N, 3) with N >= 1 logs a warning and changes nothing, as the wrapper does.

        Raises:
            InvalidInputError: non-finite points.
        """
        points = np.asarray(pointcloud_to_robot_base, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or points.shape[0] == 0:
            logger.warning("point cloud shape should be (n, 3), n >= 1; got %s: the world is not updated", points.shape)
            return
        self.motion_gen.update_world(WorldConfig([voxel_mesh(points, name="world_pointcloud")]))

    def reset_world(self) -> None:
        """Back to the world loaded at construction (e.g. collision_base.yml's post)."""
        self.motion_gen.update_world(copy.deepcopy(self._initial_world))

    # ------------------------------------------------------------------ simulator
    def update_obstacle_from_isaac_sim(self, world, robot_prim_path: str,
                                       ignore_prim_paths: Sequence[str] | None = None) -> WorldConfig:
        """Replace the planner's world by the simulated World's collision objects, in the
        frame of the robot at `robot_prim_path` (a scene object of `world`).

        Objects whose prim path (or name) CONTAINS any string of `ignore_prim_paths` are
        left out (the wrapper's substring rule), and so is the robot itself; ground planes
        are kept even when ignored (with a warning, once): cuRobo plans nothing under the
        floor either way in the tutorial's scene, and a plan through it drags a carried
        object along the floor. Returns the new WorldConfig.

        Raises:
            InvalidInputError: no scene object at `robot_prim_path` (the message lists them).
        """
        robot = _find_robot(world, robot_prim_path)
        if isinstance(ignore_prim_paths, str):
            ignore_prim_paths = [ignore_prim_paths]
        subs = [s for s in (ignore_prim_paths or ()) if s]
        objects = world.scene.get_collision_objects()
        ignored = {id(o) for o in objects if any(s in o.prim_path or s in o.name for s in subs)}
        grounds = [o.prim_path for o in objects if id(o) in ignored and o.shape == "plane"]
        if grounds and not self._warned_ground:
            logger.warning("update_obstacle_from_isaac_sim: ignore_prim_paths leaves out the ground plane %s; the "
                           "planner keeps it (a half-space under it), so that no motion passes through the floor (the "
                           "robot's base links are exempt from it)", grounds)
            self._warned_ground = True
        kept = [o for o in objects if id(o) not in ignored or o.shape == "plane"]
        filtered = SimpleNamespace(scene=SimpleNamespace(get_collision_objects=lambda include_robots=True: kept))
        return self.motion_gen.update_world_from_sim(filtered, robot)

    update_obstacle_from_world = update_obstacle_from_isaac_sim

    def get_joint_state_from_isaac_sim(self, robot_prim) -> TutorialJointState:
        """The simulated robot's joint state in the planner's joint order (a warning is
        logged if the simulator returned NaN positions).

        Raises:
            UnknownNameError: a planned joint is not a DoF of the robot.
        """
        state = robot_prim.get_joints_state()
        names = [str(n) for n in robot_prim.dof_names]
        if np.any(np.isnan(state.positions)):
            logger.warning("the simulator returned NaN joint positions for %s", getattr(robot_prim, "prim_path", robot_prim))
        idx = _indices(self.motion_gen.joint_names, names)
        v = np.asarray(state.velocities, dtype=float)[idx]
        return TutorialJointState(np.asarray(state.positions, dtype=float)[idx], v, np.zeros_like(v), np.zeros_like(v),
                                  list(self.motion_gen.joint_names))

    def convert_solution_to_isaac_sim_action(self, solution: dict, robot_prim) -> list[ArticulationAction]:
        """One ArticulationAction per time step of a `motion_generate` solution.

        The actions are in the full joint space (the planned joints plus the locked ones,
        e.g. the fingers at 0.04 m, velocity 0), ordered as the robot's DoFs: `joint_indices`
        are the robot's indices of those joints (locked joints the robot lacks are left out).

        Raises:
            InvalidInputError: the solution lacks a key or its arrays disagree in shape.
            UnknownNameError: a planned joint is not a DoF of the robot.
        """
        names, positions, velocities = solution_arrays(solution)
        robot_names = [str(n) for n in robot_prim.dof_names]
        locked = {n: v for n, v in self.locked_joints.items() if n in robot_names and n not in names}
        full_names = names + list(locked)
        T = positions.shape[0]
        full_pos = np.hstack([positions, np.tile(list(locked.values()), (T, 1)).reshape(T, len(locked))])
        full_vel = np.hstack([velocities, np.zeros((T, len(locked)))])
        _indices(names, robot_names)  # every planned joint must be a DoF of the robot
        order = [full_names.index(n) for n in robot_names if n in full_names]
        idx = np.array([robot_names.index(full_names[k]) for k in order], dtype=int)
        return [ArticulationAction(joint_positions=full_pos[t, order], joint_velocities=full_vel[t, order],
                                   joint_indices=idx) for t in range(T)]

    convert_solution_to_actions = convert_solution_to_isaac_sim_action


def _one_of(a, b, name_a: str, name_b: str):
    if a is not None and b is not None:
        raise InvalidInputError(f"give either {name_a} or {name_b}, not both")
    return a if a is not None else b


def _indices(names: Sequence[str], robot_names: list[str]) -> list[int]:
    """Indices of `names` in `robot_names`.

    Raises:
        UnknownNameError: a name is missing (the message lists the robot's DoFs).
    """
    for n in names:
        if n not in robot_names:
            raise UnknownNameError("joint", n, robot_names)
    return [robot_names.index(n) for n in names]


def _solution(result: PlanResult) -> dict | None:
    """The tutorial's solution dict of a PlanResult (None on failure, with the reason logged)."""
    if not result.success:
        logger.warning("motion_generate failed: %s (%s)", result.status.name, result.message)
        return None
    traj = result.trajectory
    return {
        "success": True,
        "joint_names": list(traj.joint_names),
        "positions": traj.positions.tolist(),
        "velocities": traj.velocities.tolist(),
        "accelerations": traj.accelerations.tolist(),
        "jerks": traj.jerks.tolist(),
        "interpolation_dt": float(traj.dt),
        "raw_data": traj,
    }


def _find_robot(world, prim_path: str):
    """The scene object whose prim path is `prim_path` (duck-typed over manip.sim's Scene)."""
    scene = world.scene
    objects = [scene.get_object(name) for name in scene.get_object_names()]
    for obj in objects:
        if getattr(obj, "prim_path", None) == prim_path:
            return obj
    paths = sorted(str(getattr(o, "prim_path", "?")) for o in objects)
    raise InvalidInputError(f"no robot with prim path '{prim_path}' in the world's scene; prim paths: {paths}")
