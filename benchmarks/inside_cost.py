"""Added cost of the inside test (`manip.collision.inside`): `_check(inside=True)` against
`_check(inside=False)` on MotionBenchMaker worlds (every other world of the first 2 problems per
scene), 4000 random configurations as one batch and 300 one at a time, twice each, CPU time.

    python benchmarks/inside_cost.py
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import load_mbm_problems


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=4000)
    parser.add_argument("--singles", type=int, default=300)
    args = parser.parse_args()
    worlds = load_mbm_problems(limit_per_scene=2)[::2]
    rng = np.random.default_rng(0)
    batch, single = {True: 0.0, False: 0.0}, {True: 0.0, False: 0.0}
    differ = 0
    for problem in worlds:
        checker = MotionGenerator("franka", WorldConfig.from_dict(problem.world)).checker
        Q = rng.uniform(checker.kinematics.lower, checker.kinematics.upper, (args.batch, 7))
        for _ in range(2):
            for inside in (False, True):
                t = time.thread_time()
                checker._check(Q, inside=inside)
                batch[inside] += time.thread_time() - t
                t = time.thread_time()
                for q in Q[:args.singles]:
                    checker._check(q[None], inside=inside)
                single[inside] += time.thread_time() - t
        differ += int((checker._check(Q, inside=True) != checker._check(Q, inside=False)).sum())
    calls = 2 * args.singles * len(worlds)
    print(f"{len(worlds)} worlds; batch of {args.batch}: {batch[True]:.3f} s with the inside test, {batch[False]:.3f} s "
          f"without ({batch[True] / batch[False]:.2f} x); one configuration: {single[True] / calls * 1e6:.1f} us "
          f"against {single[False] / calls * 1e6:.1f} us ({single[True] / single[False]:.2f} x); "
          f"configurations whose answer differs: {differ} of {args.batch * len(worlds)}")


if __name__ == "__main__":
    main()
