"""More path searches when the first one took a long way round.

RRT-Connect finds some path; shortcutting only straightens it within its homotopy class (the
way it goes round the obstacles: over or under a bar of a cage, left or right of a post).
When the shortened path still takes much longer than the straight line would (a detour),
a few more short searches may find a shorter way round, drawing their global samples only
where a path shorter than the current one can pass (`rrt_connect.informed_sampler`: the
ellipsoid of the path's joint length around its start and goal), towards the goals closer
than that length; the fastest of the shortened candidates is kept. Only detours pay for the
searches (the measurements behind the constants: BENCHMARKS.md, "Constants").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from manip.planning.path.rrt_connect import informed_sampler
from manip.planning.path.search import search_path
from manip.planning.path.shortcut import path_length
from manip.planning.validity import Validity

#: A path taking longer than this times the straight line (in `time_length`) is a detour.
DETOUR = 1.5
#: Further searches for a detour.
SEARCHES = 2
#: RRT iterations of each further search (a count: results do not depend on the machine).
ITERATIONS = 300
#: RRT iterations of the fine-resolution repairs of each further search, together (a count).
REPAIR_ITERATIONS = 200
#: A candidate replaces the path only when it takes at most this fraction of its time (a
#: small gain in `time_length` is within what the optimiser changes anyway).
GAIN = 0.9


def time_length(path: np.ndarray, vmax: np.ndarray) -> float:
    """The duration [s] of a (K, dof) path at the velocity limits vmax (dof,), stopping at
    no waypoint and ignoring acceleration: a cheap proxy of its motion time."""
    return float(np.sum(np.max(np.abs(np.diff(path, axis=0)) / vmax, axis=1)))


def shorter_way_round(
    path: np.ndarray,
    goals: np.ndarray,
    validity: Validity,
    shorten: Callable[[np.ndarray], np.ndarray],
    *,
    rng: np.random.Generator,
    deadline: float,
    velocity: np.ndarray,
) -> np.ndarray:
    """`path`, or a faster valid path between its start and one of `goals` when it is a detour.

    Args:
        path: (K, dof) a valid shortened path [rad].
        goals: (G, dof) the configurations the searches may reach [rad].
        validity: the plan's validity questions (see `search_path`).
        shorten: the plan's shortcutting, path (K, dof) -> shorter valid path.
        rng: the plan's generator (the searches draw from it only for a detour, so a plan
            without one is unchanged).
        deadline: `time.perf_counter()` value at which to stop.
        velocity: (dof,) the call's velocity limits [rad/s].
    Returns:
        (K', dof) the fastest of `path` and the shortened candidates (by `time_length`).
    """
    start = path[0]
    best = time_length(path, velocity)
    for _ in range(SEARCHES):
        if best <= DETOUR * time_length(np.stack([start, path[-1]]), velocity):
            break  # no (longer a) detour
        length = path_length(path)
        roots = goals[np.linalg.norm(goals - start, axis=1) <= length]  # path[-1] among them
        sample = informed_sampler(start, path[-1], length, validity.kinematics.lower, validity.kinematics.upper)
        candidate, _ = search_path(start, roots, validity, rng, deadline, max_iterations=ITERATIONS,
                                   max_repair_iterations=REPAIR_ITERATIONS, sample=sample)
        if candidate is None:
            continue
        if len(candidate) > 2:
            candidate = shorten(candidate)
        length = time_length(candidate, velocity)
        if length <= GAIN * best:
            path, best = candidate, length
    return path
