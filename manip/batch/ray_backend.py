"""The Ray backend: long-lived planning actors on a Ray cluster (or a local Ray instance).

Each actor (one CPU) warms up once (`worker.warm_up`) and keeps its generators for its
life; the driver keeps `INFLIGHT_PER_WORKER` tasks queued per actor and streams results
back with `ray.wait`. Actors, not tasks: a Ray task may land on a fresh worker process that
would compile or load its kernels inside a problem's time budget (see BENCHMARKS.md for
the measured difference).

Faults: an actor whose process or node dies is restarted by Ray (`max_restarts`) and the
task it was running is retried (`max_task_retries`), on the restarted actor, which Ray
places on a live node. A task whose retries run out goes back to the driver's queue for
another actor; `WorkerLostError` after `MAX_ATTEMPTS` of those. On KeyboardInterrupt the
actors are killed. A Ray runtime started here (no `ray.init` before) is shut down at the end.
"""

from __future__ import annotations

import logging
import os
from collections import deque
from collections.abc import Iterator, Sequence
from typing import Any

from manip.batch import worker
from manip.batch.problem import ProblemId, RobotSpec, Task
from manip.batch.process_pool import INFLIGHT_PER_WORKER, MAX_ATTEMPTS, Job, WorkerLostError
from manip.errors import ManipError

log = logging.getLogger(__name__)


def import_ray() -> Any:
    """The `ray` module, or a ManipError saying how to install it."""
    try:
        import ray
    except ImportError as exc:
        raise ManipError('backend="ray" needs Ray: pip install "manip[ray]"') from exc
    return ray


class PlanActor:
    """A Ray actor holding warm motion generators (wrapped by `ray.remote` in `run`)."""

    def __init__(self, robots: tuple[str | RobotSpec, ...]):
        worker.start(robots)

    def solve(self, task: Task, job: Job = worker.solve) -> tuple[ProblemId, Any]:
        """`job(task)` (default `worker.solve`) in the actor's process."""
        return job(task)

    def pid(self) -> int:
        """The actor's process id."""
        return os.getpid()


def start_actors(workers: int, robots: tuple[str | RobotSpec, ...]) -> list[Any]:
    """Start `workers` planning actors of one CPU each (they warm up in the background)."""
    ray = import_ray()
    actor = ray.remote(num_cpus=1, max_restarts=MAX_ATTEMPTS, max_task_retries=MAX_ATTEMPTS)(PlanActor)
    return [actor.remote(robots) for _ in range(workers)]


def run(tasks: Sequence[Any], workers: int | None, address: str | None = None,
        actors: list[Any] | None = None, job: Job = worker.solve) -> Iterator[tuple[ProblemId, Any]]:
    """Plan `tasks` on Ray actors; yield (id, result) as plans finish.

    Args:
        tasks: validated tasks (a `Task`, or a job's own picklable task type with `id` and `robot`).
        workers: number of actors (None: the cluster's CPUs); no more are started than
            there are tasks.
        address: passed to `ray.init` when Ray is not initialised yet (None: a local
            instance; "auto" or "ray://host:10001": an existing cluster).
        actors: actors from `start_actors` to use (they are left running); None = start them.
        job: the function run on each task (module level, importable on the cluster).

    Yields:
        (problem id, job's result), each task exactly once, in order of completion.

    Raises:
        WorkerLostError: a task failed on `MAX_ATTEMPTS` actors.
    """
    ray = import_ray()
    started = not ray.is_initialized()
    if started:
        ray.init(address=address, log_to_driver=False)
    own = actors is None
    try:
        if own:
            n = min(workers or max(1, int(ray.cluster_resources().get("CPU", 1))), max(1, len(tasks)))
            actors = start_actors(n, tuple(sorted({t.robot for t in tasks}, key=str)))
        yield from _dispatch(ray, tasks, list(actors), job)
    finally:
        if own and actors:
            for a in actors:
                ray.kill(a, no_restart=True)
        if started:
            ray.shutdown()


def _dispatch(ray: Any, tasks: Sequence[Any], actors: list[Any], job: Job) -> Iterator[tuple[ProblemId, Any]]:
    queue = deque(tasks)
    attempts: dict[ProblemId, int] = {}
    load = [0] * len(actors)
    dead: set[int] = set()
    inflight: dict[Any, tuple[Task, int]] = {}
    while queue or inflight:
        for a in sorted(set(range(len(actors))) - dead, key=load.__getitem__):
            while queue and load[a] < INFLIGHT_PER_WORKER:
                task = queue.popleft()
                attempts[task.id] = attempts.get(task.id, 0) + 1
                inflight[actors[a].solve.remote(task, job)] = (task, a)
                load[a] += 1
        if not inflight:
            raise WorkerLostError(f"every actor died; {len(queue)} problems not planned")
        ready, _ = ray.wait(list(inflight), num_returns=1)
        for ref in ready:
            task, a = inflight.pop(ref)
            load[a] -= 1
            try:
                yield ray.get(ref)
            except ray.exceptions.RayTaskError as exc:  # the planning code raised: a bug, not a fault
                raise exc.as_instanceof_cause() from None
            except ray.exceptions.RayError as exc:  # the actor (process or node) died, retries exhausted
                if isinstance(exc, ray.exceptions.ActorDiedError):
                    dead.add(a)  # its restarts are used up: no more tasks for it
                if attempts[task.id] >= MAX_ATTEMPTS:
                    raise WorkerLostError(f"problem {task.id!r} failed on {MAX_ATTEMPTS} actors: {exc}") from exc
                log.warning("problem %r: actor lost (%s); resubmitting", task.id, type(exc).__name__)
                queue.appendleft(task)
