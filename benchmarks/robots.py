"""Per-robot figures: FK agreement (Pinocchio vs MuJoCo), IK on reachable poses, planning on
seeded scenes scaled to the robot, and simulated tracking of a planned trajectory.

Usage::

    .venv/bin/python benchmarks/robots.py                       # full counts (1000 IK poses, 100 scenes/kind)
    .venv/bin/python benchmarks/robots.py --ik 200 --scenes 10 --robots ur5 xarm7
"""

from __future__ import annotations

import argparse
import platform
import time

import mujoco
import numpy as np

from manip.benchmarking.scenes import make_problems
from manip.benchmarking.verify import Verifier
from manip.motion_generator import MotionGenerator
from manip.pose import Pose
from manip.sim import World, create_new_stage
from manip.sim.articulations.articulation import Robot
from manip.sim.playback import play_trajectory
from manip.sim.robots.robot import robot_model_path
from manip.sim.scenes.stage import add_reference_to_stage

ROBOTS = ["franka", "ur5", "ur10", "kinova", "xarm7"]


def fk_error(mg: MotionGenerator, n: int = 200) -> float:
    c = mg.config
    m = mujoco.MjModel.from_xml_path(str(c.mjcf_path))
    d = mujoco.MjData(m)
    adr = [m.joint(j).qposadr[0] for j in c.arm_joints]
    worst = 0.0
    for q in np.random.default_rng(0).uniform(c.lower_limits, c.upper_limits, size=(n, c.dof)):
        d.qpos[adr] = q
        mujoco.mj_kinematics(m, d)
        worst = max(worst, float(np.linalg.norm(d.site(c.ee_link).xpos - mg.fk(q).position)))
    return worst


def ik_figures(mg: MotionGenerator, n: int) -> tuple[float, int]:
    c = mg.config
    rng = np.random.default_rng(1)
    solved = wrong = k = 0
    while k < n:
        q = rng.uniform(c.lower_limits, c.upper_limits)
        if mg.check_collision(q):
            continue
        k += 1
        goal = mg.fk(q)
        r = mg.ik(goal)
        if r.success:
            solved += 1
            wrong += np.linalg.norm(mg.fk(r.q).position - goal.position) > 1e-3
    return solved / n, wrong


STAGES = ("ik", "plan", "optimize", "restarts", "timing", "validate", "trajopt")


def planning_figures(mg: MotionGenerator, n: int) -> dict:
    """Plans of `n` seeded problems per scene kind: counts, median time, and per stage
    (`PlanResult.timings`) the median and mean [ms] over all problems (0 for a stage a plan
    skipped), the median trajectory duration [s] and samples."""
    verifier = Verifier(mg.config)
    times, solved, invalid, total = [], 0, 0, 0
    stages: dict[str, list[float]] = {s: [] for s in STAGES}
    durations, samples = [], []
    for kind in ("table", "shelf", "clutter"):
        for p in make_problems(kind, n, seed=0, robot=mg.config.name, verifier=verifier):
            mg.update_world(p.world)
            t0 = time.perf_counter()
            r = mg.plan_joints(p.start, p.goal)
            times.append(time.perf_counter() - t0)
            for s in STAGES:
                stages[s].append(r.timings.get(s, 0.0))
            total += 1
            if r.success:
                solved += 1
                t = r.trajectory
                durations.append(float(t.times[-1]))
                samples.append(len(t.times))
                invalid += not verifier.verify_trajectory(p, t.times, t.positions, t.velocities).valid
    mg.update_world({})
    return {"total": total, "solved": solved, "invalid": invalid, "median_ms": 1e3 * float(np.median(times)),
            "stage_median_ms": {s: 1e3 * float(np.median(v)) for s, v in stages.items()},
            "stage_mean_ms": {s: 1e3 * float(np.mean(v)) for s, v in stages.items()},
            "duration_s": float(np.median(durations)) if durations else float("nan"),
            "samples": float(np.median(samples)) if samples else float("nan")}


def tracking_error(mg: MotionGenerator, n: int = 10) -> float:
    """Largest tool distance [m] between the planned and the simulated arm over `n` planned
    pose-goal motions from the retract configuration (targets 10-25 cm away), played in
    manip.sim with position + velocity targets every physics step (1/60 s)."""
    c = mg.config
    rng = np.random.default_rng(5)
    worst = 0.0
    for _ in range(n):
        World.clear_instance()
        create_new_stage()
        start = c.default_joint_positions
        home = mg.fk(start)
        step = rng.normal(size=3)
        target = Pose(home.position + rng.uniform(0.1, 0.25) * step / np.linalg.norm(step), home.quaternion)
        plan = mg.plan_pose(start, target)
        if not plan.success:
            continue
        world = World()
        add_reference_to_stage(robot_model_path(c.name), "/World/arm")
        robot = world.scene.add(Robot("/World/arm", name="arm"))
        world.reset()
        robot.set_joint_positions(start, plan.trajectory.joint_indices_for(robot))
        played = play_trajectory(world, robot, plan.trajectory)
        tool_error = np.linalg.norm(mg.fk(played).position - mg.fk(plan.trajectory.positions).position, axis=-1)
        worst = max(worst, float(tool_error.max()))
    World.clear_instance()
    create_new_stage()
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="*", default=ROBOTS)
    ap.add_argument("--ik", type=int, default=1000, help="IK poses per robot")
    ap.add_argument("--scenes", type=int, default=100, help="problems per scene kind per robot")
    args = ap.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| robot | FK max err (m) | IK solved | IK wrong | plans solved | invalid | median plan (ms) | sim tracking max (m) |")
    print("|---|---|---|---|---|---|---|---|")
    bad = 0
    breakdown = []
    for name in args.robots:
        mg = MotionGenerator(name, seed=0)
        fk = fk_error(mg)
        rate, wrong = ik_figures(mg, args.ik)
        pl = planning_figures(mg, args.scenes)
        track = tracking_error(mg)
        print(f"| {name} | {fk:.1e} | {100 * rate:.1f} % of {args.ik} | {wrong} | {pl['solved']}/{pl['total']} | "
              f"{pl['invalid']} | {pl['median_ms']:.0f} | {track:.4f} |", flush=True)
        bad += (fk > 1e-6 or rate < 0.995 or wrong > 0 or pl["invalid"] > 0 or pl["solved"] < 0.99 * pl["total"]
                or track > 0.02)
        breakdown.append((name, pl))
    print("\nPlanning stages, median / mean [ms] over the problems (0 when a plan skips the stage):\n")
    print("| robot | " + " | ".join(STAGES) + " | total | trajectory duration (s) | samples |")
    print("|---|" + "---|" * (len(STAGES) + 3))
    for name, pl in breakdown:
        cells = [f"{pl['stage_median_ms'][s]:.0f} / {pl['stage_mean_ms'][s]:.0f}" for s in STAGES]
        print(f"| {name} | " + " | ".join(cells) + f" | {pl['median_ms']:.0f} | {pl['duration_s']:.2f} | "
              f"{pl['samples']:.0f} |")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
