"""`generate`: plan a dataset of seeded problems on every core or on a Ray cluster.

The workers of `manip.batch` build each scene, plan and verify its pairs
(`job.plan_scene`, one task per scene); the rows are written here as scenes come back
(`dataset.PartWriter`). Problem ids already in the folder are skipped, so an
interrupted run is resumed by running the same command again; on an interrupt (Ctrl-C)
the rows received so far are written before the workers are stopped. One run writes a
folder at a time (`lock.writer_lock`): a second is refused at once.
"""

from __future__ import annotations

import logging
import time
from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from manip.batch.plan import run_tasks, validate
from manip.batch.problem import BATCH_SEARCH_ITERATIONS, BATCH_TIME_BUDGET
from manip.benchmarking.scenes import SCENE_KINDS
from manip.datagen import dataset
from manip.datagen.job import SceneTask, plan_scene
from manip.datagen.lock import writer_lock
from manip.datagen.problems import check_kinds, plan_ids, problem_id
from manip.errors import UnknownNameError
from manip.planning.options import PlanOptions
from manip.planning.result import PlanStatus
from manip.robot_config import available_robots
from manip.validation import integer

log = logging.getLogger(__name__)

#: The default robot of a dataset.
ROBOT = "franka"


@dataclass(frozen=True)
class Summary:
    """What a `generate` run did.

    Attributes:
        planned: problems planned and written by this run.
        skipped: problems already in the folder.
        succeeded: planned problems with `success`.
        verified: planned problems whose trajectory passed the independent verifier.
        raised: planned problems whose planning raised (rows with status "raised"; the
            message names the problem and the error).
        seconds: wall time of the run [s] (building problems, starting workers, planning, writing).
        workers: worker count (None: all cores / the cluster's CPUs).
    """

    planned: int
    skipped: int
    succeeded: int
    verified: int
    seconds: float
    workers: int | None
    raised: int = 0

    @property
    def rate(self) -> float:
        """Problems planned per second of the run."""
        return self.planned / self.seconds if self.seconds > 0 else float("nan")


def generate(
    out: str | Path,
    *,
    scenes: int = 2,
    problems_per_scene: int = 2,
    kinds: Sequence[str] = SCENE_KINDS,
    seed: int = 0,
    robot: str = ROBOT,
    workers: int | None = None,
    backend: str = "process",
    ray_address: str | None = None,
    time_budget: float = BATCH_TIME_BUDGET,
    search_iterations: int | None = BATCH_SEARCH_ITERATIONS,
    dt: float | None = None,
    rows_per_part: int = 256,
    on_total: Callable[[int], None] | None = None,
    on_row: Callable[[dict], None] | None = None,
) -> Summary:
    """Generate (or complete) a dataset in the folder `out`.

    Args:
        out: dataset folder (created if missing).
        scenes: number of scenes, spread over `kinds` in turn.
        problems_per_scene: start/goal pairs per scene.
        kinds: scene kinds, among `manip.benchmarking.scenes.SCENE_KINDS`.
        seed: dataset seed (scenes, pairs and planning seeds derive from it).
        robot: a shipped robot's name (`manip.available_robots()`); its scenes are the
            Franka's scaled by its reach.
        workers: workers (None: all cores, or the Ray cluster's CPUs).
        backend: "process" or "ray".
        ray_address: `ray.init` address for backend="ray" (None: a local Ray instance).
        time_budget: planning wall-time budget per problem [s], a safety net (a row planned
            past it has `planning.context.SAFETY_NET` in its message).
        search_iterations: RRT iterations of a plan's main search (`PlanOptions.search_iterations`;
            a count: the dataset is the same on any machine); None = until the time budget.
        dt: sample period of the trajectories [s]; None = the planner's default (1/60 s). A
            problem whose motion would have more than `manip.validation.MAX_SAMPLES` samples
            raises in its worker and is written as a failed row (status "raised").
        rows_per_part: rows per Parquet part file.
        on_total: called once with the number of problems to plan (e.g. to size a progress bar).
        on_row: called with each row once it is buffered for writing.

    Returns:
        A `Summary`.

    Raises:
        UnknownNameError: `robot` is not a shipped robot (the message lists them).
        InvalidInputError: bad arguments, or `out` holds a dataset made with other settings.
        DatasetBusyError: another run is writing `out` (`manip.datagen.lock`: one writer per
            folder; a run that ended, even by a crash, holds nothing).
    """
    t0 = time.perf_counter()
    kinds = check_kinds(kinds)
    seed = integer(seed, "seed", 0)
    rows_per_part = integer(rows_per_part, "rows_per_part", 1)
    if not isinstance(robot, str) or robot not in available_robots():
        raise UnknownNameError("robot", str(robot), available_robots())
    ids = plan_ids(kinds, scenes, problems_per_scene)
    _, n = validate([], workers, backend, seed, ray_address=ray_address)  # bad settings fail before any work
    checked = PlanOptions(time_budget=time_budget, search_iterations=search_iterations,
                          **({} if dt is None else {"dt": dt}))  # bad values raise here
    options = {"time_budget": checked.time_budget, "search_iterations": checked.search_iterations,
               **({} if dt is None else {"dt": checked.dt})}
    settings = {"seed": seed, "kinds": list(kinds), "problems_per_scene": problems_per_scene, "robot": robot,
                **options}
    with writer_lock(dataset.create_folder(out)) as folder:  # one writer per folder
        return _generate(folder, settings, ids, robot=robot, seed=seed, options=options, n=n, backend=backend,
                         ray_address=ray_address, rows_per_part=rows_per_part, on_total=on_total, on_row=on_row, t0=t0)


def _generate(folder: Path, settings: dict, ids: list[tuple[str, int, int]], *, robot: str, seed: int,
              options: dict, n: int | None, backend: str, ray_address: str | None, rows_per_part: int,
              on_total: Callable[[int], None] | None, on_row: Callable[[dict], None] | None, t0: float) -> Summary:
    """`generate` once the arguments are checked and the folder is locked."""
    dataset.open_folder(folder, settings)
    done = dataset.finished_ids(folder)
    wanted = [t for t in ids if problem_id(*t) not in done]
    skipped = len(ids) - len(wanted)
    if on_total is not None:
        on_total(len(wanted))
    pairs: dict[tuple[str, int], list[int]] = defaultdict(list)
    for kind, scene, pair in wanted:
        pairs[(kind, scene)].append(pair)
    tasks = [SceneTask(f"{kind}-{scene:06d}", robot, kind, scene, tuple(ps), seed, options)
             for (kind, scene), ps in pairs.items()]
    writer = dataset.PartWriter(folder, rows_per_part)
    succeeded = verified = raised = 0
    stream = run_tasks(tasks, workers=n, backend=backend, ray_address=ray_address, job=plan_scene)
    try:
        for _, planned in stream:
            for problem, problem_seed, result, verdict in planned:
                row = dataset.make_row(problem, problem_seed, robot, result, verdict)
                writer.add(row)
                succeeded += bool(result.success)
                verified += verdict.verified
                raised += result.status is PlanStatus.RAISED
                if on_row is not None:
                    on_row(row)
    finally:
        writer.flush()  # keep what arrived, also on Ctrl-C
        if hasattr(stream, "close"):
            stream.close()
    return Summary(writer.written, skipped, succeeded, verified, time.perf_counter() - t0, n, raised)
