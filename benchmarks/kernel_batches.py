#!/usr/bin/env python3
"""The collision checker's per-configuration kernels on recorded batches: CPU per configuration of
the forward kinematics, the world broadphase and the self broadphase, and of the whole `_check`.

    python benchmarks/kernel_batches.py [--limit-per-scene 4] [--repeat 5] [--goal joint]

Plans the first N valid MotionBenchMaker problems of each scene (Franka, seed 0) and records every
batch the checker's `_check_chunk` is given inside `_segments_valid` (the shortcut's,
`remove_redundant`'s and the repairs' segment checks) with its checker (a snapshot); then replays
the batches: each kernel alone (min over `--repeat` passes of the main thread's CPU), the
structure-of-arrays kernels (`manip.collision.broadphase_soa`, `kinematics._joint_frames_lanes`
through `joint_transforms`) next to the per-configuration ones, the world broadphase's answers
compared (identical candidate triples and depths, or the script fails), and `_check_chunk` as the
segment checks call it. CPU times depend on the machine: take the bench lock and
note the load.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.collision import broadphase
from manip.collision.checker import CollisionChecker
from manip.collision.segments import SegmentChecks
from manip.jit import kernel_array
from manip.kinematics import _joint_frames


def record(limit: int, kinds: list[str]) -> list[tuple]:
    """(checker, Q, group) of every `_check_chunk` batch of the segment checks of the plans."""
    batches: list[tuple] = []
    inside = [0]
    seg, chunk = SegmentChecks._segments_valid, CollisionChecker._check_chunk

    def seg_rec(self, *a, **k):
        inside[0] += 1
        try:
            return seg(self, *a, **k)
        finally:
            inside[0] -= 1

    def chunk_rec(self, Q, group, *a, **k):
        if inside[0]:
            batches.append((self, np.array(Q), None if group is None else np.array(group), a[0]))
        return chunk(self, Q, group, *a, **k)

    SegmentChecks._segments_valid, CollisionChecker._check_chunk = seg_rec, chunk_rec
    try:
        mg = MotionGenerator("franka")
        verifier = Verifier(mg.config)
        problems = [p for p in load_mbm_problems(limit_per_scene=limit) if verifier.check_problem(p).valid]
        for p in problems:
            mg.update_world(WorldConfig.from_dict(p.world))
            for kind in kinds:
                if kind == "joint":
                    mg.plan_joints(p.start, p.goal, seed=0)
                else:
                    mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0)
    finally:
        SegmentChecks._segments_valid, CollisionChecker._check_chunk = seg, chunk
    return batches


def _old_kernels(fn):
    """fn() with the checker on the per-configuration FK and world broadphase kernels."""
    from manip import kinematics
    from manip.collision import broadphase_soa

    soa_world, lanes_from = broadphase_soa.world_candidates, kinematics.FK_LANES_FROM
    broadphase_soa.world_candidates = lambda R, p, margin, *tables: broadphase.world_candidates(R, p, margin,
                                                                                              *tables[:-1])
    kinematics.FK_LANES_FROM = 1 << 62
    try:
        return fn()
    finally:
        broadphase_soa.world_candidates, kinematics.FK_LANES_FROM = soa_world, lanes_from


def _cpu(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.thread_time()
        fn()
        best = min(best, time.thread_time() - t0)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit-per-scene", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--goal", choices=("joint", "pose", "both"), default="joint")
    args = ap.parse_args(argv)
    kinds = ["joint", "pose"] if args.goal == "both" else [args.goal]
    load0 = os.getloadavg()[0]
    batches = record(args.limit_per_scene, kinds)
    N = sum(b[1].shape[0] for b in batches)
    print(f"{len(batches)} batches, {N} configurations ({N / len(batches):.0f} a batch)")
    fk = [(c, kernel_array(Q)) for c, Q, _, _ in batches]
    frames = [(c, Q) + c._fk(Q) for c, Q in fk]
    world = [(c, R, p) for c, Q, R, p in frames if len(c._obs) and c._l0_joint.size]
    soa = None
    try:
        from manip.collision import broadphase_soa as soa
    except ImportError:
        pass

    def run_fk():
        for c, Q in fk:
            c._fk(Q)

    def run_fk_old():
        for c, Q in fk:
            kin = c.kinematics
            _joint_frames(Q, kin._sb_q, kin._sb_parent_a, kin._sb_table)

    def run_world():
        for c, R, p in world:
            broadphase.world_candidates(R, p, c._padding + 1e-9, *c._bp_world, *c._bp_obstacles)

    def run_world_soa():
        for c, R, p in world:
            soa.world_candidates(R, p, c._padding + 1e-9, *c._bp_world, *c._bp_obstacles, soa.LANES)

    def run_self():
        for c, Q, R, p in frames:
            broadphase.self_candidates(R, p, Q, c._self_padding + 1e-9, *c._bp_self)

    def run_check():
        for c, Q, g, deep in batches:
            c._check_chunk(Q, g, deep, set(), np.zeros(Q.shape[0], dtype=bool))

    rows = [("FK, per configuration (_joint_frames)", run_fk_old), ("FK (Kinematics.joint_transforms)", run_fk),
            ("world broadphase", run_world)]
    if soa is not None:
        for c, R, p in world:   # identical answers, or no figures
            a = broadphase.world_candidates(R, p, c._padding + 1e-9, *c._bp_world, *c._bp_obstacles)
            b = soa.world_candidates(R, p, c._padding + 1e-9, *c._bp_world, *c._bp_obstacles, soa.LANES)
            if not all(np.array_equal(x, y) for x, y in zip(a, b)):
                raise SystemExit("world_candidates: the structure-of-arrays kernel answers differently")
        rows.append(("world broadphase, structure of arrays", run_world_soa))
    rows.append(("self broadphase", run_self))
    rows.append(("_check_chunk (all of it)", run_check))
    if soa is not None:
        rows.append(("_check_chunk, per-configuration kernels", lambda: _old_kernels(run_check)))
    for _, fn in rows:   # compile / load everything before timing
        fn()
    print(f"{'kernel':40s} {'CPU [s]':>9s} {'us / configuration':>19s}")
    for name, fn in rows:
        t = _cpu(fn, args.repeat)
        print(f"{name:40s} {t:9.4f} {1e6 * t / N:19.3f}")
    print(f"load average {load0:.2f} -> {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
