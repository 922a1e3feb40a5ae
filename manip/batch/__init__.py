"""Plan many problems at once: every core of this machine, or a Ray cluster.

`plan_many(problems, workers=..., backend="process" | "ray", seed=...)` returns the
`PlanResult`s of the single calls in input order; `plan_stream` yields (id, result) as plans
finish. A `Problem` is a world, a start, a goal (joints or a Pose), a robot and options.
Workers are long-lived and keep one warm `MotionGenerator` per robot; a problem's seed is
derived from the batch seed and its id (`problem_seed`), and its search is bounded by a count
(`BATCH_OPTIONS`), so results do not depend on the backend, the worker count, the order of
completion or the machine's speed (unless the time budget, a safety net, runs out: the
result's message says so). With Ray, the actors stay warm between the batches of a process
(`ray_backend.KEEP_WARM` s; `release_ray_actors()` stops them now). See `python -m manip.datagen` for datasets.
"""

from __future__ import annotations

from manip.batch.plan import BACKENDS, plan_many, plan_stream
from manip.batch.problem import BATCH_OPTIONS, Problem, ProblemId, problem_seed
from manip.batch.process_pool import WorkerLostError
from manip.batch.ray_backend import release_actors as release_ray_actors

__all__ = ["BACKENDS", "BATCH_OPTIONS", "Problem", "ProblemId", "WorkerLostError", "plan_many", "plan_stream", "problem_seed",
           "release_ray_actors"]
