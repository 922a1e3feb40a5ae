"""The Isaac Sim tutorial's cuRobo wrapper names, as thin calls into `MotionGenerator`.

Scripts written against the tutorial's wrapper keep working: poses are lists
[x, y, z, qx, qy, qz, qw], failures return None, solutions are dicts. New code should use
the typed API (`plan_pose`, `plan_joints`: results with statuses that say why).

- `TutorialAPI` (a base of `MotionGenerator`): `init_motion_gen`, `motion_generate`,
  `update_obstacle_from_world` / `update_obstacle_from_isaac_sim`,
  `convert_solution_to_actions` / `convert_solution_to_isaac_sim_action`, `ik_batch`,
  `set_constraint`, `reset_constraint`, `wxyz_to_xyzw`, `xyzw_to_wxyz` (and the tutorial's
  spelling `wxzy_to_xyzw`).
- `manip.motion_generator.TutorialMotionGen`: a `MotionGenerator` whose `fk` and `ik` also
  follow the wrapper (lists in [x, y, z, qx, qy, qz, qw] order, None on failure).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np

from manip import quaternion as quat
from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.pose import Pose
from manip.trajectory import Trajectory

logger = logging.getLogger(__name__)


def wxyz_to_xyzw(q: Sequence[float]) -> list[float]:
    """[w, x, y, z] -> [x, y, z, w]."""
    return quat.wxyz_to_xyzw(np.asarray(q, dtype=float)).tolist()


def xyzw_to_wxyz(q: Sequence[float]) -> list[float]:
    """[x, y, z, w] -> [w, x, y, z]."""
    return quat.xyzw_to_wxyz(np.asarray(q, dtype=float)).tolist()


class TutorialAPI:
    """The tutorial wrapper's names on a MotionGenerator (mixed into `MotionGenerator`).

    Uses only the typed planning API and `kinematics` / `_ik`, never `fk` / `ik` (which
    `TutorialMotionGen` redefines).
    """

    _hold_vec_weight: np.ndarray | None = None

    wxyz_to_xyzw = staticmethod(wxyz_to_xyzw)
    wxzy_to_xyzw = staticmethod(wxyz_to_xyzw)  # the tutorial's spelling
    xyzw_to_wxyz = staticmethod(xyzw_to_wxyz)

    def init_motion_gen(self) -> None:
        """Warm up: an IK solve and a short plan in free space (first-call costs paid here)."""
        q0 = self.default_joint_positions
        pose = self.kinematics.fk(q0, self.ee_link)
        self._ik.solve(pose, self.ee_link, seed_q=q0)
        step = np.where(q0 < self.upper_limits - 0.1, 0.05, -0.05)
        if not self.checker.in_collision(q0) and not self.checker.in_collision(q0 + step):
            self.plan_joints(q0, q0 + step)

    def ik_batch(self, poses_xyzw: Sequence[Sequence[float]]) -> list[list[float] | None]:
        """Joint angles for each [x, y, z, qx, qy, qz, qw] (collision-free); None where it fails."""
        out: list[list[float] | None] = []
        for pose in np.atleast_2d(np.asarray(poses_xyzw, dtype=float)):
            res = self._ik.solve(
                Pose.from_xyz_xyzw(pose), self.ee_link, seed_q=self.default_joint_positions,
                validity_fn=lambda Q: ~self.checker.in_collision_batch(np.atleast_2d(Q)),
            )
            out.append(res.q.tolist() if res.success else None)
        return out

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
        start = np.asarray(start_joint_angles, dtype=float)
        if (goal_end_effector_pose is None) == (goal_joint_angles is None):
            raise InvalidInputError("give exactly one of goal_end_effector_pose or goal_joint_angles")
        if goal_joint_angles is not None:
            result = self.plan_joints(start, np.asarray(goal_joint_angles, dtype=float))
        else:
            goal = Pose.from_xyz_xyzw(goal_end_effector_pose)
            if self._hold_vec_weight is not None and np.any(self._hold_vec_weight > 0):
                goal = self._constrained_goal(start, goal)
                if goal is None:
                    return None
                result = self.plan_pose(start, goal, linear=True)
            else:
                result = self.plan_pose(start, goal)
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
        now = self.kinematics.fk(start, self.ee_link)
        if np.any(w[:3] > 0):
            goal = Pose(goal.position, now.quaternion)
        delta = now.inverse() @ goal  # goal expressed in the start's end-effector frame
        held = np.flatnonzero(w[3:] > 0)
        if held.size and np.any(np.abs(delta.position[held]) > 1e-4):
            logger.warning("motion_generate: the goal moves held axes %s of the end-effector frame", held.tolist())
            return None
        return goal

    def update_obstacle_from_world(self, world, robot_prim_path: str, ignore_prim_paths: Sequence[str] = ()) -> None:
        """Read the simulated World's collision objects into the planner (robot base frame).

        Objects whose name or prim path starts with an entry of `ignore_prim_paths` are left
        out, and so is the robot at `robot_prim_path`.
        """
        robot = _find_robot(world, robot_prim_path)
        self.update_world_from_sim(world, robot, ignore=list(ignore_prim_paths))

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
    scene = world.scene
    objects = [scene.get_object(name) for name in scene.get_object_names()]
    for obj in objects:
        if getattr(obj, "prim_path", None) == prim_path:
            return obj
    paths = sorted(str(getattr(o, "prim_path", "?")) for o in objects)
    raise InvalidInputError(f"no robot with prim path '{prim_path}' in the world's scene; prim paths: {paths}")
