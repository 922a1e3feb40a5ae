"""`python -m manip.datagen`: generate a planning dataset (see `manip.datagen`).

Exit status: 0 when done, 1 when a trajectory planned as successful failed the independent
verifier, 2 on bad flags or settings, 3 when another run is writing --out (one writer per
folder: the second is refused at once; a run that ended, even by a crash, holds nothing),
130 after Ctrl-C (the rows received are kept).
"""

from __future__ import annotations

import argparse
import sys

from manip.batch.problem import BATCH_SEARCH_ITERATIONS, BATCH_TIME_BUDGET
from manip.benchmarking.scenes import SCENE_KINDS
from manip.datagen.lock import DatasetBusyError
from manip.errors import ManipError


def main(argv: list[str] | None = None) -> int:
    """Parse the flags, generate, print a final line with problems/s; 0 on success."""
    ap = argparse.ArgumentParser(
        prog="python -m manip.datagen", description=__doc__,
        epilog="Read the dataset back with manip.datagen.read_dataset(OUT) (rows in dataset order) or "
               "pandas.read_parquet(OUT); one row per problem, columns in manip.datagen.dataset.")
    ap.add_argument("--scenes", type=int, default=2, help="scenes, spread over the kinds in turn (default 2)")
    ap.add_argument("--problems-per-scene", type=int, default=2, help="start/goal pairs per scene (default 2)")
    ap.add_argument("--kinds", default=",".join(SCENE_KINDS), help=f"comma-separated scene kinds (default {','.join(SCENE_KINDS)})")
    ap.add_argument("--seed", type=int, default=0, help="dataset seed (default 0)")
    ap.add_argument("--robot", default="franka", help="a shipped robot (default franka); scenes scaled to its reach")
    ap.add_argument("--out", required=True, help="dataset folder; rerunning the same command resumes it")
    ap.add_argument("--workers", type=int, default=None, help="worker processes / Ray actors (default: all CPUs)")
    ap.add_argument("--backend", choices=("process", "ray"), default=None,
                    help="process (default) or ray (implied by --ray-address)")
    ap.add_argument("--ray-address", default=None, help="Ray cluster address for ray.init, e.g. auto or ray://head:10001")
    ap.add_argument("--time-budget", type=float, default=BATCH_TIME_BUDGET,
                    help=f"planning wall-time budget per problem [s], a safety net (default {BATCH_TIME_BUDGET:g})")
    ap.add_argument("--search-iterations", type=int, default=BATCH_SEARCH_ITERATIONS,
                    help="RRT iterations of a plan's path search, a count: the dataset does not depend on the "
                         f"machine (default {BATCH_SEARCH_ITERATIONS})")
    ap.add_argument("--dt", type=float, default=None,
                    help="sample period of the trajectories [s] (default: the planner's, 1/60); a problem whose "
                         "motion would need more than 100,000 samples is a failed row (status raised)")
    ap.add_argument("--rows-per-part", type=int, default=256, help="rows per Parquet part file (default 256)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = ap.parse_args(argv)

    from manip.datagen.generate import generate

    backend = args.backend or ("ray" if args.ray_address else "process")
    bar = None

    def on_total(n: int) -> None:
        nonlocal bar
        if not args.no_progress:
            from tqdm import tqdm

            bar = tqdm(total=n, unit="problem", smoothing=0.05)

    def on_row(row: dict) -> None:
        if bar is not None:
            bar.update(1)
            bar.set_postfix(status=row["status"], refresh=False)

    try:
        s = generate(args.out, scenes=args.scenes, problems_per_scene=args.problems_per_scene,
                     kinds=[k.strip() for k in args.kinds.split(",") if k.strip()], seed=args.seed, robot=args.robot,
                     workers=args.workers, backend=backend, ray_address=args.ray_address,
                     time_budget=args.time_budget, search_iterations=args.search_iterations, dt=args.dt,
                     rows_per_part=args.rows_per_part, on_total=on_total, on_row=on_row)
    except DatasetBusyError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 3
    except ManipError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"\ninterrupted: the rows received so far are in {args.out}; run the same command to resume",
              file=sys.stderr)
        return 130
    finally:
        if bar is not None:
            bar.close()
    raised = f", {s.raised} raised (see their message)" if s.raised else ""
    print(f"{s.planned} problems planned in {s.seconds:.1f} s: {s.rate:.2f} problems/s "
          f"({s.succeeded} succeeded, {s.verified} verified{raised}; {s.skipped} already in {args.out})")
    return 0 if s.verified == s.succeeded else 1


if __name__ == "__main__":
    sys.exit(main())
