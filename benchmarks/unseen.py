"""Problems nobody tuned for: random worlds for the five arms, random task calls, bad inputs.

    python benchmarks/unseen.py arms --robots franka ur5 --n 40 --seed 1000 --json /tmp/a.json
    python benchmarks/unseen.py tasks --n 30 --seed 2000 --json /tmp/t.json
    python benchmarks/unseen.py bad
    python benchmarks/unseen.py cost                                  # CPU of checks and 56 MBM plans
    python benchmarks/unseen.py turns --n 20 --seed 5400              # pose goals of the +-2 pi arms
    python benchmarks/unseen.py table /tmp/a.json /tmp/t.json        # tabulate saved runs

`arms`: problem i of a robot (seeded by (seed, robot index, i)) is a random world of 5-25
obstacles (cuboids, spheres, capsules, cylinders, one or two triangle meshes; sizes 2-30 cm,
random poses within the arm's reach, a table top below the workspace), a start and a goal
sampled uniformly within the joint limits and free for both manip's checker and the
independent verifier, and a goal that is the joint goal (even i) or the end-effector pose at it
(odd i). Every returned trajectory is checked by the independent verifier (exact meshes, every
`--resolution` rad, position/velocity/acceleration/jerk limits, start, goal within 1 mm /
0.01 rad, at rest) and by manip's continuous certificate (`CollisionChecker.certify_path`).
A failure is replanned with another seed and a 20 s budget to tell hard from infeasible.

`tasks`: plan_grasp of a random box (random dims and yaw) among random clutter, then plan_place
of it with an upright `OrientationConstraint`, then `dual_franka` plan_poses among clutter.

`bad`: inputs users get wrong; each must raise a manip error or give a failure status.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from manip import MotionGenerator, Pose
from manip.benchmarking.verify import Verifier
from manip.benchmarking.verify_inside import InsideTest

ROBOTS = ["franka", "ur5", "ur10", "kinova", "xarm7"]
MESH_DIR = Path(tempfile.gettempdir()) / "manip_unseen_meshes"


def _meshes() -> list[str]:
    """Two mesh files (an icosphere and a random convex hull), written once."""
    import trimesh

    MESH_DIR.mkdir(parents=True, exist_ok=True)
    out = []
    for name, make in (("ico.stl", lambda: trimesh.creation.icosphere(1, 0.5)),
                       ("hull.stl", lambda: trimesh.convex.convex_hull(
                           np.random.default_rng(7).uniform(-0.5, 0.5, (30, 3))))):
        p = MESH_DIR / name
        if not p.exists():
            make().export(p)
        out.append(str(p))
    return out


def _random_quat(rng) -> list[float]:
    q = rng.normal(size=4)
    return list(q / np.linalg.norm(q))


def random_world(rng, reach: float, dense: bool = False) -> dict:
    """A table top below the workspace and 5-25 random obstacles within `reach` [m], all around
    the robot; `dense`: 15-25 of them in front of it (azimuth within 90 deg, 0.25-0.8 reach)."""
    w: dict = {"cuboid": {}, "sphere": {}, "capsule": {}, "cylinder": {}, "mesh": {}}
    top = rng.uniform(-0.25, 0.0) * reach
    w["cuboid"]["table"] = {"dims": [1.2 * reach, 2.0 * reach, 0.04],
                            "pose": [0.55 * reach, 0, top - 0.02, 1, 0, 0, 0]}
    meshes = _meshes()
    n_mesh = int(rng.integers(1, 3))
    for k in range(int(rng.integers(15 if dense else 5, 26))):
        r = rng.uniform(0.25, 0.8 if dense else 1.0) * reach
        a = rng.uniform(-np.pi / 2, np.pi / 2) if dense else rng.uniform(-np.pi, np.pi)
        c = [r * math.cos(a), r * math.sin(a), rng.uniform(top, (0.7 if dense else 0.9) * reach)]
        s = rng.uniform(0.02, 0.30, 3)
        kind = "mesh" if k < n_mesh else rng.choice(["cuboid", "sphere", "capsule", "cylinder"])
        pose = c + _random_quat(rng)
        if kind == "cuboid":
            w["cuboid"][f"box{k}"] = {"dims": list(s), "pose": pose}
        elif kind == "sphere":
            w["sphere"][f"ball{k}"] = {"radius": s[0] / 2, "position": c}
        elif kind == "capsule":
            d = np.array(_random_quat(rng)[:3])
            d = d / np.linalg.norm(d) * s[1] / 2
            w["capsule"][f"cap{k}"] = {"radius": s[0] / 2, "base": list(np.array(c) - d),
                                       "tip": list(np.array(c) + d), "pose": [0, 0, 0, 1, 0, 0, 0]}
        elif kind == "cylinder":
            w["cylinder"][f"cyl{k}"] = {"radius": s[0] / 2, "height": s[1], "pose": pose}
        else:
            w["mesh"][f"mesh{k}"] = {"file_path": meshes[k % 2], "pose": pose, "scale": list(s)}
    return {k: v for k, v in w.items() if v}


class SupportVerifier(Verifier):
    """The independent verifier with manip's documented support convention (README "Simulation"):
    an obstacle wholly below the base's z = 0 (top within 1 mm) is not checked against the
    robot's geometries fixed to the base (no motion changes that contact); every moving
    geometry is checked against it."""

    def _build_world(self, world: dict):
        import pinocchio as pin

        from manip.benchmarking.verify import world_geometries

        wm = super()._build_world(world)
        fixed = {i for i, g in enumerate(wm.gm.geometryObjects[: self._n_robot]) if g.parentJoint == 0}
        below = set()
        for k, (name, shape, M) in enumerate(world_geometries(world)):
            shape.computeLocalAABB()
            corners = np.array([[x, y, z] for x in (shape.aabb_local.min_[0], shape.aabb_local.max_[0])
                                for y in (shape.aabb_local.min_[1], shape.aabb_local.max_[1])
                                for z in (shape.aabb_local.min_[2], shape.aabb_local.max_[2])])
            if (corners @ M.rotation.T + M.translation)[:, 2].max() <= 1e-3:
                below.add(self._n_robot + k)
        if not fixed or not below:
            return wm
        keep = [(p.first, p.second) for p in wm.gm.collisionPairs if not (p.first in fixed and p.second in below)]
        wm.gm.removeAllCollisionPairs()
        for a, b in keep:
            wm.gm.addCollisionPair(pin.CollisionPair(a, b))
        wm.gd = wm.gm.createData()
        wm.bp = pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(self.model, wm.gm, wm.gd)
        wm.inside = InsideTest(wm.gm, keep, surfaces=wm.surfaces)
        return wm


def free_configuration(mg, verifier, world, rng, tries: int = 400):
    """A configuration uniform in the limits, free for manip and the verifier (None if none found).
    Also counts disagreements: free for manip but colliding for the verifier."""
    lo, hi = mg.lower_limits, mg.upper_limits
    for _ in range(tries):
        q = rng.uniform(lo, hi)
        manip_free = not mg.check_collision(q)
        ver_free = verifier.in_collision(q, world) is None
        if manip_free and not ver_free:
            return ("DISAGREE", q)
        if manip_free and ver_free:
            return q
    return None


def random_options(rng) -> dict:
    """Per-call options a user may pass: velocity and acceleration scales in [0.2, 1], the smooth
    or time-optimal optimiser, a sample period of 1/60, 0.01 or 0.05 s."""
    return {"velocity_scale": float(rng.uniform(0.2, 1.0)), "acceleration_scale": float(rng.uniform(0.2, 1.0)),
            "smoothness": str(rng.choice(["time_optimal", "smooth"])), "dt": float(rng.choice([1 / 60, 0.01, 0.05]))}


def check_result(mg, verifier, world, r, start, goal, resolution: float, options: dict | None = None) -> dict:
    """The independent checks of one result, against the limits the call's `options` scale; a dict."""
    from manip.planning import PlanOptions
    out = {"status": r.status.name, "message": (r.message or "")[:300], "success": bool(r.success)}
    if not r.success:
        return out
    t = r.trajectory
    kw = {"goal_pose": goal} if isinstance(goal, Pose) else {"goal_q": goal}
    o = PlanOptions().updated(options or {})
    c = mg.config
    v = verifier.verify_trajectory(world, t.times, t.positions, t.velocities, t.accelerations, t.jerks,
                                   start_q=start, check_jerk=True, velocity_limits=c.velocity_limits * o.velocity_scale,
                                   acceleration_limits=c.acceleration_limits * o.acceleration_scale,
                                   jerk_limits=c.jerk_limits * o.jerk_scale, **kw)
    cert = mg.checker.certify_path(t.positions)
    out.update(valid=bool(v.valid), reasons=list(v.reasons)[:3], certified=bool(cert.certified),
               cert_reason=cert.reason, duration=float(t.duration), source=r.source,
               goal_pos_err=float(v.goal_position_error), goal_rot_err=float(v.goal_rotation_error),
               vel=float(v.max_velocity_ratio), acc=float(v.max_acceleration_ratio), jerk=float(v.max_jerk_ratio))
    return out


def run_arms(args) -> list[dict]:
    rows = []
    for ri, robot in enumerate(args.robots):
        mg = MotionGenerator(robot)
        verifier = SupportVerifier(mg.config, resolution=args.resolution)
        reach = _reach(mg)
        for i in range(args.start, args.start + args.n):
            rng = np.random.default_rng([args.seed, ROBOTS.index(robot), i])
            row = {"part": ("arms, dense" if args.dense else "arms") + (", random options" if args.random_options else ""),
                   "robot": robot, "i": i, "goal": "joint" if i % 2 == 0 else "pose"}
            for _attempt in range(20):
                world = random_world(rng, reach, args.dense)
                mg.update_world(world)
                a = free_configuration(mg, verifier, world, rng)
                b = free_configuration(mg, verifier, world, rng) if a is not None else None
                if a is not None and b is not None:
                    break
            else:
                row["status"] = "NO_PROBLEM"
                rows.append(row)
                continue
            row["n_obstacles"] = sum(len(v) for v in world.values())
            if isinstance(a, tuple) or isinstance(b, tuple):
                row.update(status="CHECKER_DISAGREES", q=(a if isinstance(a, tuple) else b)[1].tolist())
                rows.append(row)
                _print(row)
                continue
            goal = b if row["goal"] == "joint" else mg.fk(b)
            opts = random_options(np.random.default_rng([args.seed, ROBOTS.index(robot), i, 5])) if args.random_options else {}
            row["options"] = opts
            t0 = time.perf_counter()
            try:
                r = mg.plan_joints(a, goal, **opts) if row["goal"] == "joint" else mg.plan_pose(a, goal, **opts)
            except Exception as exc:  # noqa: BLE001 - a finding, recorded
                row.update(status="EXCEPTION", message=f"{type(exc).__name__}: {exc}"[:300],
                           trace=traceback.format_exc()[-800:])
                rows.append(row)
                _print(row)
                continue
            row["plan_s"] = time.perf_counter() - t0
            row.update(check_result(mg, verifier, world, r, a, goal, args.resolution, opts))
            if not r.success and args.retry:
                again = dict(opts, seed=1, time_budget=20.0, search_iterations=None)
                r2 = mg.plan_joints(a, goal, **again) if row["goal"] == "joint" else mg.plan_pose(a, goal, **again)
                row["retry_status"] = r2.status.name
            row["start"], row["goal_q"] = a.tolist(), b.tolist()
            rows.append(row)
            _print(row)
    return rows


def _reach(mg) -> float:
    Q = np.random.default_rng(0).uniform(mg.lower_limits, mg.upper_limits, (300, mg.robot_dof))
    return float(max(np.linalg.norm(mg.fk(q).position) for q in Q))


def _print(row: dict) -> None:
    keep = ("robot", "i", "goal", "status", "valid", "certified", "plan_s", "retry_status", "message", "reasons")
    print({k: (round(v, 3) if isinstance(v, float) else v) for k, v in row.items() if k in keep}, flush=True)


def table(rows: list[dict]) -> str:
    """A markdown table per (part, robot, goal): problems, success, invalid, statuses, time."""
    groups: dict = {}
    for r in rows:
        groups.setdefault((r["part"], r.get("robot", ""), r.get("goal", "")), []).append(r)
    lines = [("| part | robot | goal | problems | success | invalid (verifier) | uncertified | "
              "failures by status (retry with seed 1, 20 s) | plan time median / max [s] |"),
             "|---|---|---|---|---|---|---|---|---|"]
    for (part, robot, goal), rs in sorted(groups.items()):
        ok = [r for r in rs if r.get("success")]
        bad = [r for r in ok if not r.get("valid", True)]
        unc = [r for r in ok if not r.get("certified", True)]
        fails = Counter(f"{r['status']}" + (f" ({r['retry_status']})" if "retry_status" in r else "")
                        for r in rs if not r.get("success"))
        ts = [r["plan_s"] for r in rs if "plan_s" in r]
        tt = f"{np.median(ts):.3f} / {max(ts):.2f}" if ts else "-"
        lines.append(f"| {part} | {robot} | {goal} | {len(rs)} | {len(ok)} | {len(bad)} | {len(unc)} | "
                     f"{', '.join(f'{k}: {v}' for k, v in sorted(fails.items())) or '-'} | {tt} |")
    return "\n".join(lines)


def cost() -> None:
    """What the checks cost: 20,000 uniformly random configurations per arm (empty world) through
    `in_collision_batch`, then 3000 through `check_collision` (CPU s); then 56 MotionBenchMaker
    plans (4 problems of each scene, joint and pose goals): their CPU and the sum of their
    durations (equal sums: the same motions). Run it with each tree on PYTHONPATH to compare."""
    import manip
    from manip.benchmarking.mbm_problems import MBM_SCENES, goal_pose, load_mbm_problems
    from manip.benchmarking.verify import check_problem

    print(manip.__file__)
    for robot in ROBOTS:
        mg = MotionGenerator(robot)
        Q = np.random.default_rng(0).uniform(mg.lower_limits, mg.upper_limits, (20000, mg.robot_dof))
        mg.checker.in_collision_batch(Q[:50])
        t = time.process_time()
        hits = mg.checker.in_collision_batch(Q)
        batch = time.process_time() - t
        t = time.process_time()
        for q in Q[:3000]:
            mg.check_collision(q)
        print(f"{robot}: {int(hits.sum())} of 20000 colliding, batch {batch:.3f} s, 3000 single {time.process_time() - t:.3f} s")
    mg = MotionGenerator("franka")
    cpu, total = [], 0.0
    for scene in MBM_SCENES:
        for p in [p for p in load_mbm_problems(scenes=[scene]) if check_problem(p).valid][:4]:
            mg.update_world(p.world)
            for goal in (p.goal, goal_pose(p)):
                t = time.process_time()
                r = mg.plan_joints(p.start, goal) if isinstance(goal, np.ndarray) else mg.plan_pose(p.start, goal)
                cpu.append(time.process_time() - t)
                total += r.trajectory.duration if r.success else float("nan")
    print(f"{len(cpu)} MBM plans: CPU {sum(cpu):.2f} s, median {1e3 * np.median(cpu):.1f} ms, durations sum {total:.4f} s")


def turns(args) -> None:
    """Pose goals of the arms whose joints turn +-2 pi, in `arms`' random worlds (problem i seeded as
    there, goal the pose of a second free configuration): per robot, solved, the plans' CPU (median,
    sum), the motions' durations (sum) and how many turn a joint more than pi where the other way is
    within the limits. Run it with each tree on PYTHONPATH to compare."""
    import manip

    print(manip.__file__)
    for robot in args.robots:
        mg = MotionGenerator(robot)
        reach = _reach(mg)
        lo, hi = mg.lower_limits, mg.upper_limits
        cpu, dur, far, ok = [], 0.0, 0, 0
        for i in range(args.n):
            rng = np.random.default_rng([args.seed, ROBOTS.index(robot), i])
            mg.update_world(random_world(rng, reach, args.dense))
            Q = [q for q in rng.uniform(lo, hi, (400, len(lo))) if not mg.check_collision(q)][:2]
            if len(Q) < 2:
                continue
            t = time.process_time()
            r = mg.plan_pose(Q[0], mg.fk(Q[1]))
            cpu.append(time.process_time() - t)
            if r.success:
                ok += 1
                dur += r.trajectory.duration
                d = r.trajectory.positions[-1] - Q[0]
                other = r.trajectory.positions[-1] - 2 * np.pi * np.sign(d)
                far += bool(np.any((np.abs(d) > np.pi) & (other >= lo) & (other <= hi)))
        print(f"{robot}: {ok}/{len(cpu)} solved, CPU median {1e3 * np.median(cpu):.1f} ms, sum {sum(cpu):.2f} s, "
              f"durations sum {dur:.2f} s, {far} turning a joint more than pi where less would do", flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("arms", help="random worlds, the five arms, joint and pose goals")
    a.add_argument("--robots", nargs="+", default=ROBOTS, choices=ROBOTS)
    a.add_argument("--n", type=int, default=40, help="problems per robot")
    a.add_argument("--start", type=int, default=0, help="first problem index (to run in chunks)")
    a.add_argument("--seed", type=int, default=1000)
    a.add_argument("--resolution", type=float, default=0.005, help="verifier's collision resolution [rad]")
    a.add_argument("--dense", action="store_true", help="15-25 obstacles in front of the robot")
    a.add_argument("--random-options", action="store_true",
                   help="random velocity/acceleration scales, smoothness and dt per problem (checked against the scaled limits)")
    a.add_argument("--no-retry", dest="retry", action="store_false", help="do not replan failures")
    a.add_argument("--json", help="write the rows here")
    k = sub.add_parser("tasks", help="plan_grasp / plan_place upright on random picks; two-arm robots")
    k.add_argument("--n", type=int, default=30)
    k.add_argument("--start", type=int, default=0)
    k.add_argument("--seed", type=int, default=2000)
    k.add_argument("--resolution", type=float, default=0.005)
    k.add_argument("--json")
    b = sub.add_parser("bad", help="inputs users get wrong: each must raise clearly or fail clearly")
    b.add_argument("--json")
    sub.add_parser("cost", help="the collision checks' and MBM plans' CPU (compare trees via PYTHONPATH)")
    u = sub.add_parser("turns", help="pose goals of the +-2 pi arms: CPU, durations, extra turns (compare trees)")
    u.add_argument("--robots", nargs="+", default=["ur5", "ur10", "kinova", "xarm7"], choices=ROBOTS)
    u.add_argument("--n", type=int, default=20)
    u.add_argument("--seed", type=int, default=5400)
    u.add_argument("--dense", action="store_true")
    t = sub.add_parser("table", help="tabulate saved runs")
    t.add_argument("files", nargs="+")
    args = ap.parse_args(argv)
    if args.cmd == "table":
        rows = [r for f in args.files for r in json.loads(Path(f).read_text())]
        print(table(rows))
        return 0
    if args.cmd == "cost":
        cost()
        return 0
    if args.cmd == "turns":
        turns(args)
        return 0
    if args.cmd == "bad":
        from benchmarks.unseen_bad import run_bad

        rows = run_bad(args)
        if args.json:
            Path(args.json).write_text(json.dumps(rows))
        return 0
    if args.cmd == "arms":
        rows = run_arms(args)
    else:
        from benchmarks.unseen_tasks import run_tasks

        rows = run_tasks(args)
    if args.json:
        Path(args.json).write_text(json.dumps(rows))
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
