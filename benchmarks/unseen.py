"""Problems nobody tuned for: random worlds for the five arms, random task calls, bad inputs.

    python benchmarks/unseen.py arms --robots franka ur5 --n 40 --seed 1000 --json /tmp/a.json
    python benchmarks/unseen.py tasks --n 30 --seed 2000 --json /tmp/t.json
    python benchmarks/unseen.py bad
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

from manip import MotionGenerator, OrientationConstraint, Pose
from manip import quaternion as quat
from manip.benchmarking.verify import Verifier

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


TCP = "panda_hand_tcp"
DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # the hand pointing down (w, x, y, z)


def _yaw(a: float) -> np.ndarray:
    return quat.from_axis_angle([0.0, 0.0, 1.0], a)


def pick_world(rng):
    """(world, object dims (3,), object pose (7,), top z, free-spot sampler) of a random pick."""
    top = rng.uniform(-0.15, 0.15)
    x0, depth, width = rng.uniform(0.25, 0.45), rng.uniform(0.35, 0.55), rng.uniform(0.8, 1.3)
    world: dict = {"cuboid": {"table": {"dims": [depth, width, 0.04], "pose": [x0 + depth / 2, 0, top - 0.02, 1, 0, 0, 0]}},
                   "cylinder": {}, "sphere": {}, "capsule": {}}
    placed: list = []

    def free_spot(radius: float):
        for _ in range(300):
            p = np.array([rng.uniform(x0 + 0.06, x0 + depth - 0.06), rng.uniform(-width / 2 + 0.08, width / 2 - 0.08)])
            if all(np.linalg.norm(p - q) > radius + r + 0.02 for q, r in placed):
                placed.append((p, radius))
                return p
        return None

    dims = np.array([rng.uniform(0.03, 0.07), rng.uniform(0.03, 0.07), rng.uniform(0.03, 0.12)])
    yaw = rng.uniform(-np.pi, np.pi)
    c = np.append(free_spot(0.5 * np.hypot(*dims[:2]) + 0.05), top + dims[2] / 2)
    pose = np.concatenate([c, _yaw(yaw)])
    world["cuboid"]["object"] = {"dims": dims.tolist(), "pose": pose.tolist()}
    for k in range(int(rng.integers(3, 11))):
        size = rng.uniform(0.015, 0.06)
        p = free_spot(size + 0.01)
        if p is None:
            break
        hh = rng.uniform(0.03, 0.30)
        kind = rng.choice(["cuboid", "cylinder", "sphere", "capsule"])
        if kind == "cuboid":
            world["cuboid"][f"c{k}"] = {"dims": [2 * size, rng.uniform(0.03, 0.12), hh],
                                        "pose": [*p, top + hh / 2, *_yaw(rng.uniform(-np.pi, np.pi))]}
        elif kind == "cylinder":
            world["cylinder"][f"c{k}"] = {"radius": size, "height": hh, "pose": [*p, top + hh / 2, 1, 0, 0, 0]}
        elif kind == "sphere":
            world["sphere"][f"c{k}"] = {"radius": size, "position": [*p, top + size]}
        else:
            world["capsule"][f"c{k}"] = {"radius": size, "base": [*p, top + size], "tip": [*p, top + size + hh],
                                         "pose": [0, 0, 0, 1, 0, 0, 0]}
    if rng.random() < 0.5:  # a board overhead, over part of the table
        h = top + rng.uniform(0.35, 0.6)
        world["cuboid"]["board"] = {"dims": [depth * 0.6, width * 0.5, 0.02],
                                    "pose": [x0 + depth * 0.6, rng.uniform(-0.3, 0.3), h, 1, 0, 0, 0]}
    return {k: v for k, v in world.items() if v}, dims, pose, top, free_spot


def top_grasps(dims, pose) -> Pose:
    """Top grasps of a box: the fingers closing across a side narrower than 7.5 cm, 4 depths."""
    c, yaw = pose[:3], 2 * math.atan2(pose[6], pose[3])
    out = []
    for k in range(4):
        width = dims[1] if k % 2 == 0 else dims[0]
        if width > 0.075:
            continue
        for d in (0.0, 0.01, 0.02):
            z = c[2] + max(0.0, dims[2] / 2 - 0.025 - d)
            out.append(Pose([c[0], c[1], z], quat.multiply(_yaw(yaw + k * np.pi / 2), DOWN)))
    return Pose.stack(out)


def _without(world: dict, name: str) -> dict:
    return {k: {n: v for n, v in d.items() if n != name} for k, d in world.items()}


def carried_collision(mg, verifier, world_without, dims, rel: Pose, traj) -> str | None:
    """The first obstacle the carried box touches along the densified trajectory (exact coal), or None."""
    import coal
    import pinocchio as pin

    from manip.benchmarking.verify import world_geometries

    _, Q = verifier.densify(traj.times, traj.positions)
    fid = mg.kinematics.frame_id(TCP)
    R, p = mg.kinematics.frame_transforms(Q, [fid])
    box = coal.Box(*dims)
    Rr, pr = quat.to_matrix(rel.quaternion), rel.position
    geoms = world_geometries(world_without)
    req, res = coal.CollisionRequest(), coal.CollisionResult()
    for i in range(Q.shape[0]):
        M = coal.Transform3s(R[i, 0] @ Rr, p[i, 0] + R[i, 0] @ pr)
        for name, shape, Mo in geoms:
            res.clear()
            if coal.collide(box, M, shape, coal.Transform3s(Mo.rotation, Mo.translation), req, res):
                return name
    del pin
    return None


def run_tasks(args) -> list[dict]:
    mg = MotionGenerator("franka")
    verifier = SupportVerifier(mg.config, resolution=args.resolution)
    upright = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1, link=TCP)
    ready = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    rows = []
    for i in range(args.start, args.start + args.n):
        rng = np.random.default_rng([args.seed, i])
        world, dims, opose, top, free_spot = pick_world(rng)
        mg.update_world(world)
        start = ready + rng.normal(0.0, 0.1, 7)
        if mg.check_collision(start):
            start = mg.default_joint_positions
        grasps = top_grasps(dims, opose)
        row = {"part": "tasks", "robot": "franka", "i": i, "goal": "plan_grasp", "n_grasps": len(grasps)}
        t0 = time.perf_counter()
        try:
            g = mg.plan_grasp(start, grasps, "object", link=TCP, seed=i)
        except Exception as exc:  # noqa: BLE001 - a finding
            row.update(status="EXCEPTION", message=f"{type(exc).__name__}: {exc}"[:300], trace=traceback.format_exc()[-800:])
            rows.append(row)
            _print(row)
            continue
        row.update(plan_s=time.perf_counter() - t0, status=g.status.name, success=bool(g.success),
                   message=(g.message or "")[:300])
        rows.append(row)
        if not g.success:
            _print(row)
            continue
        without = _without(world, "object")
        reasons = []
        for name, seg, w in zip(g.stages, g.segments, (world, without, without)):
            tr = seg.trajectory
            v = verifier.verify_trajectory(w, tr.times, tr.positions, tr.velocities, tr.accelerations, tr.jerks,
                                           start_q=tr.positions[0], goal_q=tr.positions[-1], check_jerk=True)
            reasons += [f"{name}: {r}" for r in v.reasons]
        row.update(valid=not reasons, reasons=reasons[:3], certified=True)
        _print(row)
        # place it with the hand kept upright, on a random free spot of the table
        q_grasp, q_lift = g.segment("approach").goal_q, g.segment("lift").goal_q
        mg.attach_object("object", q=q_grasp, link=TCP)
        rel = mg.fk(q_grasp, TCP).inverse() @ Pose(opose[:3], opose[3:])
        spots = [free_spot(0.5 * np.hypot(*dims[:2]) + 0.03) for _ in range(4)]
        places = Pose.stack([Pose([s[0], s[1], top + dims[2] / 2 + 0.002], _yaw(rng.uniform(-np.pi, np.pi)))
                             for s in spots if s is not None])
        prow = {"part": "tasks", "robot": "franka", "i": i, "goal": "plan_place upright"}
        t0 = time.perf_counter()
        try:
            pl = mg.plan_place(q_lift, places, constraints=(upright,), seed=i)
        except Exception as exc:  # noqa: BLE001 - a finding
            prow.update(status="EXCEPTION", message=f"{type(exc).__name__}: {exc}"[:300], trace=traceback.format_exc()[-800:])
            rows.append(prow)
            _print(prow)
            mg.detach_object(q_lift)
            continue
        prow.update(plan_s=time.perf_counter() - t0, status=pl.status.name, success=bool(pl.success),
                    message=(pl.message or "")[:300])
        if pl.success:
            reasons = []
            for name, seg in zip(pl.stages, pl.segments):
                tr = seg.trajectory
                v = verifier.verify_trajectory(without, tr.times, tr.positions, tr.velocities, tr.accelerations,
                                               tr.jerks, start_q=tr.positions[0], goal_q=tr.positions[-1],
                                               check_jerk=True)
                reasons += [f"{name}: {r}" for r in v.reasons]
                if name != "retreat":
                    hit = carried_collision(mg, verifier, _without(without, "table") if name == "descend" else without,
                                            dims, rel, tr)
                    if hit:
                        reasons.append(f"{name}: the carried box touches {hit}")
                    tilt = float(upright.tilt(mg.kinematics, verifier.densify(tr.times, tr.positions)[1]).max())
                    if tilt > 0.1:
                        reasons.append(f"{name}: tilt {tilt:.4f} > 0.1")
            prow.update(valid=not reasons, reasons=reasons[:3], certified=True)
        rows.append(prow)
        _print(prow)
        mg.detach_object(q_lift)
    rows += run_two_arms(args)
    rows += run_tutorial(args)
    return rows


def run_two_arms(args) -> list[dict]:
    """dual_ur5 plan_poses and a Franka + UR5 pair plan_joints among random clutter."""
    rows = []
    for label, make in (("dual_ur5", lambda: MotionGenerator("dual_ur5")),
                        ("franka+ur5", lambda: MotionGenerator.from_robots(
                            {"left": ("franka", Pose([0, 0.4, 0])), "right": ("ur5", Pose([0, -0.4, 0]))}))):
        mg = make()
        verifier = SupportVerifier(mg.config, resolution=args.resolution)
        hands = [link for link in _arm_ee_links(mg)]
        for i in range(args.start, args.start + max(1, args.n // 2)):
            rng = np.random.default_rng([args.seed, 77, i, len(label)])
            world = {"cuboid": {}, "sphere": {}}
            for k in range(int(rng.integers(3, 12))):
                c = [rng.uniform(0.3, 0.9), rng.uniform(-0.8, 0.8), rng.uniform(0.0, 0.8)]
                s = rng.uniform(0.02, 0.2, 3)
                if k % 2:
                    world["sphere"][f"s{k}"] = {"radius": s[0] / 2, "position": c}
                else:
                    world["cuboid"][f"b{k}"] = {"dims": list(s), "pose": c + _random_quat(rng)}
            mg.update_world(world)
            a = free_configuration(mg, verifier, world, rng)
            b = free_configuration(mg, verifier, world, rng) if a is not None else None
            goal = "plan_poses" if label == "dual_ur5" else "plan_joints"
            row = {"part": "two arms", "robot": label, "i": i, "goal": goal}
            if a is None or b is None or isinstance(a, tuple) or isinstance(b, tuple):
                row["status"] = "NO_PROBLEM" if a is None or b is None else "CHECKER_DISAGREES"
                rows.append(row)
                _print(row)
                continue
            t0 = time.perf_counter()
            try:
                if goal == "plan_poses":
                    targets = {h: mg.fk(b, h) for h in hands}
                    r = mg.plan_poses(a, targets, seed=i)
                else:
                    r = mg.plan_joints(a, b, seed=i)
            except Exception as exc:  # noqa: BLE001 - a finding
                row.update(status="EXCEPTION", message=f"{type(exc).__name__}: {exc}"[:300], trace=traceback.format_exc()[-800:])
                rows.append(row)
                _print(row)
                continue
            row["plan_s"] = time.perf_counter() - t0
            row.update(check_result(mg, verifier, world, r, a, b if goal == "plan_joints" else None, args.resolution))
            if r.success and goal == "plan_poses":
                errs = [max(float(np.linalg.norm(mg.fk(r.goal_q, h).position - targets[h].position)), 0) for h in hands]
                row["goal_pos_err"] = max(errs)
                if max(errs) > 1e-3:
                    row["valid"] = False
                    row["reasons"] = row.get("reasons", []) + [f"hand off its goal by {max(errs):.4f} m"]
            rows.append(row)
            _print(row)
    return rows


def run_tutorial(args) -> list[dict]:
    """The Isaac tutorial's wrapper as its scripts call it: `motion_generate` from a 9-value state
    to an [x, y, z, qx, qy, qz, qw] goal (the end effector's pose at a free configuration) in
    random worlds; the returned dict's positions checked by the verifier."""
    from manip import TutorialMotionGen

    t = TutorialMotionGen("franka.yml")
    t.init_motion_gen()
    mg = t.motion_gen
    verifier = SupportVerifier(mg.config, resolution=args.resolution)
    reach, rows = _reach(mg), []
    for i in range(args.start, args.start + max(1, args.n // 2)):
        rng = np.random.default_rng([args.seed, 99, i])
        world = random_world(rng, reach)
        mg.update_world(world)
        a = free_configuration(mg, verifier, world, rng)
        b = free_configuration(mg, verifier, world, rng) if a is not None else None
        row = {"part": "tutorial", "robot": "franka", "i": i, "goal": "motion_generate xyzw"}
        if a is None or b is None or isinstance(a, tuple) or isinstance(b, tuple):
            row["status"] = "NO_PROBLEM" if a is None or b is None else "CHECKER_DISAGREES"
            rows.append(row)
            continue
        goal = t.fk(list(b))
        t0 = time.perf_counter()
        try:
            out = t.motion_generate(list(a) + [0.04, 0.04], goal_end_effector_pose=goal)
        except Exception as exc:  # noqa: BLE001 - a finding
            row.update(status="EXCEPTION", message=f"{type(exc).__name__}: {exc}"[:300])
            rows.append(row)
            _print(row)
            continue
        row["plan_s"] = time.perf_counter() - t0
        row.update(status="SUCCESS" if out else "None", success=bool(out))
        if out:
            tr = out["raw_data"]
            v = verifier.verify_trajectory(world, tr.times, tr.positions, tr.velocities, tr.accelerations, tr.jerks,
                                           start_q=a, check_jerk=True)
            end = np.array(t.fk(list(tr.positions[-1])))
            err = float(np.linalg.norm(end[:3] - goal[:3]))
            dot = abs(float(np.dot(end[3:], goal[3:])))   # the gripper's half-turn twin counts (symmetric_gripper)
            twin = abs(float(np.dot(end[3:], quat.wxyz_to_xyzw(quat.multiply(quat.xyzw_to_wxyz(goal[3:]), [0, 0, 0, 1])))))
            reasons = list(v.reasons)[:3] + ([f"end {err * 1e3:.2f} mm from the goal"] if err > 1e-3 else []) \
                + ([f"end orientation off ({max(dot, twin):.5f})"] if max(dot, twin) < 1 - 1e-4 else [])
            row.update(valid=not reasons, reasons=reasons, certified=bool(mg.checker.certify_path(tr.positions).certified))
        rows.append(row)
        _print(row)
    return rows


def _arm_ee_links(mg) -> list[str]:
    return [arm.ee_link for arm in mg.config.arms] if getattr(mg.config, "arms", None) else [mg.ee_link]


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
    t = sub.add_parser("table", help="tabulate saved runs")
    t.add_argument("files", nargs="+")
    args = ap.parse_args(argv)
    if args.cmd == "table":
        rows = [r for f in args.files for r in json.loads(Path(f).read_text())]
        print(table(rows))
        return 0
    if args.cmd == "bad":
        from benchmarks.unseen_bad import run_bad

        rows = run_bad(args)
        if args.json:
            Path(args.json).write_text(json.dumps(rows))
        return 0
    rows = run_arms(args) if args.cmd == "arms" else run_tasks(args)
    if args.json:
        Path(args.json).write_text(json.dumps(rows))
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
