"""Task calls on random problems, for `benchmarks/unseen.py tasks`: plan_grasp and plan_place with
the hand upright, two-arm robots, and the Isaac tutorial's wrapper (see unseen.py's docstring)."""

from __future__ import annotations

import math
import time
import traceback

import numpy as np

from benchmarks.unseen import (
    SupportVerifier,
    _print,
    _random_quat,
    _reach,
    check_result,
    free_configuration,
    random_world,
)
from manip import MotionGenerator, OrientationConstraint, Pose
from manip import quaternion as quat

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
