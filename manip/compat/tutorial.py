"""`TutorialMotionGen`: the Isaac Sim tutorial's cuRobo wrapper names, holding a MotionGenerator.

Scripts written against the tutorial's wrapper keep working: poses are lists
[x, y, z, qx, qy, qz, qw], failures return None (the reason is logged), solutions are dicts
of per-step lists. New code should use `MotionGenerator` (results with statuses that say why).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.motion_generator import MotionGenerator
from manip.planning.result import PlanResult
from manip.pose import Pose
from manip.sim_bridge import solution_to_actions

logger = logging.getLogger(__name__)


def wxyz_to_xyzw(q: Sequence[float]) -> list[float]:
    """[w, x, y, z] -> [x, y, z, w]."""
    return quat.wxyz_to_xyzw(np.asarray(q, dtype=float)).tolist()


def xyzw_to_wxyz(q: Sequence[float]) -> list[float]:
    """[x, y, z, w] -> [w, x, y, z]."""
    return quat.xyzw_to_wxyz(np.asarray(q, dtype=float)).tolist()


class TutorialMotionGen:
    """The tutorial wrapper's API on a `MotionGenerator` it holds (`.motion_gen`).

    Args:
        robot, world, **kwargs: as `MotionGenerator` (a new one is built), or
        motion_gen: an existing MotionGenerator to wrap (then give nothing else).

    Every attribute not defined here (robot facts, `plan_*`, world edits) is the held
    MotionGenerator's.
    """

    wxyz_to_xyzw = staticmethod(wxyz_to_xyzw)
    wxzy_to_xyzw = staticmethod(wxyz_to_xyzw)  # the tutorial's spelling
    xyzw_to_wxyz = staticmethod(xyzw_to_wxyz)

    def __init__(self, robot="franka", world=None, *, motion_gen: MotionGenerator | None = None, **kwargs):
        if motion_gen is not None:
            if not isinstance(motion_gen, MotionGenerator):
                raise InvalidInputError(f"motion_gen must be a MotionGenerator; got {type(motion_gen).__name__}")
            if world is not None or kwargs:
                raise InvalidInputError("give either motion_gen or the MotionGenerator's arguments, not both")
            self.motion_gen = motion_gen
        else:
            self.motion_gen = MotionGenerator(robot, world, **kwargs)
        self._hold_vec_weight: np.ndarray | None = None

    @classmethod
    def wrap(cls, motion_gen: MotionGenerator) -> TutorialMotionGen:
        """The wrapper around an existing MotionGenerator."""
        return cls(motion_gen=motion_gen)

    def __getattr__(self, name: str):
        if name == "motion_gen":  # not yet set (during construction)
            raise AttributeError(name)
        return getattr(self.motion_gen, name)

    # ------------------------------------------------------------------ kinematics
    def init_motion_gen(self) -> None:
        """Warm up: an IK solve and a short plan in free space (first-call costs paid here)."""
        mg = self.motion_gen
        q0 = mg.default_joint_positions
        mg.ik(mg.fk(q0), seed_q=q0)
        step = np.where(q0 < mg.upper_limits - 0.1, 0.05, -0.05)
        if not mg.check_collision(q0) and not mg.check_collision(q0 + step):
            mg.plan_joints(q0, q0 + step)

    def fk(self, joint_angles, link: str | None = None) -> list[float]:
        """[x, y, z, qx, qy, qz, qw] of `link` (default `ee_link`) at the joint angles (dof,)."""
        mg = self.motion_gen
        q = mg.kinematics.check_q(joint_angles, "joint_angles")
        return mg.fk(q, link).to_xyz_xyzw().tolist()

    def ik(self, pose_xyzw, seed_joint_angles=None) -> list[float] | None:
        """Collision-free joint angles placing `ee_link` at [x, y, z, qx, qy, qz, qw], or None."""
        mg = self.motion_gen
        seed = mg.default_joint_positions if seed_joint_angles is None else seed_joint_angles
        res = mg.ik(Pose.from_xyz_xyzw(pose_xyzw), seed_q=seed, collision_free=True)
        return res.q.tolist() if res.success else None

    def ik_batch(self, poses_xyzw: Sequence[Sequence[float]]) -> list[list[float] | None]:
        """Joint angles for each [x, y, z, qx, qy, qz, qw] (collision-free); None where it fails."""
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
        """Remove the constraint set by `set_constraint`."""
        self._hold_vec_weight = None

    # ------------------------------------------------------------------ planning
    def motion_generate(
        self,
        start_joint_angles: Sequence[float],
        goal_end_effector_pose: Sequence[float] | None = None,
        goal_joint_angles: Sequence[float] | None = None,
    ) -> dict | None:
        """Plan to a pose [x, y, z, qx, qy, qz, qw] of `ee_link` or to joint angles.

        Returns:
            None on failure (the reason is logged), else {"success", "joint_names",
            "positions", "velocities", "accelerations", "jerks" (one list per time step),
            "interpolation_dt"}.
        """
        mg = self.motion_gen
        start = np.asarray(start_joint_angles, dtype=float)
        if (goal_end_effector_pose is None) == (goal_joint_angles is None):
            raise InvalidInputError("give exactly one of goal_end_effector_pose or goal_joint_angles")
        if goal_joint_angles is not None:
            result = mg.plan_joints(start, np.asarray(goal_joint_angles, dtype=float))
        else:
            goal = Pose.from_xyz_xyzw(goal_end_effector_pose)
            if self._hold_vec_weight is not None and np.any(self._hold_vec_weight > 0):
                goal = self._constrained_goal(start, goal)
                if goal is None:
                    return None
                result = mg.plan_pose(start, goal, linear=True)
            else:
                result = mg.plan_pose(start, goal)
        return _solution(result)

    def _constrained_goal(self, start: np.ndarray, goal: Pose) -> Pose | None:
        """The goal with held rotation taken from the start; None if it moves a held axis."""
        w = self._hold_vec_weight
        now = self.motion_gen.fk(start)
        if np.any(w[:3] > 0):
            goal = Pose(goal.position, now.quaternion)
        delta = now.inverse() @ goal  # goal expressed in the start's end-effector frame
        held = np.flatnonzero(w[3:] > 0)
        if held.size and np.any(np.abs(delta.position[held]) > 1e-4):
            logger.warning("motion_generate: the goal moves held axes %s of the end-effector frame", held.tolist())
            return None
        return goal

    # ------------------------------------------------------------------ simulator
    def update_obstacle_from_world(self, world, robot_prim_path: str, ignore_prim_paths: Sequence[str] = ()):
        """Read the simulated World's collision objects into the planner (robot base frame).

        Objects whose name or prim path starts with an entry of `ignore_prim_paths` are left
        out, and so is the robot at `robot_prim_path`. Returns the new WorldConfig.
        """
        robot = _find_robot(world, robot_prim_path)
        return self.motion_gen.update_world_from_sim(world, robot, ignore=list(ignore_prim_paths or ()))

    update_obstacle_from_isaac_sim = update_obstacle_from_world

    def convert_solution_to_actions(self, solution: dict, robot) -> list[ArticulationAction]:
        """One ArticulationAction per time step of a `motion_generate` solution."""
        return solution_to_actions(solution, robot)

    convert_solution_to_isaac_sim_action = convert_solution_to_actions


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
