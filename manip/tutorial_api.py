"""The Isaac Sim tutorial's cuRobo wrapper names, as thin calls into `MotionGenerator`.

Scripts written against the tutorial's wrapper keep working: poses are lists
[x, y, z, qx, qy, qz, qw], failures return None, solutions are dicts. New code should use
`MotionGenerator` directly (typed results, statuses that say why).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.motion_generator import MotionGenerator
from manip.pose import Pose
from manip.trajectory import Trajectory

logger = logging.getLogger(__name__)


def wxyz_to_xyzw(q: Sequence[float]) -> list[float]:
    """[w, x, y, z] -> [x, y, z, w]."""
    return quat.wxyz_to_xyzw(np.asarray(q, dtype=float)).tolist()


def xyzw_to_wxyz(q: Sequence[float]) -> list[float]:
    """[x, y, z, w] -> [w, x, y, z]."""
    return quat.xyzw_to_wxyz(np.asarray(q, dtype=float)).tolist()


class TutorialMotionGen:
    """The tutorial wrapper's interface over a `MotionGenerator`.

    Args:
        robot: robot name or config path ("franka").
        world: obstacles (WorldConfig or cuRobo world dict), in the robot base frame.
        **kwargs: passed to `MotionGenerator`.
    """

    def __init__(self, robot: str = "franka", world=None, **kwargs):
        self.motion_gen = MotionGenerator(robot, world, **kwargs)
        self._hold_vec_weight: np.ndarray | None = None

    # names of the wrapper
    @property
    def joint_names(self) -> list[str]:
        return self.motion_gen.joint_names

    @property
    def default_joint_positions(self) -> list[float]:
        return self.motion_gen.default_joint_positions.tolist()

    @property
    def robot_dof(self) -> int:
        return self.motion_gen.robot_dof

    wxyz_to_xyzw = staticmethod(wxyz_to_xyzw)
    wxzy_to_xyzw = staticmethod(wxyz_to_xyzw)  # the tutorial's spelling
    xyzw_to_wxyz = staticmethod(xyzw_to_wxyz)

    def init_motion_gen(self) -> None:
        """Warm up: one IK and one plan in free space (first-call costs paid here)."""
        mg = self.motion_gen
        q0 = mg.default_joint_positions
        mg.ik(mg.fk(q0), seed_q=q0)
        from manip.collision import WorldConfig

        probe = MotionGenerator(mg.config, WorldConfig(), seed=mg.seed)
        probe.plan_joints(q0, q0 + np.where(q0 < mg.upper_limits - 0.1, 0.05, -0.05))

    def fk(self, joint_angles: Sequence[float]) -> list[float]:
        """End-effector pose [x, y, z, qx, qy, qz, qw] of the arm joint angles."""
        return self.motion_gen.fk(np.asarray(joint_angles, dtype=float)).to_xyz_xyzw().tolist()

    def ik(self, pose_xyzw: Sequence[float], seed_joint_angles: Sequence[float] | None = None) -> list[float] | None:
        """Joint angles reaching [x, y, z, qx, qy, qz, qw] (collision-free), or None."""
        res = self.motion_gen.ik(Pose.from_xyz_xyzw(pose_xyzw), seed_q=seed_joint_angles, collision_free=True)
        return res.q.tolist() if res.success else None

    def ik_batch(self, poses_xyzw: Sequence[Sequence[float]]) -> list[list[float] | None]:
        """`ik` of each pose; None where it fails."""
        res = self.motion_gen.ik(Pose.from_xyz_xyzw(np.atleast_2d(np.asarray(poses_xyzw, dtype=float))))
        return [q.tolist() if ok else None for ok, q in zip(res.success, res.q)]

    def set_constraint(self, hold_vec_weight: Sequence[float]) -> None:
        """Hold parts of the end-effector pose during pose motions.

        `hold_vec_weight` is [roll, pitch, yaw, x, y, z] in the goal frame (1 = hold). Pose
        goals are then reached by a straight-line motion keeping the start orientation where
        the rotation is held; a goal that changes a held component is refused (None).
        """
        w = np.asarray(hold_vec_weight, dtype=float)
        if w.shape != (6,) or not np.all(np.isfinite(w)):
            raise InvalidInputError(f"hold_vec_weight must be 6 finite weights [roll, pitch, yaw, x, y, z]; got {w}")
        self._hold_vec_weight = w

    def reset_constraint(self) -> None:
        """Remove the constraint set by `set_constraint`."""
        self._hold_vec_weight = None

    def motion_generate(
        self,
        start_joint_angles: Sequence[float],
        goal_end_effector_pose: Sequence[float] | None = None,
        goal_joint_angles: Sequence[float] | None = None,
    ) -> dict | None:
        """Plan to a pose [x, y, z, qx, qy, qz, qw] or to joint angles.

        Returns:
            None on failure, else {"success", "joint_names", "positions", "velocities",
            "accelerations", "jerks" (one list per time step), "interpolation_dt"}.
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

    def update_obstacle_from_world(self, world, robot_prim_path: str, ignore_prim_paths: Sequence[str] = ()) -> None:
        """Read the simulated World's collision objects into the planner (robot base frame)."""
        robot = _find_robot(world, robot_prim_path)
        self.motion_gen.update_world_from_sim(world, robot, ignore=list(ignore_prim_paths) + [robot_prim_path])

    update_obstacle_from_isaac_sim = update_obstacle_from_world

    def convert_solution_to_actions(self, solution: dict, robot) -> list[ArticulationAction]:
        """One ArticulationAction per time step of a `motion_generate` solution."""
        positions = np.asarray(solution["positions"], dtype=float)
        dt = float(solution["interpolation_dt"])
        traj = Trajectory(
            times=np.arange(len(positions)) * dt,
            positions=positions,
            velocities=np.asarray(solution["velocities"], dtype=float),
            accelerations=np.asarray(solution["accelerations"], dtype=float),
            jerks=np.asarray(solution["jerks"], dtype=float),
            dt=dt,
            joint_names=solution["joint_names"],
        )
        return traj.to_articulation_actions(robot)

    convert_solution_to_isaac_sim_action = convert_solution_to_actions


def _find_robot(world, prim_path: str):
    """The scene object whose prim path is `prim_path` (duck-typed over manip.sim's Scene)."""
    for obj in world.scene.get_objects() if hasattr(world.scene, "get_objects") else []:
        if getattr(obj, "prim_path", None) == prim_path:
            return obj
    raise InvalidInputError(f"no robot with prim path '{prim_path}' in the world's scene")
