"""Batch planning throughput: 1 vs 2 worker processes, Ray actors vs tasks vs the process
pool, a two-node Ray test cluster against the local run (bit for bit), and a worker killed
in the middle of the batch. Prints a markdown section for BENCHMARKS.md.

Ray actors are measured twice: on the first batch of the Ray session (the actors start:
a fresh interpreter each, imports and warm-up) and on later batches, which run on the
actors the batch before kept warm (`ray_backend.KEEP_WARM`), interleaved round by round
with the process pool's later batches (workers forked from the warm caller).

The problems: `make_problems(kind, n / 5, seed)` of each of the five seeded scene kinds
(table, shelf, box, cage, clutter), joint goals, the batch's default options
(`manip.batch.BATCH_OPTIONS`: a count budget for the path search, the time budget a safety
net; "past budget" counts the results the safety net may have changed), batch seed 0.
Throughput is given end to end (plan_stream's wall time: validation, worker start and
warm-up included) and steady (results 2..n over the time between the first and the last
result). Each problem runs through `timed_solve`, which measures the worker's CPU time
(user + system, `time.process_time`) of the planning call, and on a worker's first problem
the CPU the worker spent before it (interpreter start, imports, warm-up): so CPU per problem
and start-up CPU per worker are separate (getrusage of the children, used before, counted
each worker's start-up in the CPU per problem). The calling process's own CPU (validation,
dispatch, result unpickling) is given too. A calibration runs a fixed pure-Python loop in
1 and then 2 processes: the machine's own 2-core scaling. The machine is shared: compare
ratios within one run; "CPU stolen" is the share of the machine's CPU time the hypervisor
gave to other guests during a run (/proc/stat), the part of the drift that can be seen.

Workers start with the default start method (`process_pool.default_start_method()`: "fork"
on Linux with Python < 3.12), or with each of `--start-methods` in turn (interleaved rounds).
A fork server lives as long as the calling process, so only the first "forkserver" run of a
benchmark pays for starting it: its later rounds are not first calls. Likewise with "fork" the
caller warms up once (`process_pool.WARM_CALLER`): it does so here before the timed runs, so
they are all later batches of a warm caller; `--cold-caller` turns that off (every run then
a first call: each worker warms up itself).

Usage:
    .venv/bin/python benchmarks/batch.py [--n 200] [--rounds 6] [--no-ray] [--start-methods fork,spawn]
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import signal
import subprocess
import sys
import time
import multiprocessing as mp
from collections import Counter

import numpy as np

from manip.batch import BATCH_OPTIONS, Problem, process_pool, ray_backend, worker
from manip.batch.plan import run_tasks, validate
from manip.batch.problem import prepare
from manip.benchmarking.scenes import SCENE_KINDS, make_problems
from manip.motion_generator import MotionGenerator
from manip.planning.context import SAFETY_NET
from manip.planning.result import PlanStatus


def problems(n: int, seed: int = 0) -> list[Problem]:
    """n problems, n / 5 of each scene kind, ids "<kind>/<i>"."""
    out = []
    for kind in SCENE_KINDS:
        for p in make_problems(kind, n // len(SCENE_KINDS), seed):
            out.append(Problem(p.world, p.start, p.goal, id=f"{kind}/{p.index}"))
    return out


def _self_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _cpu_ticks() -> tuple[int, int]:
    """(steal, total) CPU ticks of the machine so far (/proc/stat; (0, 0) where there is none)."""
    try:
        with open("/proc/stat") as f:
            fields = [int(x) for x in f.readline().split()[1:]]
    except OSError:
        return 0, 0
    return (fields[7] if len(fields) > 7 else 0), sum(fields[:8])


def timed_solve(task):
    """`worker.solve` with the worker's CPU time [s] of the call, and on the worker's first
    call the CPU time it spent before (start-up: interpreter, imports, warm-up)."""
    startup = None
    # marked on the worker module: Ray unpickles a new copy of this function for every task
    if not getattr(worker, "_benchmark_started", False):
        worker._benchmark_started = True
        startup = time.process_time()
    c = time.process_time()
    pid, result = worker.solve(task)
    return pid, (result, time.process_time() - c, startup)


def run(batch, kill_after: int | None = None, workers: int | None = None, backend: str = "process",
        seed: int = 0, start_method: str | None = None) -> dict:
    """Plan `batch` as `plan_stream` does (validation, then the backend) with `timed_solve`."""
    parent0 = _self_cpu()
    ticks0 = _cpu_ticks()
    t0 = time.perf_counter()
    times, results, seen, cpu, startup = [], {}, Counter(), [], []
    tasks, n_workers = validate(batch, workers, backend, seed, start_method)
    for pid, (r, c, s) in run_tasks(tasks, workers=n_workers, backend=backend, job=timed_solve,
                                    start_method=start_method):
        times.append(time.perf_counter())
        results[pid] = r
        seen[pid] += 1
        cpu.append(c)
        if s is not None:
            startup.append(s)
        if kill_after is not None and len(times) == kill_after:
            victim = mp.active_children()[0].pid
            os.kill(victim, signal.SIGKILL)
    wall = time.perf_counter() - t0
    n = len(batch)
    return {
        "wall": wall, "e2e": n / wall, "steady": (n - 1) / (times[-1] - times[0]), "first": times[0] - t0,
        "results": results, "seen": seen, "cpu": float(np.mean(cpu)),
        "startup": float(np.mean(startup)) if startup else float("nan"),  # none: workers kept from a batch before
        "cpu_with_startup": (sum(cpu) + sum(startup)) / n, "parent": _self_cpu() - parent0,
        "plan_mean": float(np.mean([r.plan_time for r in results.values()])),
        "success": sum(bool(r.success) for r in results.values()), "late": late(results), "steal": _steal(ticks0),
    }


def _steal(ticks0: tuple[int, int]) -> float:
    """Share of the machine's CPU time the hypervisor gave to other guests since `ticks0` [%]."""
    steal, total = _cpu_ticks()
    return 100.0 * (steal - ticks0[0]) / max(1, total - ticks0[1])


CALIBRATION = "import time\nt = time.perf_counter()\nx = 0\nfor i in range(20_000_000): x += i & 7\nprint(time.perf_counter() - t)"


def calibrate() -> tuple[float, float]:
    """Wall time [s] of a fixed pure-Python loop alone, and the mean of two run at once."""
    def go(k: int) -> float:
        procs = [subprocess.Popen([sys.executable, "-c", CALIBRATION], stdout=subprocess.PIPE, text=True)
                 for _ in range(k)]
        return float(np.mean([float(p.communicate()[0]) for p in procs]))
    return go(1), go(2)


def late(results: dict) -> int:
    """How many results ran past their time budget (TIMEOUT, or the SAFETY_NET note)."""
    return sum(r.status is PlanStatus.TIMEOUT or SAFETY_NET in r.message for r in results.values())


def identical(a: dict, b: dict) -> int:
    """How many problems have the same status and bit-identical trajectories in both runs."""
    same = 0
    for pid, ra in a["results"].items():
        rb = b["results"][pid]
        if ra.status is rb.status and (
            (ra.trajectory is None and rb.trajectory is None)
            or (ra.trajectory is not None and rb.trajectory is not None
                and np.array_equal(ra.trajectory.positions, rb.trajectory.positions))):
            same += 1
    return same


def world_switch_cost(batch) -> tuple[float, float]:
    """Median [ms] of `update_world` on a warm generator vs building a new generator with the world."""
    worker.warm_up(("franka",))
    mg = worker.generator("franka")
    upd, new = [], []
    for p in batch[:50]:
        t = time.perf_counter()
        mg.update_world(p.world)
        upd.append(time.perf_counter() - t)
        t = time.perf_counter()
        MotionGenerator("franka", p.world)
        new.append(time.perf_counter() - t)
    return 1e3 * float(np.median(upd)), 1e3 * float(np.median(new))


def ray_tasks(ray, batch, seed: int) -> dict:
    """The same batch as Ray tasks (worker processes warm up on their first task)."""
    parent0 = _self_cpu()
    ticks0 = _cpu_ticks()
    t0 = time.perf_counter()
    tasks = prepare(batch, seed)
    solve = ray.remote(num_cpus=1)(timed_solve)
    refs = [solve.remote(t) for t in tasks]
    results, times, cpu = {}, [], []
    pending = list(refs)
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        pid, (r, c, _) = ray.get(done[0])
        results[pid] = r
        cpu.append(c)
        times.append(time.perf_counter())
    wall = time.perf_counter() - t0
    n = len(batch)
    # a Ray task's process may have warmed up inside an earlier task: no start-up figure
    return {"wall": wall, "e2e": n / wall, "steady": (n - 1) / (times[-1] - times[0]), "first": times[0] - t0,
            "results": results, "seen": Counter(results), "cpu": float(np.mean(cpu)), "startup": float("nan"),
            "cpu_with_startup": float("nan"), "parent": _self_cpu() - parent0,
            "success": sum(bool(r.success) for r in results.values()), "late": late(results), "steal": _steal(ticks0),
            "plan_mean": float(np.mean([r.plan_time for r in results.values()]))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=200, help="problems (a multiple of 5)")
    ap.add_argument("--rounds", type=int, default=2,
                    help="alternating 1-worker / 2-worker rounds (the load of a shared machine drifts)")
    ap.add_argument("--no-ray", action="store_true", help="skip the Ray runs")
    ap.add_argument("--start-methods", default=None,
                    help="comma-separated start methods of the process workers, measured in interleaved "
                         "rounds (default: the default method only)")
    ap.add_argument("--cold-caller", action="store_true",
                    help="forked workers warm up themselves, the caller does not (process_pool.WARM_CALLER off)")
    ap.add_argument("--worker-sessions", action="store_true",
                    help="process workers in sessions of their own (process_pool.NEW_SESSION), as Ray's are")
    args = ap.parse_args()
    batch = problems(args.n)
    process_pool.NEW_SESSION = args.worker_sessions
    process_pool.WARM_CALLER = not args.cold_caller
    rows = []
    load = os.getloadavg()[0]
    alone, pair = calibrate()

    default = process_pool.default_start_method()
    methods = args.start_methods.split(",") if args.start_methods else [default]
    if process_pool.WARM_CALLER and "fork" in methods:
        worker.warm_up(("franka",))  # untimed: every timed run is a later batch of a warm caller
    pairs = []  # (method, round, 1-worker run, 2-worker run)
    for k in range(args.rounds):
        for m in methods:
            a = run(batch, workers=1, start_method=m)
            rows.append((f"process, {m} (round {k + 1})", 1, a))
            b = run(batch, workers=2, start_method=m)
            rows.append((f"process, {m} (round {k + 1})", 2, b))
            pairs.append((m, k, a, b))
    _, _, r1, r2 = next(p for p in pairs if p[0] == default) if default in methods else pairs[0]
    fault = run(batch, workers=2, kill_after=args.n // 2)
    upd, new = world_switch_cost(batch)  # after the timed runs: it warms up this process
    extra, ray_pairs = {}, []
    if not args.no_ray:
        import ray
        from ray.cluster_utils import Cluster

        ray.init(num_cpus=2, log_to_driver=False)
        # the pool's batch between two Ray batches may last longer than the default idle time
        ray_backend.KEEP_WARM = 3600.0
        rr = run(batch, workers=2, backend="ray")  # the first batch: the actors start and warm up
        rows.append(("ray actors, first batch (actors start)", 2, rr))
        for k in range(args.rounds):  # later batches, interleaved with the pool's (the load drifts)
            p = run(batch, workers=2, start_method=default)
            rows.append((f"process, {default}, beside Ray (round {k + 1})", 2, p))
            w = run(batch, workers=2, backend="ray")  # on the actors kept warm by the batch before
            rows.append((f"ray actors, kept warm (round {k + 1})", 2, w))
            ray_pairs.append((p, w))
        ray_backend.release_actors()
        rt = ray_tasks(ray, batch, 0)
        rows.append(("ray tasks", 2, rt))
        ray.shutdown()
        cluster = Cluster(initialize_head=True, head_node_args={"num_cpus": 1})
        cluster.add_node(num_cpus=1)
        ray.init(address=cluster.address, log_to_driver=False)
        rc = run(batch, backend="ray")
        rows.append(("ray 2-node cluster", 2, rc))
        ray.shutdown()
        cluster.shutdown()
        extra = {"ray": rr, "tasks": rt, "cluster": rc}

    cpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    model = next((ln.split(":", 1)[1].strip() for ln in cpu.splitlines() if ln.startswith("Model name")), platform.processor())
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    print(f"Machine: {model}, {os.cpu_count()} cores; Python {platform.python_version()}; commit {commit}; "
          f"{time.strftime('%Y-%m-%d %H:%M', time.gmtime())} UTC; load average {load:.1f} before the run (shared machine).\n")
    print(f"{args.n} problems ({args.n // 5} of each seeded kind), joint goals, {BATCH_OPTIONS}, seed 0; "
          f"process workers in {'sessions of their own' if args.worker_sessions else 'the caller session'}; "
          f"default start method {default}; caller warm-up {'off' if args.cold_caller else 'on'}; PYTHONDONTWRITEBYTECODE={os.environ.get('PYTHONDONTWRITEBYTECODE', '')!r}.\n")
    print("| backend | workers | wall [s] | problems/s end to end | problems/s steady | first result [s] "
          "| worker CPU s / problem | start-up CPU s / worker | caller CPU [s] | mean plan time [s] | success "
          "| past budget | identical to 1 process | CPU stolen [%] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, w, r in rows:
        start = "n/a" if np.isnan(r["startup"]) else f"{r['startup']:.2f}"
        print(f"| {name} | {w} | {r['wall']:.1f} | {r['e2e']:.2f} | {r['steady']:.2f} | {r['first']:.2f} | "
              f"{r['cpu']:.3f} | {start} | {r['parent']:.2f} | {r['plan_mean']:.3f} | {r['success']}/{args.n} | "
              f"{r['late']} | {identical(r, r1)}/{args.n} | {r['steal']:.1f} |")
    print()
    print(f"- Calibration, a fixed pure-Python loop: {alone:.2f} s alone, {pair:.2f} s each with two at once "
          f"(the machine's 2-process scaling: {2 * alone / pair:.2f}x).")
    for m, k, a, b in pairs:
        print(f"- {m}, round {k + 1}, 2 workers / 1 worker: {b['e2e'] / a['e2e']:.2f}x end to end, "
              f"{b['steady'] / a['steady']:.2f}x steady; worker CPU per problem {b['cpu'] / a['cpu']:.2f}x "
              f"({b['cpu_with_startup'] / a['cpu_with_startup']:.2f}x with the start-up counted in, as before).")
    if extra:
        for key, label in (("ray", "Ray actors, first batch (the actors start)"), ("tasks", "Ray tasks")):
            print(f"- {label} / process pool at 2 workers: {extra[key]['e2e'] / r2['e2e']:.2f}x end to end, "
                  f"{extra[key]['steady'] / r2['steady']:.2f}x steady.")
        for k, (p, w) in enumerate(ray_pairs):
            print(f"- Round {k + 1}, Ray actors kept warm / process pool (warm caller), 2 workers, batches run one "
                  f"after the other: {w['e2e'] / p['e2e']:.2f}x end to end, {w['steady'] / p['steady']:.2f}x steady.")
        print(f"- 2-node Ray cluster vs local 2-process run: {identical(extra['cluster'], r2)}/{args.n} bit-identical.")
    print(f"- Fault run (2 workers, one SIGKILLed after {args.n // 2} results): {len(fault['seen'])}/{args.n} ids back, "
          f"each once: {set(fault['seen'].values()) == {1}}; identical to the undisturbed run: "
          f"{identical(fault, r2)}/{args.n}; wall {fault['wall']:.1f} s vs {r2['wall']:.1f} s.")
    print(f"- World switch on a warm worker: update_world {upd:.1f} ms vs a new MotionGenerator {new:.0f} ms (median).")
    per_core = max(a["steady"] for _, _, a, _ in pairs)
    print(f"- Per core: {per_core:.2f} problems/s; 1 M problems = {1e6 / per_core / 3600:.0f} core-hours, "
          f"e.g. {1e6 / per_core / 3600 / 64:.1f} h on 64 cores, {1e6 / per_core / 3600 / 512:.1f} h on 512.")


if __name__ == "__main__":
    main()
