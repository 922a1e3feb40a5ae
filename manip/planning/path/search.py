"""The path-search policy: RRT-Connect coarse-to-fine, with repairs of failing edges.

Most of a planning problem's space is far from obstacles, so the search checks its edges at
the coarse `search_resolution`; the found path is then re-checked at the fine resolution and
every edge that fails is replaced by a fine-resolution search between its endpoints.
"""

from __future__ import annotations

import numpy as np

from manip.planning.path import compiled_search
from manip.planning.path.compiled_search import CompiledChecks
from manip.planning.path.rrt_connect import Sampler, rrt_connect
from manip.planning.validity import ADVANCE_BACKOFF_STEPS, Validity

#: Edges of a coarse search path replaced by fine searches before giving up on the path.
MAX_REPAIRS = 6
#: RRT iterations of a search (and of its repairs together) when the caller gives no count.
MAX_ITERATIONS = 20000
#: The coarse search runs in compiled code (`compiled_search`: the same samples, answers and
#: path) where it can; False: the Python `rrt_connect` always (BENCHMARKS.md, "Round nine").
COMPILED_SEARCH = True
#: The repairs' fine searches run in compiled code too (with `COMPILED_SEARCH`); off: no faster
#: (BENCHMARKS.md, "Round nine").
REPAIRS_COMPILED = False


def compiled_checks(validity: Validity, fine: bool = False) -> CompiledChecks | None:
    """The compiled search's tables for `validity`'s coarse advance (`fine`: its fine one, the
    repairs'), or None where it keeps the Python search: `COMPILED_SEARCH` off, another kind of
    validity or one that changes the advance (a constrained one), a strict one advancing at its
    fine resolution (it certifies), occupancy maps in the world."""
    cls = type(validity)
    if (not COMPILED_SEARCH or not isinstance(validity, Validity) or cls.coarse_advance is not Validity.coarse_advance
            or cls.advance is not Validity.advance or getattr(validity, "steer", None) is not None):
        return None
    resolution = validity.resolution if fine else validity.search_resolution
    if validity.certified and resolution == validity.resolution:
        return None
    state = validity.checker.state
    if state.occupancy_maps or state.every_configuration_collides:
        return None
    return CompiledChecks(state, resolution, ADVANCE_BACKOFF_STEPS,
                          narrowphase=compiled_search.KERNEL_NARROWPHASE and not fine)


def search_path(
    start: np.ndarray, goals: np.ndarray, validity: Validity, rng: np.random.Generator, deadline: float, *,
    max_iterations: int | None = MAX_ITERATIONS,
    max_repair_iterations: int | None = MAX_ITERATIONS,
    sample: Sampler | None = None,
) -> tuple[np.ndarray | None, int]:
    """A collision-free polyline from `start` (dof,) to one of `goals` (G, dof).

    `max_iterations` caps the coarse search and `max_repair_iterations` the fine repair
    searches together (counts, not times: the result depends only on the generator's state,
    unless `deadline`, a `time.perf_counter()` value, comes first); None = MAX_ITERATIONS.
    A repair that runs out of iterations fails the search (None). `sample` replaces the
    coarse search's uniform samples (`rrt_connect`).

    Returns:
        (path (K, dof) valid at the fine resolution, or None; RRT iterations used).
    """
    lower, upper = validity.kinematics.lower, validity.kinematics.upper
    steer = None
    if getattr(validity, "steer", None) is not None:  # a constrained search: steps along the constraint set
        def steer(q0, q1):
            return validity.steer(q0, q1, validity.search_resolution)
    path, iterations = rrt_connect(
        start, goals, lower, upper, validity.coarse_motion, rng, deadline, advance=validity.coarse_advance,
        max_iterations=MAX_ITERATIONS if max_iterations is None else max_iterations, sample=sample, steer=steer,
        compiled=None if steer is not None else compiled_checks(validity),
    )
    if validity.search_resolution == validity.resolution:
        return path, iterations
    path, more = repair_path(path, validity, rng, deadline,
                             max_iterations=MAX_ITERATIONS if max_repair_iterations is None else max_repair_iterations)
    return path, iterations + more


def repair_path(
    path: np.ndarray | None, validity: Validity, rng: np.random.Generator, deadline: float,
    max_iterations: int = MAX_ITERATIONS,
) -> tuple[np.ndarray | None, int]:
    """`path` (K, dof) with its failing segments (by `validity.segments`) replaced by searches.

    The first failing segment is replaced by an RRT-Connect search between its endpoints
    with the fine `validity.motion` / `validity.advance` (certified ones for a strict
    Validity), at most MAX_REPAIRS times; `max_iterations` caps those searches together (a
    count). None when a repair fails or the path still fails after MAX_REPAIRS.

    Returns:
        (the valid path (K', dof) or None; RRT iterations used).
    """
    lower, upper = validity.kinematics.lower, validity.kinematics.upper
    iterations = 0
    compiled = None
    known: dict[bytes, bool] = {}   # the answers of segments checked before (the same endpoints: the same answer)
    for _ in range(MAX_REPAIRS):
        if path is None:
            return None, iterations
        ok = _segments_known(validity, path, known)
        if ok.all():
            return path, iterations
        if iterations >= max_iterations:
            return None, iterations
        s = int(np.argmin(ok))
        if compiled is None and REPAIRS_COMPILED:
            compiled = compiled_checks(validity, fine=True)
        sub, more = rrt_connect(
            path[s], path[s + 1][None], lower, upper, validity.motion, rng, deadline, advance=validity.advance,
            max_iterations=max_iterations - iterations, steer=getattr(validity, "steer", None), compiled=compiled,
        )
        iterations += more
        path = None if sub is None else np.concatenate([path[:s], sub, path[s + 2 :]])
    if path is not None and not validity.path(path):
        path = None
    return path, iterations


def _segments_known(validity: Validity, path: np.ndarray, known: dict[bytes, bool]) -> np.ndarray:
    """(K-1,) `validity.segments` of the segments of `path` (K, dof), those whose endpoints are
    keys of `known` (their two rows' bytes) answered from it; the others checked and added."""
    keys = [path[s:s + 2].tobytes() for s in range(len(path) - 1)]
    ok = np.array([known.get(k, False) for k in keys], dtype=bool)
    new = np.array([k not in known for k in keys], dtype=bool)
    if new.any():
        ok[new] = validity.segments(path[:-1][new], path[1:][new])
        known.update((k, bool(v)) for k, v, n in zip(keys, ok.tolist(), new.tolist()) if n)
    return ok
