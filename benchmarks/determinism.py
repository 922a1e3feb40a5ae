#!/usr/bin/env python3
"""Are plans the same, bit for bit, from run to run? Digests of results and of the checker's calls.

    python benchmarks/determinism.py [--limit-per-scene 5] [--repeat 2] [--json OUT] [--compare A.json B.json]

Plans, with seed 0: the first N valid MotionBenchMaker problems of each scene (joint and pose
goals, `plan_joints` / `plan_pose`), two seeded problems of each scene kind for each of the four
other arms (as tests/test_robots.py), one `plan_batch` and a `plan_grasp` + `plan_place` (the
scene of tests/planning/test_plan_grasp.py). Per plan it records a digest of the result (status,
success, attempts, source, message, trajectory arrays, path, goal) and a digest of the sequence of
`CollisionChecker._check` calls (each call's Q bytes and flags), with the number of calls, and
whether the plan's deadline passed (`SAFETY_NET` / TIMEOUT: then the machine's speed may show).
`--repeat` runs the whole suite that many times in this process and reports rows that differ;
`--compare` compares two JSON files of runs (e.g. two processes, one quiet and one under load).
No timings are compared: only answers and the checks that led to them.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from manip import MotionGenerator, Pose, WorldConfig
from manip import quaternion as quat
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems
from manip.benchmarking.scenes import SCENE_KINDS, make_problems
from manip.benchmarking.verify import Verifier
from manip.collision.checker import CollisionChecker
from manip.planning.context import SAFETY_NET

_CALLS: list = []   # hashes of the current plan's checker calls


def _record_checks() -> None:
    """Wrap `CollisionChecker._check` to hash every call (Q's bytes, shape, flags)."""
    original = CollisionChecker._check

    def _check(self, Q, stop_at_first=False, group=None, deepest_first=True, inside=False):
        h = hashlib.blake2b(np.ascontiguousarray(Q).tobytes(), digest_size=8)
        h.update(repr((Q.shape, stop_at_first, deepest_first, inside)).encode())
        if group is not None:
            h.update(np.ascontiguousarray(group).tobytes())
        out = original(self, Q, stop_at_first, group, deepest_first, inside)
        h.update(out.tobytes())
        _CALLS.append(h.digest())
        return out

    CollisionChecker._check = _check


def _arrays(r) -> list:
    """The arrays of a PlanResult that make the answer."""
    out = []
    if r.trajectory is not None:
        t = r.trajectory
        out += [t.positions, t.velocities, t.accelerations, np.array([t.dt])]
    for a in (r.path, r.goal_q):
        if a is not None:
            out.append(np.asarray(a))
    return out


def _digest(results) -> dict:
    """Digest of PlanResults (a list: a plan_batch or a grasp plan's segments)."""
    h = hashlib.blake2b(digest_size=12)
    late = False
    for r in results:
        h.update(repr((str(r.status), bool(r.success), r.attempts, getattr(r, "source", None),
                       r.message.replace(SAFETY_NET, ""))).encode())
        for a in _arrays(r):
            h.update(np.ascontiguousarray(a).tobytes())
        late |= SAFETY_NET in r.message or str(r.status).endswith("TIMEOUT")
    calls = hashlib.blake2b(b"".join(_CALLS), digest_size=12).hexdigest()
    return {"result": h.hexdigest(), "checks": calls, "n_checks": len(_CALLS), "late": late,
            "status": [str(r.status) for r in results]}


def _run(name: str, fn, rows: dict) -> None:
    _CALLS.clear()
    out = fn()
    rows[name] = _digest(out if isinstance(out, list) else [out])


def suite(limit_per_scene: int) -> dict:
    """Every plan of the suite: name -> digest row."""
    rows: dict = {}
    mg = MotionGenerator("franka", seed=0)
    verifier = Verifier(mg.config)
    problems = [p for p in load_mbm_problems(limit_per_scene=limit_per_scene) if verifier.check_problem(p).valid]
    for p in problems:
        mg.update_world(WorldConfig.from_dict(p.world))
        _run(f"mbm/{p.scene}/{p.index}/joint", lambda p=p: mg.plan_joints(p.start, p.goal, seed=0), rows)
        _run(f"mbm/{p.scene}/{p.index}/pose",
             lambda p=p: mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0), rows)
    p = problems[0]
    mg.update_world(WorldConfig.from_dict(p.world))
    goals = np.stack([q.goal for q in problems[:4]])
    _run("plan_batch", lambda: list(mg.plan_batch(p.start, goals, seed=0)), rows)
    for robot in ("ur5", "ur10", "kinova", "xarm7"):
        arm = MotionGenerator(robot, seed=0)
        verifier = Verifier(arm.config)
        for kind in SCENE_KINDS:
            for q in make_problems(kind, 2, seed=3, robot=robot, verifier=verifier):
                arm.update_world(WorldConfig.from_dict(q.world))
                _run(f"{robot}/{q.scene}/{q.index}", lambda arm=arm, q=q: arm.plan_joints(q.start, q.goal), rows)
    _grasp_and_place(rows)
    return rows


def _grasp_and_place(rows: dict) -> None:
    """tests/planning/test_plan_grasp.py's scene: a grasp, then an upright place."""
    from manip import OrientationConstraint

    cube = [0.5, 0.2, 0.025]
    world = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]},
                        "cube": {"dims": [0.05, 0.05, 0.05], "pose": cube + [1, 0, 0, 0]},
                        "post": {"dims": [0.06, 0.06, 0.3], "pose": [0.5, 0.05, 0.15, 1, 0, 0, 0]}}}
    mg = MotionGenerator("franka", world, seed=0)
    tcp = "panda_hand_tcp"
    down = [quat.multiply(quat.from_axis_angle([0, 0, 1], k * np.pi / 2), np.array([0.0, 1.0, 0.0, 0.0]))
            for k in range(4)]
    grasps = Pose.stack([Pose(np.add(cube, [0, 0, 0.003]), d) for d in down])
    grasp = mg.plan_grasp(mg.default_joint_positions, grasps, "cube", link=tcp)
    _CALLS.clear()
    grasp = mg.plan_grasp(mg.default_joint_positions, grasps, "cube", link=tcp)
    rows["plan_grasp"] = _digest(list(grasp.segments))
    rows["plan_grasp"]["index"] = grasp.grasp_index
    if not grasp.success:
        return
    mg.attach_object("cube", q=grasp.segment("approach").goal_q, link=tcp)
    upright = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1, link=tcp)
    places = Pose.stack([Pose([0.4, -0.3, 0.025], quat.from_axis_angle([0, 0, 1], a)) for a in (0.0, 0.4)])
    _run("plan_place", lambda: list(mg.plan_place(grasp.segment("lift").goal_q, places,
                                                  constraints=(upright,)).segments), rows)


def compare(a: dict, b: dict, what: str) -> int:
    """Print the rows of a and b that differ; returns their number."""
    bad = 0
    for name, x in a.items():
        y = b.get(name)
        if y is None or x["result"] != y["result"] or x["checks"] != y["checks"]:
            bad += 1
            print(f"{what}: {name}: result {'same' if y and x['result'] == y['result'] else 'DIFFERS'}, "
                  f"checks {x['n_checks']} vs {y and y['n_checks']}, late {x['late']} / {y and y['late']}")
    return bad


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--limit-per-scene", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--json", help="write the runs' rows here")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"), help="compare the first runs of two JSON files")
    args = ap.parse_args()
    if args.compare:
        a, b = (json.loads(Path(f).read_text())[0] for f in args.compare)
        bad = compare(a, b, "A vs B")
        print(f"{len(a)} plans, {bad} differ; late plans: {sum(r['late'] for r in a.values())} / "
              f"{sum(r['late'] for r in b.values())}")
        return 1 if bad else 0
    _record_checks()
    runs = []
    for k in range(args.repeat):
        runs.append(suite(args.limit_per_scene))
        print(f"run {k}: {len(runs[-1])} plans, {sum(r['n_checks'] for r in runs[-1].values())} checker calls, "
              f"{sum(r['late'] for r in runs[-1].values())} late, load {os.getloadavg()[0]:.2f}", flush=True)
    bad = sum(compare(runs[0], r, f"run 0 vs {k}") for k, r in enumerate(runs[1:], 1))
    if args.json:
        Path(args.json).write_text(json.dumps(runs))
    print(f"{bad} differences within the process")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
