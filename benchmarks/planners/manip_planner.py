"""manip's MotionGenerator behind the same interface as the peers (`benchmarks.peers`).

Set-up per problem (untimed, reported as `setup_time_s`): the problem's world is loaded with
`mg.update_world(WorldConfig.from_dict(problem.world))`. Timed (`plan_time_s`, wall clock
around one call): `plan_joints` or `plan_pose(..., link="panda_hand")`, i.e. IK, path,
optimisation, ruckig timing and manip's own validation.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from benchmarks.peers import PlannerOutput
from manip.benchmarking.mbm_problems import goal_pose


class ManipPlanner:
    """`manip.MotionGenerator` as a benchmark planner.

    Args:
        time_budget: planning budget per problem [s] (None: the MotionGenerator's default).
        robot: robot name or `RobotConfig` the MotionGenerator is built from (default
            "franka"); the benchmark's `--curobo-limits` passes a copy of the Franka config
            with cuRobo's acceleration and jerk limits.
        plan_options: keyword options given to every `plan_joints` / `plan_pose` call (e.g.
            `{"smoothness": "smooth"}`). The planner is warmed up with them when it is built
            (free space, around a box, a pose goal), so an option the MotionGenerator does
            not know fails here with its own error message (InvalidInputError), and the
            compiled kernels' first-use cost is never timed.
        **options: further keyword options of `MotionGenerator(...)`.
    """

    name = "manip"

    def __init__(self, time_budget: float | None = None, robot: Any = "franka",
                 plan_options: dict[str, Any] | None = None, **options: Any):
        try:
            from manip import MotionGenerator, WorldConfig
        except ImportError:  # the lead exports these from manip/__init__.py
            from manip.collision import WorldConfig
            from manip.motion_generator import MotionGenerator
        self._WorldConfig = WorldConfig
        if time_budget is not None:
            options["time_budget"] = time_budget
        self.mg = MotionGenerator(robot, **options)
        self.plan_options: dict[str, Any] = dict(plan_options or {})
        self._world: dict | None = None
        self._probe_plan_options()

    @property
    def config(self) -> Any:
        """The `RobotConfig` the planner plans with (its limits are the ones it obeys)."""
        return self.mg.config

    def _probe_plan_options(self) -> None:
        """Warm up and check `plan_options` (raises what the planner raises): a short free-space
        motion, then one around a box, so that every compiled kernel (numba: about 20 s in a
        fresh checkout) is loaded before anything is timed."""
        q0 = self.mg.default_joint_positions
        q1 = q0.copy()
        q1[0] += 0.2
        self.mg.update_world(self._WorldConfig.from_dict({}))
        self._world = None
        self.mg.plan_joints(q0, q1, **self.plan_options)
        wall = {"cuboid": {"wall": {"dims": [0.3, 0.04, 0.5], "pose": [0.5, 0.0, 0.25, 1, 0, 0, 0]}},
                "cylinder": {"can": {"radius": 0.03, "height": 0.1, "pose": [0.3, 0.4, 0.05, 1, 0, 0, 0]}}}
        self.mg.update_world(self._WorldConfig.from_dict(wall))
        left = np.array([0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])
        for seed in range(8):  # until the optimiser has run once (its kernels compile on first use)
            r = self.mg.plan_joints(left, left * np.array([-1, 1, 1, 1, 1, 1, 1]), seed=seed, **self.plan_options)
            if "trajopt" in r.timings or self.plan_options.get("trajopt") is False:
                break
        self.mg.plan_pose(q0, self.mg.fk(q0), **self.plan_options)

    def plan(self, problem: Any, goal_kind: str = "joint", seed: int = 0) -> PlannerOutput:
        """Plan `problem` to its joint goal ("joint") or its panda_hand pose goal ("pose")."""
        t0 = time.perf_counter()
        if self._world is not problem.world:
            self.mg.update_world(self._WorldConfig.from_dict(problem.world))
            self._world = problem.world
        setup = time.perf_counter() - t0
        start = np.asarray(problem.start, dtype=float)
        if goal_kind == "joint":
            t1 = time.perf_counter()
            r = self.mg.plan_joints(start, np.asarray(problem.goal, dtype=float), seed=seed, **self.plan_options)
        elif goal_kind == "pose":
            g = goal_pose(problem)  # FK, not part of planning
            t1 = time.perf_counter()
            r = self.mg.plan_pose(start, g, link="panda_hand", seed=seed, **self.plan_options)
        else:
            raise ValueError(f"goal_kind must be 'joint' or 'pose'; got {goal_kind!r}")
        plan_time = time.perf_counter() - t1
        tr = r.trajectory if r.success else None
        return PlannerOutput(
            success=bool(r.success),
            status=r.status.name,
            plan_time_s=plan_time,
            times=None if tr is None else np.asarray(tr.times),
            positions=None if tr is None else np.asarray(tr.positions),
            velocities=None if tr is None else np.asarray(tr.velocities),
            accelerations=None if tr is None else np.asarray(tr.accelerations),
            jerks=None if tr is None else np.asarray(tr.jerks),
            claims_jerk_limits=True,
            setup_time_s=setup,
            stage_times_s=dict(r.timings),
            goal_configuration=None if r.goal_q is None else np.asarray(r.goal_q),
            n_waypoints=0 if r.path is None else len(r.path),
        )
