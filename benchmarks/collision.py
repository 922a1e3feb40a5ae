"""Collision-checking speed: manip's CollisionChecker vs a plain Pinocchio/coal mesh check.

For each scene (a synthetic shelf, and one problem of each MotionBenchMaker scene when the
dataset is available) it measures, on the same configurations:

- `in_collision_batch` per configuration, batches of 100, on random configurations (a mix
  of free and colliding) and on free ones only (what a planner mostly checks);
- `in_collision` (one configuration per call);
- the baseline: `pinocchio.computeCollisions` over the URDF meshes with the SRDF pairs
  removed and the obstacles added, stopping at the first contact;
- `motion_valid` on 2 rad edges (L-inf) at 0.01 rad resolution, valid and invalid ones;
- agreement with the baseline (must be 100 %).

Usage:
    .venv/bin/python benchmarks/collision.py [--configs 1000] [--no-mbm]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import coal
import numpy as np
import pinocchio as pin

from manip import Kinematics, Pose, load_robot_config
from manip.collision import Capsule, CollisionChecker, Cuboid, Cylinder, Sphere, WorldConfig


def shelf_world() -> WorldConfig:
    """A bookshelf in front of the robot: 7 boxes."""
    rz = Pose([0, 0, 0], [np.cos(0.15), 0, 0, np.sin(0.15)])
    base = Pose([0.75, 0.05, 0.0]) @ rz
    boxes = [
        ("bottom", [0.35, 0.9, 0.02], [0, 0, 0.25]),
        ("middle", [0.35, 0.9, 0.02], [0, 0, 0.6]),
        ("top", [0.35, 0.9, 0.02], [0, 0, 0.95]),
        ("left", [0.35, 0.02, 1.0], [0, 0.45, 0.5]),
        ("right", [0.35, 0.02, 1.0], [0, -0.45, 0.5]),
        ("back", [0.02, 0.9, 1.0], [0.175, 0, 0.5]),
        ("floor", [2.0, 2.0, 0.02], [-0.6, 0, -0.02]),
    ]
    return WorldConfig([Cuboid(n, d, base @ Pose(p)) for n, d, p in boxes])


def baseline(config, kin: Kinematics, world: WorldConfig, padding: float = 0.0):
    """pinocchio.computeCollisions over meshes + obstacles (stop at first)."""
    gm = pin.buildGeomFromUrdf(kin.model, str(config.urdf_path), pin.COLLISION, package_dirs=list(config.package_dirs))
    gm.addAllCollisionPairs()
    pin.removeCollisionPairs(kin.model, gm, str(config.srdf_path))
    n_robot = len(gm.geometryObjects)
    for ob in world:
        if isinstance(ob, Cuboid):
            g = coal.Box(*ob.dims)
        elif isinstance(ob, Cylinder):
            g = coal.Cylinder(ob.radius, ob.height)
        elif isinstance(ob, Sphere):
            g = coal.Sphere(ob.radius)
        elif isinstance(ob, Capsule):
            g = coal.Capsule(ob.radius, ob.height)
        else:
            raise ValueError(f"baseline: unsupported {ob}")
        oid = gm.addGeometryObject(pin.GeometryObject(ob.name, 0, 0, pin.SE3(ob.pose.rotation, ob.pose.position), g))
        for r in range(n_robot):
            gm.addCollisionPair(pin.CollisionPair(r, oid))
    gd = pin.GeometryData(gm)
    for k, cp in enumerate(gm.collisionPairs):
        if cp.second >= n_robot:
            gd.collisionRequests[k].security_margin = padding
    model, data = kin.model, kin.model.createData()
    return lambda q: bool(pin.computeCollisions(model, data, gm, gd, q, True)), len(gm.collisionPairs)


def best_of(f, repeat: int = 3) -> float:
    """Smallest wall time [s] of `repeat` calls (the machine is shared: noise only adds)."""
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return best


def measure(name: str, config, kin: Kinematics, world: WorldConfig, n: int, rng: np.random.Generator) -> dict:
    t0 = time.perf_counter()
    cc = CollisionChecker(config, kin, world)
    t_build = time.perf_counter() - t0
    ref, n_pairs = baseline(config, kin, world)
    Q = rng.uniform(kin.lower, kin.upper, (n, 7))
    hit = cc.in_collision_batch(Q)
    expected = np.array([ref(q) for q in Q])
    free = Q[~hit]

    def batched(X: np.ndarray) -> None:
        for s in range(0, X.shape[0], 100):
            cc.in_collision_batch(X[s:s + 100])

    us = 1e6
    r = {
        "scene": name,
        "obstacles": len(world),
        "pairs": n_pairs,
        "build_s": t_build,
        "colliding": float(hit.mean()),
        "agree": float((hit == expected).mean()),
        "false_free": int((expected & ~hit).sum()),
        "batch_mixed_us": best_of(lambda: batched(Q)) / n * us,
        "batch_free_us": best_of(lambda: batched(free)) / max(1, free.shape[0]) * us,
        "single_free_us": best_of(lambda: [cc.in_collision(q) for q in free[:200]]) / min(200, free.shape[0]) * us,
        "baseline_mixed_us": best_of(lambda: [ref(q) for q in Q[:400]]) / 400 * us,
        "baseline_free_us": best_of(lambda: [ref(q) for q in free[:400]]) / min(400, free.shape[0]) * us,
    }
    # edges from free configurations: 2 rad (straight-line attempts, shortcuts) and 0.5 rad
    # (RRT extensions), L-inf, checked at 0.01 rad
    for length, key in ((2.0, "edge"), (0.5, "short")):
        valid_t, invalid_t = [], []
        for q0 in free[:80]:
            d = rng.uniform(-1, 1, 7)
            q1 = np.clip(q0 + length * d / np.abs(d).max(), kin.lower, kin.upper)
            t = time.perf_counter()
            ok = cc.motion_valid(q0, q1, 0.01)
            (valid_t if ok else invalid_t).append(time.perf_counter() - t)
        r[f"{key}_valid_ms"] = float(np.median(valid_t)) * 1e3 if valid_t else float("nan")
        r[f"{key}_invalid_ms"] = float(np.median(invalid_t)) * 1e3 if invalid_t else float("nan")
        r[f"{key}s"] = f"{len(valid_t)}/{len(valid_t) + len(invalid_t)}"
    return r


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--configs", type=int, default=1000, help="random configurations per scene")
    ap.add_argument("--no-mbm", action="store_true", help="skip the MotionBenchMaker scenes")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    config = load_robot_config("franka")
    kin = Kinematics(config)
    rng = np.random.default_rng(args.seed)
    scenes = [("shelf (7 boxes)", shelf_world())]
    if not args.no_mbm:
        try:
            from manip.benchmarking.mbm_problems import load_mbm_problems

            for p in load_mbm_problems(limit_per_scene=1):
                scenes.append((p.scene, WorldConfig.from_dict(p.world)))
        except FileNotFoundError as exc:
            print(f"(MotionBenchMaker scenes skipped: {exc})", file=sys.stderr)
    rows = [measure(name, config, kin, w, args.configs, rng) for name, w in scenes]
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; us per configuration (best of 3)\n")
    print("| scene | obst. | colliding | agree | batch mixed | batch free | single free | pin mixed | pin free | speed-up free "
          "| edge 2 rad valid / invalid [ms] (valid/all) | edge 0.5 rad valid / invalid [ms] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['scene']} | {r['obstacles']} | {r['colliding']:.0%} | {r['agree']:.2%} | "
              f"{r['batch_mixed_us']:.1f} | {r['batch_free_us']:.1f} | {r['single_free_us']:.0f} | "
              f"{r['baseline_mixed_us']:.0f} | {r['baseline_free_us']:.0f} | "
              f"{r['baseline_free_us'] / r['batch_free_us']:.0f}x | "
              f"{r['edge_valid_ms']:.2f} / {r['edge_invalid_ms']:.2f} ({r['edges']}) | "
              f"{r['short_valid_ms']:.2f} / {r['short_invalid_ms']:.2f} ({r['shorts']}) |")
    bad = [r["scene"] for r in rows if r["false_free"] or r["agree"] < 1.0]
    if bad:
        print(f"DISAGREEMENT with the baseline in: {bad}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
