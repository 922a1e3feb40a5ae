"""Grasp planning: `plan_grasp` on seeded pick problems, every stage checked independently.

    python benchmarks/grasp.py [--problems 200] [--seed 0] [--write-md]

Problem i (seeded by (seed, i)): a table (top at z = 0, 0.3-0.7 m in front of the robot),
3-8 boxes and cylinders on it, and the object to pick at a random position and yaw among
them: a cube (edge 4-6 cm) or an upright cylinder (radius 2-3 cm, height 6-10 cm). Grasp
candidates (a batched Pose of `panda_hand_tcp`): for a cube, top grasps at its 4 symmetric
yaws x 4 heights and side grasps at its 4 faces x 2 finger orientations (24); for a
cylinder, top grasps at 16 yaws and side grasps from 16 directions (32). The start is the
ready configuration with 0.1 rad of noise.

A problem counts as having a feasible candidate when some candidate's grasp and pre-grasp
poses both have a collision-free IK solution (the fingers allowed to touch the object;
independently searched with `IKSolver` from 50 random starts); the success rate is over
those. Each stage of a returned plan is checked by the independent verifier (exact meshes,
limits): the free motion against the whole world, the approach against the world without
the object (the fingers touch it; manip's own certificate covers the other links against
it), the lift against the world without the object (it is carried). Planning time is the
whole `plan_grasp` call (candidate ranking, IK, the three stages), wall and CPU.
`--write-md` replaces the "## Grasp planning" section of BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import cpu_model, replace_section  # noqa: E402
from manip import MotionGenerator, Pose  # noqa: E402
from manip import quaternion as quat  # noqa: E402
from manip.benchmarking.verify import default_verifier  # noqa: E402

TCP = "panda_hand_tcp"
DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # the hand pointing down (w, x, y, z)


def _yaw(a: float) -> np.ndarray:
    return quat.from_axis_angle([0.0, 0.0, 1.0], a)


def make_problem(seed: int, i: int) -> tuple[dict, str, Pose, np.ndarray]:
    """(world (cuRobo dict), object kind, grasp candidates, start (7,)) of problem i."""
    rng = np.random.default_rng([seed, i, 2029])
    x0, depth, width = rng.uniform(0.3, 0.4), rng.uniform(0.35, 0.5), rng.uniform(0.8, 1.2)
    world: dict = {"cuboid": {"table": {"dims": [depth, width, 0.04], "pose": [x0 + depth / 2, 0, -0.02, 1, 0, 0, 0]}},
                   "cylinder": {}}
    kind = "cube" if rng.random() < 0.5 else "cylinder"
    placed: list[tuple[np.ndarray, float]] = []

    def free_spot(radius: float) -> np.ndarray:
        for _ in range(200):
            p = np.array([rng.uniform(x0 + 0.08, x0 + depth - 0.08), rng.uniform(-width / 2 + 0.1, width / 2 - 0.1)])
            if all(np.linalg.norm(p - q) > radius + r + 0.02 for q, r in placed):
                placed.append((p, radius))
                return p
        return None

    yaw = rng.uniform(-np.pi, np.pi)
    if kind == "cube":
        e = rng.uniform(0.04, 0.06)
        c = np.append(free_spot(e * 0.8 + 0.06), e / 2)
        world["cuboid"]["object"] = {"dims": [e, e, e], "pose": [*c, *_yaw(yaw)]}
        tops = [Pose(c + [0, 0, h], quat.multiply(_yaw(yaw + k * np.pi / 2), DOWN))
                for k in range(4) for h in (0.0, 0.005, 0.01, 0.015)]
        sides = []
        for k in range(4):
            a = yaw + k * np.pi / 2
            for roll in (0.0, np.pi):
                sides.append(_side(c, a, roll))
        grasps = Pose.stack(tops + sides)
    else:
        r, h = rng.uniform(0.02, 0.03), rng.uniform(0.06, 0.1)
        c = np.append(free_spot(r + 0.06), h / 2)
        world["cylinder"]["object"] = {"radius": r, "height": h, "pose": [*c, 1, 0, 0, 0]}
        tops = [Pose(c + [0, 0, h / 2 - 0.02], quat.multiply(_yaw(a), DOWN)) for a in np.arange(16) * np.pi / 8]
        sides = [_side(c, a, 0.0) for a in np.arange(16) * np.pi / 8]
        grasps = Pose.stack(tops + sides)
    for k in range(int(rng.integers(3, 9))):
        size = rng.uniform(0.03, 0.06)
        p = free_spot(size + 0.01)
        if p is None:  # the table is full
            break
        hh = rng.uniform(0.05, 0.25)
        if rng.random() < 0.5:
            world["cuboid"][f"clutter{k}"] = {"dims": [2 * size, rng.uniform(0.04, 0.1), hh],
                                              "pose": [*p, hh / 2, *_yaw(rng.uniform(-np.pi, np.pi))]}
        else:
            world["cylinder"][f"clutter{k}"] = {"radius": size, "height": hh, "pose": [*p, hh / 2, 1, 0, 0, 0]}
    ready = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    return world, kind, grasps, ready + rng.normal(0.0, 0.1, 7)


def _side(c: np.ndarray, azimuth: float, roll: float) -> Pose:
    """A side grasp: the hand's z horizontal, towards the object's axis from `azimuth`, its y
    (the fingers' closing direction) horizontal; `roll` turns it about z."""
    z = -np.array([np.cos(azimuth), np.sin(azimuth), 0.0])
    y = np.array([-z[1], z[0], 0.0])
    x = np.cross(y, z)
    R = np.stack([x, y, z], axis=1) @ quat.to_matrix(quat.from_axis_angle([0, 0, 1], roll))
    return Pose(c.copy(), quat.from_matrix(R))


def has_feasible_candidate(mg: MotionGenerator, grasps: Pose, start: np.ndarray) -> bool:
    """Some candidate's grasp (fingers may touch the object) and pre-grasp (0.1 m back) poses
    have collision-free IK solutions (50 random starts each)."""
    touch = mg.checker.snapshot().allowing([(f, "object") for f in ("panda_leftfinger", "panda_rightfinger")])
    solver = mg.ik_solver
    for g in grasps:
        r = solver.solve(g, TCP, seed_q=start, validity_fn=lambda Q: ~touch.in_collision_batch(np.atleast_2d(Q)),
                         seed=1)
        if not r.success:
            continue
        pre = Pose(g.position - 0.10 * g.rotation[:, 2], g.quaternion)
        if solver.solve(pre, TCP, seed_q=r.q, validity_fn=lambda Q: ~mg.checker.in_collision_batch(np.atleast_2d(Q)),
                        seed=1).success:
            return True
    return False


def run(args) -> list[dict]:
    mg = MotionGenerator("franka")
    verifier = default_verifier()
    rows = []
    for i in range(args.problems):
        world, kind, grasps, start = make_problem(args.seed, i)
        mg.update_world(world)
        if mg.check_collision(start):
            start = mg.default_joint_positions
        c0, t0 = time.process_time(), time.perf_counter()
        plan = mg.plan_grasp(start, grasps, "object", link=TCP, seed=args.seed + i)
        row = {"i": i, "kind": kind, "n": len(grasps), "wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
               "ok": bool(plan.success), "status": plan.status.name, "message": plan.message}
        row["feasible"] = plan.success or has_feasible_candidate(mg, grasps, start)
        if plan.success:
            without = {k: {n: v for n, v in d.items() if n != "object"} for k, d in world.items()}
            reasons = []
            for name, seg, w in zip(plan.stages, plan.segments, (world, without, without)):
                tr = seg.trajectory
                v = verifier.verify_trajectory(w, tr.times, tr.positions, tr.velocities, tr.accelerations,
                                               start_q=tr.positions[0], goal_q=tr.positions[-1])
                reasons += [f"{name}: {r}" for r in v.reasons]
            row["valid"], row["reasons"] = not reasons, reasons
            row["motion"] = plan.trajectory.duration
        rows.append(row)
        if not args.quiet:
            print(f"{i:4d} {kind:<8} {len(grasps):2d} candidates: {plan.status.name:<16} {row['wall'] * 1e3:7.1f} ms"
                  + ("" if plan.success else f" (feasible: {row['feasible']}) {plan.message[:160]}")
                  + ("" if row.get("valid", True) else f" INVALID {row['reasons'][:2]}"), flush=True)
    return rows


def summary(rows: list[dict]) -> str:
    feas = [r for r in rows if r["feasible"]]
    ok = [r for r in feas if r["ok"]]
    wall = np.array([r["wall"] for r in rows if r["ok"]])
    cpu = np.array([r["cpu"] for r in rows if r["ok"]])
    invalid = [r for r in rows if r["ok"] and not r["valid"]]
    motion = np.array([r["motion"] for r in rows if r["ok"]])
    per = ", ".join(f"{k} {sum(r['ok'] for r in feas if r['kind'] == k)}/{sum(1 for r in feas if r['kind'] == k)}"
                    for k in ("cube", "cylinder"))
    return ("| problems | with a feasible candidate | solved (of those) | invalid | planning wall median / p98 [ms] "
            "| CPU median / p98 [ms] | motion time median [s] |\n|---|---|---|---|---|---|---|\n"
            f"| {len(rows)} | {len(feas)} | {len(ok)} ({100 * len(ok) / max(len(feas), 1):.1f} %; {per}) | "
            f"{len(invalid)} | {np.median(wall) * 1e3:.0f} / {np.percentile(wall, 98) * 1e3:.0f} | "
            f"{np.median(cpu) * 1e3:.0f} / {np.percentile(cpu, 98) * 1e3:.0f} | {np.median(motion):.2f} |\n\n"
            "Failures among the feasible: "
            + ("; ".join(f"{r['i']} ({r['kind']}): {r['status']}: {r['message'][:200]}" for r in feas if not r["ok"])
               or "none") + ".")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--problems", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quiet", action="store_true")
    parser.add_argument("--write-md", action="store_true", help="replace the section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    load0, t0 = os.getloadavg()[0], time.perf_counter()
    rows = run(args)
    text = summary(rows)
    machine = (f"{cpu_model()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
               f"{dt.datetime.now().strftime('%Y-%m-%d %H:%M')}; load average {load0:.2f} at the start, "
               f"{os.getloadavg()[0]:.2f} at the end; {time.perf_counter() - t0:.0f} s in all")
    print(text)
    print(machine)
    if args.write_md:
        cmd = "python benchmarks/grasp.py " + " ".join(argv if argv is not None else sys.argv[1:])
        replace_section(ROOT / "BENCHMARKS.md", "## Grasp planning",
                        f"## Grasp planning\n\n`{cmd.strip()}` ({machine}).\n\n{text}\n")
    feas = [r for r in rows if r["feasible"]]
    bad = sum(1 for r in rows if r["ok"] and not r["valid"])
    return 0 if feas and sum(r["ok"] for r in feas) >= 0.99 * len(feas) and bad == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
