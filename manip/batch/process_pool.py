"""The local backend: a pool of long-lived worker processes on this machine.

Workers warm up once (`worker.warm_up`) and then plan task after task. At most
`INFLIGHT_PER_WORKER` tasks per worker are queued at a time, so results stream back as
they finish and an interrupt has little to cancel.

Start methods (`default_start_method`): on Linux with Python < 3.12 the workers are forked
from the caller ("fork", the interpreter's own default there), which has already imported
manip to validate the batch and warms up once itself (`WARM_CALLER`): a worker starts with
nothing left to do, instead of a fresh interpreter's imports and warm-up (about 1.5 s of CPU
with "spawn"). On Linux
with Python >= 3.12, where forking a process that runs threads (numpy's OpenBLAS threads,
for one) is deprecated, a fork server is used: a fresh process that imports and warms manip
once (`FORKSERVER_PRELOAD`) and forks the workers; it lives as long as the caller, so later
batches start in about 0.1 s of CPU per worker. Elsewhere, "spawn". A caller that runs threads of
its own which may hold a lock when a worker is forked (a thread compiling numba kernels, an
OpenMP region) should pass "forkserver" or "spawn".

Faults: a worker that dies (killed, out of memory, a crash in native code) breaks a
`concurrent.futures.ProcessPoolExecutor` as a whole: every unfinished task fails with
`BrokenProcessPool`. The loop then keeps the results that did arrive, starts a new pool
and submits the unfinished tasks again, so no problem is lost and none is returned twice;
a task caught in `MAX_ATTEMPTS` broken pools raises `WorkerLostError`. On KeyboardInterrupt
(or any exception) the queued tasks are cancelled and the workers terminated. A caller that
is killed outright (kill -9, the OOM killer) cannot stop its workers: each notices within
`PARENT_POLL` s that the caller is gone and exits. (A fork server's workers watch the caller,
not their parent: the server lives until the caller and every worker have exited, since each
worker holds the server's "alive" pipe open, so it never ends first.)
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import signal
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from multiprocessing.context import BaseContext
from typing import Any

from manip.batch import worker
from manip.batch.problem import ProblemId, RobotSpec, Task
from manip.errors import InvalidInputError, ManipError

log = logging.getLogger(__name__)

#: Tasks queued per worker (enough to keep it busy between two results).
INFLIGHT_PER_WORKER = 2
#: A task is tried in at most this many pools (a worker death fails every unfinished task of its pool).
MAX_ATTEMPTS = 4
#: Start each worker in a session of its own (`os.setsid`). Linux's autogroup scheduler
#: shares CPU time between sessions, so on a machine busy with other sessions the workers of
#: one session share one session's slice (Ray's workers run in sessions of their own).
#: Off by default: the machine's policy stays the user's; `benchmarks/batch.py` measures both.
NEW_SESSION = False
#: With "fork", warm the batch's robots up in the caller (`worker.warm_up`, once per process and
#: robot) before forking: the workers inherit the generators and loaded kernels and start at
#: once. A first batch costs the same (the caller warms up instead of each worker, in
#: parallel); later batches of the process skip it (about 0.4 s of CPU per worker; plans
#: take about 0.03 s, so a 200-problem batch with 2 workers lasts about 3.5 s). The caller
#: keeps one generator per robot.
WARM_CALLER = True
#: Seconds to wait for terminated workers to exit.
STOP_TIMEOUT = 5.0
#: Start methods of the local backend (those this platform offers are valid).
START_METHODS = ("fork", "forkserver", "spawn")
#: What the fork server imports before it forks workers: this module warms a generator, so
#: the kernels are loaded once there and the workers inherit them.
FORKSERVER_PRELOAD = ("manip.batch.forkserver_warm",)


class WorkerLostError(ManipError):
    """Workers kept dying while these problems were being planned."""


#: Seconds between a worker's checks that the caller still lives (`_exit_with_caller`).
PARENT_POLL = 1.0


def _init_worker(robots: tuple[str | RobotSpec, ...], new_session: bool, caller: int) -> None:
    if new_session:
        os.setsid()
    # Ctrl-C in a terminal reaches the whole process group: the caller stops the workers.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_caller(caller)
    worker.start(robots)


def process_identity(pid: int) -> str | None:
    """What tells process `pid` from a later one given the same pid: its start time in clock
    ticks where /proc exists (Linux), else "" (only that a process of that pid exists); None
    when no such process runs (a zombie, killed and not yet reaped, counts as gone)."""
    if os.path.isdir("/proc/self"):
        try:
            with open(f"/proc/{pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            return None
        return None if fields[0] in ("Z", "X") else fields[19]
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return None
    except PermissionError:
        pass
    return ""


def _exit_with_caller(caller: int) -> None:
    """End this worker when the process that made its pool (pid `caller`) ends, or when its
    parent does (POSIX): a caller killed without a chance to stop its pool (kill -9, the OOM
    killer) would leave its workers waiting for tasks forever, each holding a warm generator's
    memory. A forked worker's parent is the caller; a fork server's worker's parent is the
    server, which outlives the caller as long as any of its workers lives (module docstring)."""
    if os.name != "posix":
        return
    parent = os.getppid()
    identity = process_identity(caller)

    def watch() -> None:
        while identity is not None and os.getppid() == parent and process_identity(caller) == identity:
            time.sleep(PARENT_POLL)
        os.kill(os.getpid(), signal.SIGKILL)  # at once: no cleanup to wait for, nobody to report to

    threading.Thread(target=watch, name="manip-exit-with-caller", daemon=True).start()


def default_start_method() -> str:
    """The start method of worker processes when none is given (see the module docstring).

    Returns:
        "fork" on Linux with Python < 3.12, "forkserver" on Linux with Python >= 3.12,
        "spawn" elsewhere (and where the interpreter does not offer the other two).
    """
    if sys.platform.startswith("linux"):
        method = "fork" if sys.version_info < (3, 12) else "forkserver"
        if method in mp.get_all_start_methods():
            return method
    return "spawn"


def check_start_method(method: str | None) -> str:
    """`method`, or the default for None; raises if this platform does not offer it.

    Raises:
        InvalidInputError: not a start method of this platform (the message lists them).
    """
    if method is None:
        return default_start_method()
    valid = [m for m in START_METHODS if m in mp.get_all_start_methods()]
    if not isinstance(method, str) or method not in valid:
        raise InvalidInputError(f"start_method must be one of {valid} on this platform (or None); got {method!r}")
    return method


def _context(method: str) -> BaseContext:
    ctx = mp.get_context(method)
    if method == "forkserver":
        # takes effect when the fork server starts (once per caller process)
        ctx.set_forkserver_preload(list(FORKSERVER_PRELOAD))
    return ctx


def _new_pool(workers: int, robots: tuple[str | RobotSpec, ...], method: str) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(workers, mp_context=_context(method), initializer=_init_worker,
                               initargs=(robots, NEW_SESSION, os.getpid()))


def _workers(pool: ProcessPoolExecutor) -> list:
    """The pool's worker processes now (no public handle before Python 3.14)."""
    return list((getattr(pool, "_processes", None) or {}).values())


def _stop(pool: ProcessPoolExecutor, known: set | None = None) -> None:
    """Cancel what is queued and terminate the workers (without waiting for running plans).

    `known` adds the workers seen earlier: a broken pool may already have dropped them from
    its table while they are still exiting."""
    processes = set(_workers(pool)) | (known or set())
    pool.shutdown(wait=False, cancel_futures=True)
    for p in processes:
        if p.is_alive():
            p.terminate()
    deadline = time.monotonic() + STOP_TIMEOUT
    for p in processes:
        p.join(timeout=max(0.0, deadline - time.monotonic()))
    # the pool's manager thread may reap a worker at the same time; its exit code shows a
    # moment later (until then the process looks alive to `multiprocessing.active_children`)
    while any(p.exitcode is None for p in processes) and time.monotonic() < deadline:
        time.sleep(0.005)
    # a worker killed while it sent a result leaves the pool's manager thread reading the rest
    # of that message for ever (and the interpreter's exit joining that thread): with every
    # worker gone, closing the caller's end of the result pipe gives the reader EOF.
    writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)
    if writer is not None and all(p.exitcode is not None for p in processes):
        writer.close()


#: What a worker runs on a task: `worker.solve` (or a module-level function of the same shape).
Job = Callable[[Task], tuple[ProblemId, Any]]


def run(tasks: Sequence[Any], workers: int, job: Job = worker.solve,
        start_method: str | None = None) -> Iterator[tuple[ProblemId, Any]]:
    """Plan `tasks` on `workers` local processes; yield (id, result) as plans finish.

    Args:
        tasks: validated tasks (a `Task`, or a job's own picklable task type with `id` and `robot`).
        workers: number of worker processes (>= 1); no more are started than there are tasks.
        job: the function run on each task in a worker (picklable: module level).
        start_method: "fork", "forkserver" or "spawn"; None = `default_start_method()`.

    Yields:
        (problem id, job's result: a PlanResult for `worker.solve`), each task exactly
        once, in order of completion.

    Raises:
        WorkerLostError: a task's workers died `MAX_ATTEMPTS` times.
    """
    method = check_start_method(start_method)
    workers = max(1, min(workers, len(tasks)))  # an idle worker would only warm up
    robots = tuple(sorted({t.robot for t in tasks}, key=str))
    order = {t.id: i for i, t in enumerate(tasks)}
    queue = deque(tasks)
    attempts: dict[ProblemId, int] = {}
    inflight: dict[Future, Task] = {}
    if method == "fork" and WARM_CALLER:
        worker.warm_up(robots)  # once per caller process and robot
    pool = _new_pool(workers, robots, method)
    log.debug("%d %s workers", workers, method)
    known: set = set()  # every worker process of this run's pools
    try:
        while queue or inflight:
            while queue and len(inflight) < INFLIGHT_PER_WORKER * workers:
                task = queue.popleft()
                attempts[task.id] = attempts.get(task.id, 0) + 1
                inflight[pool.submit(job, task)] = task
            known.update(_workers(pool))
            done, _ = wait(inflight, return_when=FIRST_COMPLETED)
            lost: list[Task] = []
            for f in done:
                task = inflight.pop(f)
                if isinstance(f.exception(), BrokenProcessPool):
                    lost.append(task)
                else:
                    yield f.result()  # a worker's exception (a bug, not a failed plan) propagates
            if not lost:
                continue
            # A worker died: every other unfinished task of this pool fails too. Keep the
            # results that arrived, resubmit the rest (in their order) to a new pool.
            for f, task in list(inflight.items()):
                f_done = f.done() and not f.cancelled()
                if f_done and f.exception() is None:
                    yield f.result()
                else:
                    lost.append(task)
            inflight.clear()
            _stop(pool, known)
            lost.sort(key=lambda t: order[t.id])
            hopeless = [t.id for t in lost if attempts[t.id] >= MAX_ATTEMPTS]
            if hopeless:
                raise WorkerLostError(f"workers died {MAX_ATTEMPTS} times while planning problems {hopeless}")
            log.warning("a worker died; restarting the pool and resubmitting %d problems", len(lost))
            queue.extendleft(reversed(lost))
            pool = _new_pool(workers, robots, method)
        pool.shutdown(wait=True)  # idle workers exit on their own (a terminated one may log a signal)
    finally:
        _stop(pool, known)
