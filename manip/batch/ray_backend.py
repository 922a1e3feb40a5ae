"""The Ray backend: long-lived planning actors on a Ray cluster (or a local Ray instance).

Each actor (one CPU) warms up once (`worker.warm_up`) and keeps its generators for its
life; the driver keeps `INFLIGHT_PER_WORKER` calls queued per actor, each with up to `CHUNK`
problems, and streams results back with `ray.wait`. An actor gets work once it has started:
with more workers than the cluster has CPUs, the extra actors wait for a CPU (a warning is
logged) and the others plan the batch; those that never started are stopped at its end.
Actors, not tasks: a Ray task may land on a fresh worker process that would compile or load
its kernels inside a problem's time budget (see BENCHMARKS.md for the measured difference).

Warm actors across batches: an actor is a fresh interpreter that imports manip and loads
its kernels (about 2 s of CPU) before its first result, while a batch of 200 problems
plans in 4-7 s on two CPUs. So when the caller runs Ray itself (`ray.init` before the
batch), the actors a batch used stay alive and warm for `KEEP_WARM` seconds and the next
batch of this process in the same Ray session starts on them at once (measured in
BENCHMARKS.md, "Batch planning"). While kept, each holds its CPU of the cluster: other Ray
work waits for it until `release_actors()`, the idle timeout, `ray.shutdown()` or the end
of this process. A batch takes the kept actors it needs (the others stay kept) and starts
new ones for the rest; a batch that ends while another batch of this process runs stops its
actors (the other may be waiting for their CPUs). A Ray runtime started here (no `ray.init`
before) is shut down at the end of the batch, with its actors.

Faults: an actor whose process or node dies is restarted by Ray (`max_restarts`) and the
task it was running is retried (`max_task_retries`), on the restarted actor, which Ray
places on a live node. A task whose retries run out goes back to the driver's queue for
another actor; `WorkerLostError` after `MAX_ATTEMPTS` of those. A kept actor is checked
(`PING_TIMEOUT`) before a batch uses it, and replaced if it died while idle. On
KeyboardInterrupt (or any exception, or the stream closed early) the batch's actors are
killed, not kept.

Thread safety: batches may run on several threads of one process; the kept actors are
handed out under a lock (each to one batch at a time).
"""

from __future__ import annotations

import logging
import os
import threading
from collections import deque
from collections.abc import Iterator, Sequence
from typing import Any

from manip.batch import worker
from manip.batch.problem import ProblemId, RobotSpec, Task
from manip.batch.process_pool import INFLIGHT_PER_WORKER, MAX_ATTEMPTS, Job, WorkerLostError
from manip.errors import ManipError

log = logging.getLogger(__name__)

#: Seconds the actors of a finished batch stay warm for the next batch of this process (in
#: the same Ray session, which the caller started); 0 = stop them at the end of every batch.
KEEP_WARM = 30.0
#: Tasks per actor call at most (fewer near the end of a batch). One call costs the driver and
#: the actor about 2 ms of CPU (serialisation, scheduling), against plans of about 30 ms.
CHUNK = 4
#: Seconds a batch waits for its kept actors to answer (one that is gone is replaced; one that
#: has not answered yet, e.g. restarted and warming up again, is used all the same).
PING_TIMEOUT = 10.0

# Idle warm actors kept between batches: their Ray session, the handles, the timer that
# releases them, and the number of batches of this process running on Ray.
_lock = threading.Lock()
_kept: list[Any] = []
_kept_session: tuple[str, str] | None = None
_timer: threading.Timer | None = None
_active = 0


def import_ray() -> Any:
    """The `ray` module, or a ManipError saying how to install it."""
    try:
        import ray
    except ImportError as exc:
        raise ManipError('backend="ray" needs Ray: pip install "manip-robotics[ray]"') from exc
    return ray


class PlanActor:
    """A Ray actor holding warm motion generators (wrapped by `ray.remote` in `start_actors`)."""

    def __init__(self, robots: tuple[str | RobotSpec, ...]):
        worker.start(robots)

    def warm(self, robots: tuple[str | RobotSpec, ...]) -> int:
        """Warm up the generators of `robots` this actor has not warmed yet; its process id."""
        worker.warm_up(robots)
        return os.getpid()

    def solve_many(self, tasks: list[Task], job: Job = worker.solve) -> list[tuple[ProblemId, Any]]:
        """`job(task)` (default `worker.solve`) for each of `tasks`, in order, in the actor's
        process (one Ray call for several problems)."""
        return [job(task) for task in tasks]

    def pid(self) -> int:
        """The actor's process id."""
        return os.getpid()


def start_actors(workers: int, robots: tuple[str | RobotSpec, ...]) -> list[Any]:
    """Start `workers` planning actors of one CPU each (they warm up in the background)."""
    ray = import_ray()
    actor = ray.remote(num_cpus=1, max_restarts=MAX_ATTEMPTS, max_task_retries=MAX_ATTEMPTS)(PlanActor)
    return [actor.remote(robots) for _ in range(workers)]


def release_actors() -> int:
    """Stop the warm actors kept after the last Ray batch of this process (see the module
    docstring); returns how many were stopped. Safe to call at any time, from any thread."""
    with _lock:
        actors = _take_kept(None)
        _arm_timer()  # cancels it (nothing is kept)
    _kill(actors)
    return len(actors)


def kept_actors() -> list[Any]:
    """The handles of the actors kept warm now (a copy of the list)."""
    with _lock:
        return list(_kept)


def run(tasks: Sequence[Any], workers: int | None, address: str | None = None,
        actors: list[Any] | None = None, job: Job = worker.solve) -> Iterator[tuple[ProblemId, Any]]:
    """Plan `tasks` on Ray actors; yield (id, result) as plans finish.

    Args:
        tasks: validated tasks (a `Task`, or a job's own picklable task type with `id` and `robot`).
        workers: number of actors (None: the cluster's CPUs); no more are used than
            there are tasks.
        address: passed to `ray.init` when Ray is not initialised yet (None: a local
            instance; "auto" or "ray://host:10001": an existing cluster).
        actors: actors from `start_actors` to use (they are left running, never kept);
            None = actors kept warm from an earlier batch, and new ones as needed.
        job: the function run on each task (module level, importable on the cluster).

    Yields:
        (problem id, job's result), each task exactly once, in order of completion.

    Raises:
        WorkerLostError: a task failed on `MAX_ATTEMPTS` actors.
    """
    global _active
    ray = import_ray()
    started = not ray.is_initialized()
    if started:
        ray.init(address=address, log_to_driver=False)
    own = actors is None
    robots = tuple(sorted({t.robot for t in tasks}, key=str))
    dead: set[int] = set()
    ready: set[int] = set()
    finished = oversubscribed = False
    if own:
        with _lock:
            _active += 1
            if _timer is not None:  # kept actors stay until this batch ends
                _timer.cancel()
    try:
        if own:
            cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
            n = min(workers or cpus, max(1, len(tasks)))
            oversubscribed = n > cpus
            if oversubscribed:
                log.warning("%d Ray actors of one CPU asked for; the cluster has %d CPUs: the others start when "
                            "CPUs free up (or nodes join)", n, cpus)
            actors, answered = _actors(ray, n, robots)
            ready.update(range(answered))
        yield from _dispatch(ray, tasks, list(actors), job, dead, ready)
        finished = True
    finally:
        if own:
            # not kept: actors that died, and with more actors than CPUs those that never started
            # (waiting for a CPU); one still starting in a small batch is kept
            gone = [i in dead or (oversubscribed and i not in ready) for i in range(len(actors or []))]
            _kill([a for a, g in zip(actors or [], gone) if g])
            _finish(ray, [a for a, g in zip(actors or [], gone) if not g], finished and not started)
        if started:
            ray.shutdown()


def _session(ray: Any) -> tuple[str, str]:
    """The Ray session this process is connected to (actors of another one are gone)."""
    context = ray.get_runtime_context()
    return str(context.gcs_address), str(context.get_job_id())


def _take_kept(session: tuple[str, str] | None) -> list[Any]:
    """Empty the kept list (under `_lock`); its actors if they belong to `session` (None: any)."""
    global _kept, _kept_session
    actors = _kept if session is None or _kept_session == session else []
    _kept, _kept_session = [], None
    return actors


def _actors(ray: Any, n: int, robots: tuple[str | RobotSpec, ...]) -> tuple[list[Any], int]:
    """`n` actors for a batch: kept warm ones (those that answered a ping first), then new
    ones; and how many answered (they need no other ping before they get work)."""
    global _kept, _kept_session
    session = _session(ray)
    with _lock:
        kept = _take_kept(session)
        reuse = kept[:n]
        if kept[n:]:  # more kept than needed: they stay kept for other batches
            _kept, _kept_session = kept[n:], session
    alive, late = [], []
    if reuse:
        pings = {a.pid.remote(): a for a in reuse}
        answered, pending = ray.wait(list(pings), num_returns=len(pings), timeout=PING_TIMEOUT)
        for ref in answered:
            try:
                ray.get(ref)
                alive.append(pings[ref])
            except ray.exceptions.RayError as exc:
                log.warning("a kept actor is gone (%s); starting a new one", type(exc).__name__)
                _kill([pings[ref]])
        # busy or still starting (a restarted actor warms up again): used once it answers
        late = [pings[ref] for ref in pending]
        if late:
            log.info("%d kept actors did not answer within %.0f s", len(late), PING_TIMEOUT)
        for a in alive + late:
            a.warm.remote(robots)  # robots new to the actor (runs before the batch's tasks)
    return alive + late + start_actors(n - len(alive) - len(late), robots), len(alive)


def _finish(ray: Any, actors: list[Any], keep: bool) -> None:
    """The end of a batch that started its own actors: keep its live `actors` warm for
    `KEEP_WARM` s if `keep` and no other batch of this process runs (it may be waiting for
    their CPUs), else stop them."""
    global _kept, _kept_session, _active
    session = None
    if keep:
        try:
            session = _session(ray)
        except Exception as exc:  # Ray shut down meanwhile (by another thread): nothing to keep
            log.debug("no Ray session: %s", exc)
            keep = False
    with _lock:
        _active -= 1
        keep = keep and KEEP_WARM > 0 and _active == 0 and _kept_session in (None, session)
        if keep:
            _kept, _kept_session = _kept + actors, session
        _arm_timer()
    if not keep:
        _kill(actors)


def _arm_timer() -> None:
    """(Under `_lock`.) Release the kept actors after `KEEP_WARM` s unless a batch takes them."""
    global _timer
    if _timer is not None:
        _timer.cancel()
        _timer = None
    if _kept:
        _timer = threading.Timer(KEEP_WARM, release_actors)
        _timer.daemon = True
        _timer.start()


def _kill(actors: list[Any]) -> None:
    if not actors:
        return
    ray = import_ray()
    if not ray.is_initialized():
        return  # their session is over: they are gone with it
    for a in actors:
        try:
            ray.kill(a, no_restart=True)
        except Exception as exc:  # an actor of an earlier session, or already gone
            log.debug("ray.kill: %s", exc)


def _dispatch(ray: Any, tasks: Sequence[Any], actors: list[Any], job: Job, dead: set[int],
              ready: set[int]) -> Iterator[tuple[ProblemId, Any]]:
    """Run `tasks` on `actors`, `CHUNK` at most per call. An actor gets work once it has
    started (answered a ping): one that waits for a CPU the cluster does not have (more
    workers than CPUs) gets none, and the others finish the batch. The indices of actors
    that started are added to `ready` (those in it already are not pinged again), of those
    that died for good to `dead`."""
    queue = deque(tasks)
    attempts: dict[ProblemId, int] = {}
    load = [0] * len(actors)
    inflight: dict[Any, tuple[list[Any], int]] = {}
    starting = {actors[a].pid.remote(): a for a in range(len(actors)) if a not in dead | ready}
    lost: Exception | None = None
    while queue or inflight:
        live = sorted(ready - dead, key=load.__getitem__)
        for a in live:
            while queue and load[a] < INFLIGHT_PER_WORKER:
                # smaller calls towards the end of the batch, so that the actors finish together
                k = max(1, min(CHUNK, len(queue) // (2 * INFLIGHT_PER_WORKER * len(live))))
                chunk = [queue.popleft() for _ in range(min(k, len(queue)))]
                for task in chunk:
                    attempts[task.id] = attempts.get(task.id, 0) + 1
                inflight[actors[a].solve_many.remote(chunk, job)] = (chunk, a)
                load[a] += 1
        if not inflight and not starting:
            raise WorkerLostError(f"every actor died; {len(queue)} problems not planned (last error: {lost})")
        done, _ = ray.wait([*inflight, *starting], num_returns=1)
        for ref in done:
            if ref in starting:
                a = starting.pop(ref)
                try:
                    ray.get(ref)
                    ready.add(a)
                except ray.exceptions.RayError as exc:  # it could not start (its restarts are used up)
                    log.warning("an actor failed to start: %s", exc)
                    dead.add(a)
                    lost = exc
                continue
            chunk, a = inflight.pop(ref)
            load[a] -= 1
            try:
                results = ray.get(ref)
            except ray.exceptions.RayTaskError as exc:  # the planning code raised: a bug, not a fault
                raise exc.as_instanceof_cause() from None
            except ray.exceptions.RayError as exc:  # the actor (process or node) died, retries exhausted
                lost = exc
                if isinstance(exc, ray.exceptions.ActorDiedError):
                    dead.add(a)  # its restarts are used up: no more tasks for it
                hopeless = [t.id for t in chunk if attempts[t.id] >= MAX_ATTEMPTS]
                if hopeless:
                    raise WorkerLostError(f"problems {hopeless} failed on {MAX_ATTEMPTS} actors: {exc}") from exc
                log.warning("problems %s: actor lost (%s); resubmitting", [t.id for t in chunk], type(exc).__name__)
                queue.extendleft(reversed(chunk))
                continue
            yield from results
