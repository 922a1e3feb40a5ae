"""`plan_many` and `plan_stream`: plan a batch of problems on every core, or on a Ray cluster.

    from manip.batch import Problem, plan_many
    results = plan_many([Problem(world, start, goal) for ...], workers=2, seed=0)

Results are the `PlanResult`s of the single planning calls (`plan_joints` for a joint goal,
`plan_pose` for a Pose goal), in input order. A failed plan is a result with its status; a
problem whose planning raises in its worker is a failed result too (status RAISED, the message
naming the problem and the error), and the batch goes on.
Each problem's seed is `problem_seed(seed, id)` and its path search is bounded by a count
(`problem.BATCH_OPTIONS`: `search_iterations`, with a generous `time_budget` as a safety net),
so a problem plans the same on any backend, with any worker count, in any order of completion
and on any machine, unless the safety net fires (then the result is TIMEOUT or its message
ends with `planning.context.SAFETY_NET`).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

from manip.batch import process_pool, worker
from manip.batch.problem import Problem, ProblemId, Task, prepare
from manip.errors import InvalidInputError
from manip.planning.result import PlanResult
from manip.validation import flag, integer

log = logging.getLogger(__name__)

#: Backends of `plan_many`.
BACKENDS = ("process", "ray")


def plan_stream(
    problems: Iterable[Problem],
    *,
    workers: int | None = None,
    backend: str = "process",
    seed: int = 0,
    ray_address: str | None = None,
    start_method: str | None = None,
) -> Iterator[tuple[ProblemId, PlanResult]]:
    """Plan `problems` in parallel and yield (problem id, result) as each plan finishes.

    The batch is validated before any worker starts. Closing the iterator early (or an
    exception, or Ctrl-C while waiting) cancels what is queued and stops the workers.

    Args:
        problems: the problems (ids default to their index in this iterable).
        workers: worker processes (or Ray actors); None = all cores this process may use,
            or for Ray the cluster's CPUs. No more are started than there are problems.
        backend: "process" (local processes, no Ray needed) or "ray".
        seed: batch seed (>= 0); problem i plans with `problem_seed(seed, id_i)`.
        ray_address: for backend="ray" when Ray is not initialised: the `ray.init`
            address (None = a local instance, "auto" = the cluster this machine belongs to).
        start_method: for backend="process": how workers start, "fork", "forkserver" or
            "spawn" (those this platform offers); None = `process_pool.default_start_method()`
            ("fork" on Linux with Python < 3.12: the workers skip the imports). Results do
            not depend on it.

    Yields:
        (problem id, PlanResult), each problem exactly once, in order of completion (a
        problem whose planning raised: status RAISED, the message naming it and the error).

    Raises:
        UnknownNameError: an unknown robot (the message lists the valid ones).
        RobotConfigError: a robot.yaml given by path is malformed.
        InvalidInputError: a malformed problem, workers < 1, an unknown backend or start
            method (or a start method with backend="ray", a ray_address without it).
        WorkerLostError: workers kept dying on the same problems.
    """
    tasks, n = validate(problems, workers, backend, seed, start_method, ray_address)
    return run_tasks(tasks, workers=n, backend=backend, ray_address=ray_address, start_method=start_method)


def run_tasks(tasks: Sequence[Any], *, workers: int | None, backend: str, ray_address: str | None = None,
              job: process_pool.Job = worker.solve,
              start_method: str | None = None) -> Iterator[tuple[ProblemId, Any]]:
    """Run `job` on validated tasks on a backend; yield (task id, job result) as they finish.

    `plan_stream` runs `worker.solve` on the tasks of `prepare`; `manip.datagen` runs its own
    job on its own task type (any picklable object with `id` and `robot` attributes).
    """
    if not tasks:
        return iter(())
    if backend == "ray":
        from manip.batch import ray_backend  # optional: only with the ray extra

        ray_backend.import_ray()
        return ray_backend.run(tasks, workers, ray_address, job=job)
    return process_pool.run(tasks, workers or _cores(), job, start_method)


def plan_many(
    problems: Iterable[Problem],
    *,
    workers: int | None = None,
    backend: str = "process",
    seed: int = 0,
    progress: bool = True,
    ray_address: str | None = None,
    start_method: str | None = None,
) -> list[PlanResult]:
    """Plan `problems` in parallel; the results in input order.

    Args:
        problems: the problems.
        workers: worker processes (or Ray actors); None = all cores / the cluster's CPUs.
        backend: "process" or "ray".
        seed: batch seed (>= 0).
        progress: show a progress bar (tqdm, when installed).
        ray_address: see `plan_stream`.
        start_method: see `plan_stream`.

    Returns:
        One PlanResult per problem, in the order of `problems`.

    Raises:
        As `plan_stream`.
    """
    problems = list(problems) if not isinstance(problems, (Problem, str, dict)) else problems
    progress = flag(progress, "progress")
    stream = plan_stream(problems, workers=workers, backend=backend, seed=seed, ray_address=ray_address,
                         start_method=start_method)
    ids = [p.id if p.id is not None else i for i, p in enumerate(problems)]
    results: dict[ProblemId, PlanResult] = {}
    bar = _progress_bar(len(ids)) if progress else None
    try:
        for pid, result in stream:
            results[pid] = result
            if bar is not None:
                bar.update(1)
    finally:
        if hasattr(stream, "close"):
            stream.close()
        if bar is not None:
            bar.close()
    return [results[pid] for pid in ids]


def validate(problems: Iterable[Problem], workers: int | None, backend: str,
             seed: int, start_method: str | None = None,
             ray_address: str | None = None) -> tuple[list[Task], int | None]:
    """(tasks, worker count or None) of a batch; raises before anything starts (see `plan_stream`)."""
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise InvalidInputError(f"backend must be one of {list(BACKENDS)}; got {backend!r}")
    if ray_address is not None:
        if backend != "ray":
            raise InvalidInputError(f'ray_address is an option of backend="ray"; got it with backend={backend!r}')
        if not isinstance(ray_address, str) or not ray_address:
            raise InvalidInputError(f'ray_address must be a ray.init address such as "auto" or "ray://host:10001"; '
                                    f"got {ray_address!r}")
    if start_method is not None:
        if backend != "process":
            raise InvalidInputError(f'start_method is an option of backend="process"; got it with backend={backend!r}')
        process_pool.check_start_method(start_method)
    n = None if workers is None else integer(workers, "workers", 1)
    return prepare(problems, seed), n


def _cores() -> int:
    """CPUs this process may run on (the affinity mask where the OS has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def _progress_bar(total: int) -> Any:
    try:
        from tqdm.auto import tqdm
    except ImportError:
        log.info("planning %d problems (install tqdm for a progress bar)", total)
        return None
    return tqdm(total=total, unit="problem", smoothing=0.05)
