"""Plan many problems at once: every core of this machine, or a Ray cluster.

`plan_many(problems, workers=..., backend="process" | "ray", seed=...)` returns the
`PlanResult`s of the single calls in input order; `plan_stream` yields (id, result) as plans
finish. A `Problem` is a world, a start, a goal (joints or a Pose), a robot and options.
Workers are long-lived and keep one warm `MotionGenerator` per robot; a problem's seed is
derived from the batch seed and its id (`problem_seed`), so results do not depend on the
backend, the worker count or the order of completion. See `python -m manip.datagen` for
datasets.
"""

from __future__ import annotations

from manip.batch.plan import BACKENDS, plan_many, plan_stream
from manip.batch.problem import Problem, ProblemId, problem_seed
from manip.batch.process_pool import WorkerLostError

__all__ = ["BACKENDS", "Problem", "ProblemId", "WorkerLostError", "plan_many", "plan_stream", "problem_seed"]
