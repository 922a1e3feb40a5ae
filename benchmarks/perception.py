"""Planning on what two depth cameras see: the occupancy map against the true primitives.

    python benchmarks/perception.py [--per-kind 30] [--kinds table,shelf,box,clutter] [--seed 0]
        [--fill cells,points] [--write-md]

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
planning time (CPU) on each, and collisions with the true geometry: over all map plans, and
over those whose reached faces the cameras saw (every point of the true surfaces, sampled
every `SPACING`, within `REACH` of the plan's sphere cover lies where a camera measured a
surface: a pixel next to its own with a depth within 5 mm + two pixel footprints of it).
Each fill of `--fill` gets its own map from the same images. `--write-md` replaces the
`## Perception` section of BENCHMARKS.md.
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
SPACING = 0.005   # [m] between the surface points that judge what the cameras saw
REACH = 0.02      # [m] the surface within this of a plan's sphere cover is what it reaches


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


def surface_points(world_dict: dict, spacing: float = SPACING) -> np.ndarray:
    """(P, 3) [m] points on the surfaces of the world's boxes and cylinders, about `spacing`
    [m] apart (edges included)."""
    from manip import quaternion as quat

    out = []

    def grid(n0, n1):
        return np.meshgrid(np.linspace(-1.0, 1.0, n0), np.linspace(-1.0, 1.0, n1), indexing="ij")

    for e in (world_dict.get("cuboid") or {}).values():
        h = np.asarray(e["dims"], float) / 2.0
        R, c = quat.to_matrix(np.asarray(e["pose"][3:], float)), np.asarray(e["pose"][:3], float)
        for axis in range(3):
            u, v = [k for k in range(3) if k != axis]
            A, B = grid(max(int(np.ceil(2 * h[u] / spacing)) + 1, 2), max(int(np.ceil(2 * h[v] / spacing)) + 1, 2))
            for sign in (-1.0, 1.0):
                P = np.zeros((A.size, 3))
                P[:, axis] = sign * h[axis]
                P[:, u], P[:, v] = A.ravel() * h[u], B.ravel() * h[v]
                out.append(P @ R.T + c)
    for e in (world_dict.get("cylinder") or {}).values():
        r, hh = float(e["radius"]), float(e["height"]) / 2.0
        R, c = quat.to_matrix(np.asarray(e["pose"][3:], float)), np.asarray(e["pose"][:3], float)
        na = max(int(np.ceil(2 * np.pi * r / spacing)), 8)
        th = np.linspace(0.0, 2 * np.pi, na, endpoint=False)
        z = np.linspace(-hh, hh, max(int(np.ceil(2 * hh / spacing)) + 1, 2))
        T, Z = np.meshgrid(th, z, indexing="ij")
        P = [np.stack([r * np.cos(T.ravel()), r * np.sin(T.ravel()), Z.ravel()], axis=1)]
        for ring in np.linspace(0.0, r, max(int(np.ceil(r / spacing)) + 1, 2)):
            k = max(int(np.ceil(2 * np.pi * ring / spacing)), 1)
            a = np.linspace(0.0, 2 * np.pi, k, endpoint=False)
            for zz in (-hh, hh):
                P.append(np.stack([ring * np.cos(a), ring * np.sin(a), np.full(k, zz)], axis=1))
        out.append(np.concatenate(P) @ R.T + c)
    return np.concatenate(out) if out else np.zeros((0, 3))


def visible(points: np.ndarray, views: list) -> np.ndarray:
    """(P,) bool: which points (P, 3) [m] a camera measured: for some view (depth (H, W) [m],
    intrinsics (3, 3), camera Pose, Isaac's axes), a pixel within one of the point's pixel
    whose depth is within 5 mm + two pixel footprints of the point's depth."""
    from manip.perception.integrate import WORLD_AXES_TO_OPTICAL

    out = np.zeros(points.shape[0], dtype=bool)
    for depth, K, pose in views:
        H, W = depth.shape
        Y = (points - pose.position) @ (pose.rotation @ WORLD_AXES_TO_OPTICAL)   # optical frame
        z = Y[:, 2]
        front = z > 1e-6
        u = np.full(z.shape, -10, dtype=np.int64)
        v = np.full(z.shape, -10, dtype=np.int64)
        u[front] = np.rint(K[0, 0] * Y[front, 0] / z[front] + K[0, 2]).astype(np.int64)
        v[front] = np.rint(K[1, 1] * Y[front, 1] / z[front] + K[1, 2]).astype(np.int64)
        tol = 0.005 + 2.0 * z / K[0, 0]
        for du in (-1, 0, 1):
            for dv in (-1, 0, 1):
                uu, vv = u + du, v + dv
                ok = front & (uu >= 0) & (uu < W) & (vv >= 0) & (vv < H)
                d = np.full(z.shape, np.inf)
                d[ok] = depth[vv[ok], uu[ok]]
                out |= ok & (np.abs(d - z) <= tol)
    return out


def reached_points(mg, positions: np.ndarray, surface: np.ndarray, reach: float = REACH) -> np.ndarray:
    """Indices of the surface points (P, 3) [m] within `reach` [m] of the robot's moving
    sphere cover at any of positions (T, 7)."""
    from scipy.spatial import cKDTree

    if surface.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    st = mg.checker.state
    moving = st.fine.joint != 0
    balls = [mg.checker.spheres(q) for q in positions]
    C = np.concatenate([c[moving] for c, _, _ in balls])
    r = np.concatenate([rr[moving] for _, rr, _ in balls])
    tree = cKDTree(surface)
    hit = set()
    for rad in np.unique(np.round(r + reach, 4)):
        sel = np.round(r + reach, 4) == rad
        for ids in tree.query_ball_point(C[sel], rad):
            hit.update(ids)
    return np.array(sorted(hit), dtype=np.int64)


def run(kinds: list[str], per_kind: int, seed: int, resolution: float = RESOLUTION,
        fills: tuple[str, ...] = ("cells",)) -> dict:
    """Every problem once with the true primitives and once on a map of each fill (same images)."""
    from manip import MotionGenerator, Pose
    from manip.benchmarking.scenes import make_problems
    from manip.benchmarking.verify import default_verifier
    from manip.collision import OccupancyMap

    verifier = default_verifier()
    mg_true = MotionGenerator("franka")
    maps = {fill: MotionGenerator("franka") for fill in fills}
    out = {fill: {"rows": [], "integrate": [], "rebuild": [], "check_map": [], "check_true": []} for fill in fills}
    rng = np.random.default_rng(seed)
    for kind in kinds:
        problems = make_problems(kind, per_kind, seed)
        for k, pb in enumerate(problems):
            world, franka, cams = build_scene(pb.world, pb.start)
            views = []
            for cam in cams:
                p, o = cam.get_world_pose()
                views.append((cam.get_depth(), cam.get_intrinsics_matrix(), Pose(p, o)))
            mg_true.update_world(pb.world)
            c0 = time.thread_time()
            true_plan = mg_true.plan_joints(pb.start, pb.goal, seed=seed * 1000 + k, **OPTIONS)
            true_time = time.thread_time() - c0
            surface = surface_points(pb.world)
            Q = rng.uniform(mg_true.lower_limits, mg_true.upper_limits, (2000, 7)) if k < 3 else None
            for fill, mg_map in maps.items():
                o = out[fill]
                if "camera" in mg_map.world:
                    mg_map.remove_obstacle("camera")
                for depth, K, pose in views:
                    c0 = time.thread_time()
                    m = mg_map.update_world_from_depth(depth, K, pose, q=pb.start, resolution=resolution, fill=fill)
                    o["integrate"].append(time.thread_time() - c0)
                c0 = time.thread_time()   # the map's collision tables alone: built again from its cells
                points = None if m.points is None else (m.point_start, m.points)
                again = OccupancyMap.from_cells("camera", resolution, m.cells, m.bounds, points, _sorted=True)   # as an update
                mg_map.checker.replace_obstacle(again)
                o["rebuild"].append(time.thread_time() - c0)
                if Q is not None:   # collision checks per configuration, map vs primitives
                    for mg, key in ((mg_map, "check_map"), (mg_true, "check_true")):
                        mg.checker.in_collision_batch(Q[:10])
                        c0 = time.thread_time()
                        mg.checker.in_collision_batch(Q)
                        o[key].append((time.thread_time() - c0) / len(Q))
                row = {"kind": kind, "index": k, "cells": m.num_cells, "boxes": m.num_boxes,
                       # the clearance of start and goal (true geometry, no padding)
                       "clearance": min(mg_true.distance(pb.start), mg_true.distance(pb.goal)),
                       "true_time": true_time, "true_ok": bool(true_plan.success), "true_status": true_plan.status.name}
                c0 = time.thread_time()
                r = mg_map.plan_joints(pb.start, pb.goal, seed=seed * 1000 + k, **OPTIONS)
                row["map_time"] = time.thread_time() - c0
                row["map_ok"] = bool(r.success)
                row["map_status"] = r.status.name
                if r.success:
                    t = r.trajectory
                    v = verifier.verify_trajectory(pb.world, t.times, t.positions)
                    row["collision"] = v.collision_at is not None
                    row["collision_pair"] = v.collision_pair
                    # what the plan reaches of the true surfaces, and how much of it a camera measured
                    near = reached_points(mg_true, t.positions, surface)
                    row["reached"] = int(near.size)
                    row["unseen"] = int(near.size - visible(surface[near], views).sum())
                o["rows"].append(row)
                print(f"  {kind}/{k} {fill}: true {row['true_status']} {row['true_time']:.3f} s, map "
                      f"{row['map_status']} {row['map_time']:.3f} s"
                      f"{' COLLIDES ' + str(row['collision_pair']) if row.get('collision') else ''}"
                      f"{'' if not row.get('unseen') else ' (%d of %d reached points unseen)' % (row['unseen'], row['reached'])}; "
                      f"{m.num_cells} cells, {m.num_boxes} boxes", flush=True)
    return {"resolution": resolution, "fills": {fill: {k: (np.array(v) if k != "rows" else v) for k, v in o.items()}
                                                for fill, o in out.items()}}


def table(res: dict, fill: str) -> str:
    """The markdown table of one fill's results."""
    f = res["fills"][fill]
    rows = f["rows"]
    solvable = [r for r in rows if r["true_ok"]]
    both = [r for r in solvable if r["map_ok"]]
    planned = [r for r in rows if r["map_ok"]]
    coll = sum(bool(r.get("collision")) for r in rows)
    seen = [r for r in planned if r["unseen"] == 0]
    seen_coll = sum(bool(r.get("collision")) for r in seen)
    wide = [r for r in solvable if r["clearance"] >= res["resolution"] * np.sqrt(3.0)]
    wide_ok = [r for r in wide if r["map_ok"]]
    integ, rebuild = f["integrate"], f["rebuild"]
    lines = [
        f"`fill=\"{fill}\"`:",
        "",
        "| measure | value |",
        "|---|---|",
        f"| update per 640x480 frame (CPU), median / p90 | {np.median(integ) * 1e3:.1f} / "
        f"{np.percentile(integ, 90) * 1e3:.1f} ms |",
        f"| of which the map's collision tables, median | {np.median(rebuild) * 1e3:.1f} ms (integration alone "
        f"{(np.median(integ) - np.median(rebuild)) * 1e3:.1f} ms) |",
        f"| collision check per configuration: map / primitives | {np.median(f['check_map']) * 1e6:.1f} / "
        f"{np.median(f['check_true']) * 1e6:.1f} us ({np.median(f['check_map']) / np.median(f['check_true']):.2f}x) |",
        f"| problems solved with the true primitives | {len(solvable)}/{len(rows)} |",
        f"| of those solved on the map | {len(both)}/{len(solvable)} ({100 * len(both) / max(len(solvable), 1):.1f} %) |",
        "| planning time (CPU) median, both solved: map / primitives | " + (
            f"{np.median([r['map_time'] for r in both]) * 1e3:.0f} / {np.median([r['true_time'] for r in both]) * 1e3:.0f} "
            f"ms ({np.median([r['map_time'] for r in both]) / np.median([r['true_time'] for r in both]):.2f}x) |"
            if both else "none solved on both |"),
        f"| of those whose start and goal keep >= a cell diagonal ({res['resolution'] * np.sqrt(3) * 100:.1f} cm) "
        f"from the obstacles | {len(wide_ok)}/{len(wide)} ({100 * len(wide_ok) / max(len(wide), 1):.1f} %) |",
        f"| map plans colliding with the true geometry (verifier), all | {coll}/{len(planned)} |",
        f"| map plans colliding, of those whose reached faces the cameras saw | {seen_coll}/{len(seen)} |",
        "",
        "| kind | problems | solved (primitives) | solved (map) | map plans colliding (all / reached faces seen) "
        "| cells / boxes (median) |",
        "|---|---|---|---|---|---|",
    ]
    for kind in dict.fromkeys(r["kind"] for r in rows):
        rs = [r for r in rows if r["kind"] == kind]
        lines.append(f"| {kind} | {len(rs)} | {sum(r['true_ok'] for r in rs)} | "
                     f"{sum(r['map_ok'] and r['true_ok'] for r in rs)} | {sum(bool(r.get('collision')) for r in rs)} / "
                     f"{sum(bool(r.get('collision')) for r in rs if r['map_ok'] and r['unseen'] == 0)} of "
                     f"{sum(r['map_ok'] and r['unseen'] == 0 for r in rs)} | "
                     f"{np.median([r['cells'] for r in rs]):.0f} / {np.median([r['boxes'] for r in rs]):.0f} |")
    fails = [f"{r['kind']}/{r['index']} ({r['map_status']}, clearance {r['clearance'] * 1e3:.1f} mm)"
             for r in solvable if not r["map_ok"]]
    if fails:
        lines += ["", "Solved with the primitives, not on the map: " + ", ".join(fails)]
    hits = [f"{r['kind']}/{r['index']} {r['collision_pair']} ({r['unseen']} of {r['reached']} reached surface points "
            "unseen)" for r in rows if r.get("collision")]
    if hits:
        lines += ["", "Map plans colliding with the true geometry: " + ", ".join(hits)]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-kind", type=int, default=30)
    parser.add_argument("--kinds", default="table,shelf,box,clutter")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--resolution", type=float, default=RESOLUTION, help="cell edge of the map [m]")
    parser.add_argument("--fill", default="cells,points",
                        help="what an occupied cell holds (update_world_from_depth's fill): one or both, comma-separated")
    parser.add_argument("--write-md", action="store_true", help="update the Perception section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    kinds = [k.strip() for k in args.kinds.split(",") if k.strip()]
    fills = tuple(f.strip() for f in args.fill.split(",") if f.strip())
    if not fills or any(f not in ("cells", "points") for f in fills):
        parser.error(f"--fill: 'cells', 'points' or both (comma-separated); got {args.fill!r}")
    m = machine()
    res = run(kinds, args.per_kind, args.seed, args.resolution, fills)
    text = (f"Machine: {m['cpu']}, {m['cores']} cores; Python {m['python']}, MuJoCo {m['mujoco']}; {m['date']}; "
            f"load average at start {m['load']:.1f}\n\n" + "\n".join(table(res, fill) for fill in fills))
    print()
    print(text)
    if args.write_md:
        cmd = (f"python benchmarks/perception.py --per-kind {args.per_kind} --kinds {args.kinds} --seed {args.seed} "
               f"--resolution {args.resolution} --fill {','.join(fills)}")
        replace_section(ROOT / "BENCHMARKS.md", "## Perception",
                        "## Perception\n\n" f"`{cmd} --write-md` (see the script's docstring: seeded scenes in "
                        "manip.sim, two 640x480 depth cameras above and behind the robot, a 2 cm occupancy map "
                        "self-filtered at the start, one per fill from the same images; the same joint goals planned "
                        "on the map and on the true primitives; every map plan checked against the true geometry by "
                        "the independent verifier; 'reached faces seen': every point of the true surfaces within "
                        f"{REACH * 100:.0f} cm of the plan's sphere cover (sampled every {SPACING * 1e3:.0f} mm) was "
                        "measured by a camera; CPU times).\n\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
