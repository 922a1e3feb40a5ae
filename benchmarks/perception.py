"""Planning on what two depth cameras see: the occupancy map against the true primitives.

    python benchmarks/perception.py [--per-kind 30] [--kinds table,shelf,box,clutter] [--seed 0] [--write-md]

For each seeded problem (`manip.benchmarking.scenes`: the scene, a start and a goal), the
scene's boxes and cylinders become fixed objects of a `manip.sim` World with the Franka at the
start configuration and two 640x480 depth cameras (`manip.sim.Camera`, above and behind the
robot on either side). Their images are integrated into an occupancy map (2 cm cells,
self-filtered at the start) of a MotionGenerator that knows nothing else; another one gets
the true primitives. Both plan the same joint goal (same seed, the batch planner's count
budget); each trajectory planned on the map is then checked against the true geometry by
the independent verifier (`manip.benchmarking.verify`, its own Pinocchio + coal models).

Reported: integration time per frame (CPU time of `update_world_from_depth`, split into the
depth integration and the rebuild of the map's collision tables), a collision check against
the map and against the primitives (CPU time per configuration over 2000 random
configurations), plan success (on the map, of the problems solved with the primitives),
planning time (CPU) on each, and collisions with the true geometry. `--write-md` replaces
the `## Perception` section of BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import replace_section  # noqa: E402
from benchmarks.pick_and_place import load_example, machine  # noqa: E402

RESOLUTION = 0.02  # [m]
CAMERAS = (((-0.6, -0.9, 1.5), (0.45, 0.0, 0.25)), ((-0.6, 0.9, 1.5), (0.45, 0.0, 0.25)))
FOCAL_LENGTH = 1.2   # Isaac's units: an 82 deg horizontal field of view
OPTIONS = {"search_iterations": 10000, "time_budget": 60.0}


def build_scene(world_dict: dict, start: np.ndarray):
    """A manip.sim World of the problem's obstacles, the Franka at `start` and the cameras."""
    from manip.sim import Camera, FixedCuboid, FixedCylinder, Franka, World, create_new_stage

    World.clear_instance()
    create_new_stage()
    world = World()
    for name, e in (world_dict.get("cuboid") or {}).items():
        world.scene.add(FixedCuboid(f"/World/{name}", name=name, position=np.array(e["pose"][:3]), size=1.0,
                                    scale=np.array(e["dims"]), orientation=np.array(e["pose"][3:])))
    for name, e in (world_dict.get("cylinder") or {}).items():
        world.scene.add(FixedCylinder(f"/World/{name}", name=name, position=np.array(e["pose"][:3]),
                                      radius=e["radius"], height=e["height"], orientation=np.array(e["pose"][3:])))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    look_at = load_example("perception_rig").look_at  # Isaac's camera axes, as the flagship's cameras
    cams = []
    for i, (eye, target) in enumerate(CAMERAS):
        cam = Camera(f"/World/cam{i}", position=np.array(eye), orientation=look_at(eye, target), resolution=(640, 480))
        cam.set_focal_length(FOCAL_LENGTH)
        cams.append(cam)
    world.reset()
    q = np.concatenate([start, [0.04, 0.04]])
    franka.set_joint_positions(q)
    return world, franka, cams


def run(kinds: list[str], per_kind: int, seed: int, resolution: float = RESOLUTION, fill: str = "cells") -> dict:
    from manip import MotionGenerator, Pose
    from manip.benchmarking.scenes import make_problems
    from manip.benchmarking.verify import default_verifier
    from manip.collision import OccupancyMap

    verifier = default_verifier()
    mg_map = MotionGenerator("franka")
    mg_true = MotionGenerator("franka")
    rows = []
    integrate, rebuild, check_map, check_true = [], [], [], []
    rng = np.random.default_rng(seed)
    for kind in kinds:
        problems = make_problems(kind, per_kind, seed)
        for k, pb in enumerate(problems):
            world, franka, cams = build_scene(pb.world, pb.start)
            if "camera" in mg_map.world:
                mg_map.remove_obstacle("camera")
            for cam in cams:
                depth = cam.get_depth()
                p, o = cam.get_world_pose()
                K = cam.get_intrinsics_matrix()
                c0 = time.thread_time()
                m = mg_map.update_world_from_depth(depth, K, Pose(p, o), q=pb.start, resolution=resolution, fill=fill)
                integrate.append(time.thread_time() - c0)
            c0 = time.thread_time()   # the map's collision tables alone: built again from its cells
            again = OccupancyMap.from_cells("camera", resolution, m.cells, m.bounds)
            mg_map.checker.replace_obstacle(again)
            rebuild.append(time.thread_time() - c0)
            mg_true.update_world(pb.world)
            if k < 3:   # collision checks per configuration, map vs primitives
                Q = rng.uniform(mg_true.lower_limits, mg_true.upper_limits, (2000, 7))
                for mg, out in ((mg_map, check_map), (mg_true, check_true)):
                    mg.checker.in_collision_batch(Q[:10])
                    c0 = time.thread_time()
                    mg.checker.in_collision_batch(Q)
                    out.append((time.thread_time() - c0) / len(Q))
            row = {"kind": kind, "index": k, "cells": m.num_cells, "boxes": m.num_boxes,
                   # the map holds each surface within a cell (its far corner up to a cell diagonal away):
                   # a start or goal closer than that to an obstacle may collide with the map (the
                   # clearance of both, true geometry, no padding)
                   "clearance": min(mg_true.distance(pb.start), mg_true.distance(pb.goal))}
            for tag, mg in (("true", mg_true), ("map", mg_map)):
                c0 = time.thread_time()
                r = mg.plan_joints(pb.start, pb.goal, seed=seed * 1000 + k, **OPTIONS)
                row[f"{tag}_time"] = time.thread_time() - c0
                row[f"{tag}_ok"] = r.success
                row[f"{tag}_status"] = r.status.name
                if tag == "map" and r.success:
                    t = r.trajectory
                    v = verifier.verify_trajectory(pb.world, t.times, t.positions)
                    row["collision"] = v.collision_at is not None
                    row["collision_pair"] = v.collision_pair
            rows.append(row)
            print(f"  {kind}/{k}: true {row['true_status']} {row['true_time']:.3f} s, map {row['map_status']} "
                  f"{row['map_time']:.3f} s{' COLLIDES ' + str(row['collision_pair']) if row.get('collision') else ''}; "
                  f"{m.num_cells} cells, {m.num_boxes} boxes", flush=True)
    return {"rows": rows, "resolution": resolution, "fill": fill, "integrate": np.array(integrate),
            "rebuild": np.array(rebuild), "check_map": np.array(check_map), "check_true": np.array(check_true)}


def table(res: dict, m: dict) -> str:
    rows = res["rows"]
    solvable = [r for r in rows if r["true_ok"]]
    both = [r for r in solvable if r["map_ok"]]
    coll = sum(bool(r.get("collision")) for r in rows)
    wide = [r for r in solvable if r["clearance"] >= res["resolution"] * np.sqrt(3.0)]
    wide_ok = [r for r in wide if r["map_ok"]]
    integ, rebuild = res["integrate"], res["rebuild"]
    lines = [
        f"Machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, MuJoCo {m['mujoco']}; {m['date']}; "
        f"load average at start {m['load']:.1f}",
        "",
        "| measure | value |",
        "|---|---|",
        f"| update per 640x480 frame (CPU), median / p90 | {np.median(integ) * 1e3:.1f} / "
        f"{np.percentile(integ, 90) * 1e3:.1f} ms |",
        f"| of which the map's collision tables, median | {np.median(rebuild) * 1e3:.1f} ms (integration alone "
        f"{(np.median(integ) - np.median(rebuild)) * 1e3:.1f} ms) |",
        f"| collision check per configuration: map / primitives | {np.median(res['check_map']) * 1e6:.1f} / "
        f"{np.median(res['check_true']) * 1e6:.1f} us ({np.median(res['check_map']) / np.median(res['check_true']):.2f}x) |",
        f"| problems solved with the true primitives | {len(solvable)}/{len(rows)} |",
        f"| of those solved on the map | {len(both)}/{len(solvable)} ({100 * len(both) / max(len(solvable), 1):.1f} %) |",
        f"| planning time (CPU) median, both solved: map / primitives | "
        f"{np.median([r['map_time'] for r in both]) * 1e3:.0f} / {np.median([r['true_time'] for r in both]) * 1e3:.0f} ms "
        f"({np.median([r['map_time'] for r in both]) / np.median([r['true_time'] for r in both]):.2f}x) |",
        f"| of those whose start and goal keep >= a cell diagonal ({res['resolution'] * np.sqrt(3) * 100:.1f} cm) "
        f"from the obstacles | "
        f"{len(wide_ok)}/{len(wide)} ({100 * len(wide_ok) / max(len(wide), 1):.1f} %) |",
        f"| map plans colliding with the true geometry (verifier) | {coll}/{sum(r['map_ok'] for r in rows)} |",
        "",
        "| kind | problems | solved (primitives) | solved (map) | map plans colliding | cells / boxes (median) |",
        "|---|---|---|---|---|---|",
    ]
    for kind in dict.fromkeys(r["kind"] for r in rows):
        rs = [r for r in rows if r["kind"] == kind]
        lines.append(f"| {kind} | {len(rs)} | {sum(r['true_ok'] for r in rs)} | "
                     f"{sum(r['map_ok'] and r['true_ok'] for r in rs)} | {sum(bool(r.get('collision')) for r in rs)} | "
                     f"{np.median([r['cells'] for r in rs]):.0f} / {np.median([r['boxes'] for r in rs]):.0f} |")
    fails = [f"{r['kind']}/{r['index']} ({r['map_status']}, clearance {r['clearance'] * 1e3:.1f} mm)"
             for r in solvable if not r["map_ok"]]
    if fails:
        lines += ["", "Solved with the primitives, not on the map: " + ", ".join(fails)]
    hits = [f"{r['kind']}/{r['index']} {r['collision_pair']}" for r in rows if r.get("collision")]
    if hits:
        lines += ["", "Map plans colliding with the true geometry: " + ", ".join(hits)]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-kind", type=int, default=30)
    parser.add_argument("--kinds", default="table,shelf,box,clutter")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--resolution", type=float, default=RESOLUTION, help="cell edge of the map [m]")
    parser.add_argument("--fill", default="cells", choices=("points", "cells"),
                        help="what an occupied cell holds (update_world_from_depth's fill)")
    parser.add_argument("--write-md", action="store_true", help="update the Perception section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    kinds = [k.strip() for k in args.kinds.split(",") if k.strip()]
    m = machine()
    res = run(kinds, args.per_kind, args.seed, args.resolution, args.fill)
    text = table(res, m)
    print()
    print(text)
    if args.write_md:
        cmd = (f"python benchmarks/perception.py --per-kind {args.per_kind} --kinds {args.kinds} --seed {args.seed} "
               f"--resolution {args.resolution} --fill {args.fill}")
        replace_section(ROOT / "BENCHMARKS.md", "## Perception",
                        "## Perception\n\n" f"`{cmd} --write-md` (see the script's docstring: seeded scenes in "
                        "manip.sim, two 640x480 depth cameras above and behind the robot, a 2 cm occupancy map "
                        "self-filtered at the start; the same joint goals planned on the map and on the true "
                        "primitives; every map plan checked against the true geometry by the independent verifier; "
                        "CPU times on a machine shared with other jobs).\n\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
