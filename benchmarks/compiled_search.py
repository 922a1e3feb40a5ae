#!/usr/bin/env python3
"""The path search alone, Python against compiled (`planning.path.compiled_search`), on
MotionBenchMaker problems: the same searches one after the other, in one process.

    python benchmarks/compiled_search.py [--scenes cage_panda ...] [--limit-per-scene 40] [--seeds 3]
        [--switch compiled|narrowphase]

For each valid problem whose straight line is blocked at the search resolution (joint goal) and
each seed, `search.search_path` (the coarse search and its fine repairs) runs with
`search.COMPILED_SEARCH` off and on (alternating which goes first) from generators of the same
seed. Per scene: searches, identical paths, RRT iterations, the configurations the checker was
asked about (Python: every sample of the coarse advances and of the repairs; compiled: the samples
its kernel screened, of which those coal decided), and the main thread's CPU time (`time.thread_time`)
summed, median and p98 of the searches, B / A. With `--switch narrowphase`, A and B are both
compiled, B deciding convex candidates in the kernel (`compiled_search.KERNEL_NARROWPHASE`), A
with coal only; the coal column then says (coal decided, kernel decided). CPU times depend on the machine and its load: take
the bench lock and note the load.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.collision.checker import CollisionChecker
from manip.planning.path import compiled_search, search
from manip.planning.validity import Validity

_CONFIGS = [0]


def _counting_check():
    """`CollisionChecker._check` wrapped to count the configurations it is asked about."""
    original = CollisionChecker._check

    def wrapper(self, Q, *args, **kwargs):
        _CONFIGS[0] += len(Q)
        return original(self, Q, *args, **kwargs)

    CollisionChecker._check = wrapper


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", nargs="*", default=["cage_panda", "bookshelf_small_panda"])
    ap.add_argument("--limit-per-scene", type=int, default=40)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--switch", choices=("compiled", "narrowphase"), default="compiled",
                    help="what B switches on: the compiled search, or its kernel narrowphase")
    args = ap.parse_args(argv)
    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    _counting_check()
    rows = collections.defaultdict(list)
    load = os.getloadavg()[0]
    for p in load_mbm_problems(scenes=args.scenes, limit_per_scene=args.limit_per_scene):
        if not verifier.check_problem(p).valid:
            continue
        mg.update_world(WorldConfig.from_dict(p.world))
        v = Validity(mg.checker.snapshot(), mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
        start, goal = np.asarray(p.start, float), np.asarray(p.goal, float)
        if v.coarse_motion(start, goal):
            continue
        for seed in range(args.seeds):
            out = {}
            for compiled in ((False, True) if seed % 2 == 0 else (True, False)):
                if args.switch == "compiled":
                    search.COMPILED_SEARCH = compiled
                else:
                    search.COMPILED_SEARCH = True
                    compiled_search.KERNEL_NARROWPHASE = compiled
                screened = []
                original = compiled_search.CompiledChecks.__init__

                def init(self, *a, _orig=original, _keep=screened, **k):
                    _orig(self, *a, **k)
                    _keep.append(self)

                compiled_search.CompiledChecks.__init__ = init
                _CONFIGS[0] = 0
                t = time.thread_time()
                path, its = search.search_path(start, goal[None], v, np.random.default_rng(seed), time.perf_counter() + 600)
                cpu = time.thread_time() - t
                compiled_search.CompiledChecks.__init__ = original
                exact = sum(c.counts[0] for c in screened)
                kernel = sum(c.counts[2] for c in screened)
                decided = sum(c.counts[3] for c in screened)
                out[compiled] = (path, its, cpu, _CONFIGS[0], kernel, exact, decided)
            a, b = out[False], out[True]
            same = (a[0] is None and b[0] is None) or (a[0] is not None and b[0] is not None and a[0].shape == b[0].shape
                                                       and np.array_equal(a[0], b[0]))
            rows[p.scene].append((same, a[1], b[1], a[2], b[2], a[3], b[3], b[4], b[5], b[6], a[4], a[5]))
    search.COMPILED_SEARCH = True
    compiled_search.KERNEL_NARROWPHASE = True
    if args.switch == "narrowphase":
        print("A = compiled search, coal only; B = compiled search deciding convex candidates in the kernel")
    print(f"load average at start {load:.2f}, at end {os.getloadavg()[0]:.2f}")
    print("| scene | searches | identical paths | RRT its mean / p98 (A, B) | configs A: checker | B: kernel screened "
          "(coal decided, kernel decided) + checker (repairs) [A: the same] | CPU sum A -> B [ms] | B / A sum, median, p98 |")
    print("|---|---|---|---|---|---|---|---|")
    every = []
    for scene, rs in sorted(rows.items()):
        r = np.array(rs, dtype=float)
        every.append(r)
        print(_line(scene, r))
    if len(every) > 1:
        print(_line("all", np.concatenate(every)))
    return 0


def _line(name: str, r: np.ndarray) -> str:
    ca, cb = r[:, 3] * 1e3, r[:, 4] * 1e3
    return (f"| {name} | {len(r)} | {int(r[:, 0].sum())} | {r[:, 1].mean():.0f} / {np.percentile(r[:, 1], 98):.0f}, "
            f"{r[:, 2].mean():.0f} / {np.percentile(r[:, 2], 98):.0f} | {r[:, 5].mean():.0f} | {r[:, 7].mean():.0f} "
            f"({r[:, 8].mean():.0f}, {r[:, 9].mean():.0f}) + checker {r[:, 6].mean():.0f} [A: {r[:, 10].mean():.0f} "
            f"({r[:, 11].mean():.0f}) + {r[:, 5].mean():.0f}] | {ca.sum():.0f} -> {cb.sum():.0f} | "
            f"{cb.sum() / ca.sum():.3f}, {np.median(cb) / np.median(ca):.3f}, "
            f"{np.percentile(cb, 98) / np.percentile(ca, 98):.3f} |")


if __name__ == "__main__":
    sys.exit(main())
