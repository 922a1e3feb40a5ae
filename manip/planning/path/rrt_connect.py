"""RRT-Connect (Kuffner & LaValle, 2000) in joint space, with several goal roots.

The planner only sees two callables: a straight-segment validity check and a time source,
so it works with any collision checker. Trees grow towards uniform samples; each extension
is checked as a straight segment (the checker decides the resolution).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

MotionCheck = Callable[[np.ndarray, np.ndarray], bool]
Advance = Callable[[np.ndarray, np.ndarray], "np.ndarray | None"]
Sampler = Callable[[np.random.Generator], np.ndarray]
Steer = Callable[[np.ndarray, np.ndarray], "np.ndarray | None"]

#: Share of the samples drawn near a random node of the growing tree, and their spread
#: (Gaussian, per joint) [rad] (BENCHMARKS.md, "Constants").
LOCAL_FRACTION = 0.5
LOCAL_SIGMA = 0.5


class _Tree:
    """Nodes (K, dof) with parent indices; grows by doubling its arrays."""

    def __init__(self, roots: np.ndarray):
        roots = np.atleast_2d(roots)
        cap = max(256, 2 * len(roots))
        self.nodes = np.empty((cap, roots.shape[1]))
        self.parents = np.empty(cap, dtype=int)
        self.n = len(roots)
        self.nodes[: self.n] = roots
        self.parents[: self.n] = -1

    def add(self, q: np.ndarray, parent: int) -> int:
        if self.n == len(self.nodes):
            self.nodes = np.concatenate([self.nodes, np.empty_like(self.nodes)])
            self.parents = np.concatenate([self.parents, np.empty_like(self.parents)])
        self.nodes[self.n] = q
        self.parents[self.n] = parent
        self.n += 1
        return self.n - 1

    def nearest(self, q: np.ndarray) -> int:
        d = self.nodes[: self.n] - q
        return int(np.argmin(np.einsum("ij,ij->i", d, d)))

    def branch(self, i: int) -> list[np.ndarray]:
        """Configurations from node i back to its root."""
        out = []
        while i >= 0:
            out.append(self.nodes[i].copy())
            i = int(self.parents[i])
        return out


def _steer(q_from: np.ndarray, q_to: np.ndarray, step: float) -> tuple[np.ndarray, bool]:
    d = q_to - q_from
    dist = float(np.linalg.norm(d))
    if dist <= step:
        return q_to.copy(), True
    return q_from + d * (step / dist), False


def rrt_connect(
    start: np.ndarray,
    goals: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    motion_valid: MotionCheck,
    rng: np.random.Generator,
    deadline: float,
    *,
    advance: Advance | None = None,
    step_size: float = 1.5,
    short_step: float = 0.1,
    local_fraction: float = LOCAL_FRACTION,
    local_sigma: float = LOCAL_SIGMA,
    max_iterations: int = 20000,
    sample: Sampler | None = None,
    steer: Steer | None = None,
    compiled=None,
) -> tuple[np.ndarray | None, int]:
    """Find a collision-free piecewise-linear path from `start` to any of `goals`.

    Each iteration extends one tree towards a sample by at most `step_size` and then pulls
    the other tree towards the new node as far as it can go ("connect"). With `advance`
    (a checker that returns the farthest valid configuration along a segment) both moves
    stop just before the first collision instead of failing, in one call each.

    Args:
        start: (dof,) valid start configuration.
        goals: (G, dof) valid goal configurations (all roots of the goal tree).
        lower, upper: (dof,) joint limits for sampling [rad].
        motion_valid: `f(q0, q1) -> bool` for the straight segment q0 -> q1.
        rng: the random generator (determinism).
        deadline: `time.perf_counter()` value after which the search gives up.
        advance: `f(q0, q1) -> q or None`: the farthest configuration towards q1 whose
            segment from q0 is valid (None when no progress is possible). Optional.
        step_size: maximum extension length (joint-space L2) [rad].
        short_step: extension length tried when a full step is blocked [rad] (without
            `advance`).
        local_fraction: share of samples drawn near an existing node of the growing tree
            (Gaussian, `local_sigma` [rad]), which lets trees leave narrow pockets such as
            a hand deep in a shelf.
        max_iterations: bound on sampling iterations.
        sample: `f(rng) -> q (dof,)`, the global samples (default: uniform within the
            joint limits), e.g. `informed_sampler`'s set of shorter paths.
        compiled: a `compiled_search.CompiledChecks` of the same check as `advance`: the
            search runs in compiled code (`compiled_search`; the same samples and answers)
            unless `steer` is given or `sample` is neither None nor an `InformedSampler`.

    Returns:
        (path (K, dof) from start to a goal, or None; iterations used).
    """
    if compiled is not None and steer is None and (sample is None or isinstance(sample, InformedSampler)):
        from manip.planning.path.compiled_search import compiled_rrt_connect

        return compiled_rrt_connect(start, goals, lower, upper, compiled, rng, deadline, step_size=step_size,
                                    local_fraction=local_fraction, local_sigma=local_sigma,
                                    max_iterations=max_iterations, sample=sample)
    trees = [_Tree(start[None, :]), _Tree(goals)]
    a, b = 0, 1  # tree `a` extends towards the sample, `b` connects to it

    def extend(tree: _Tree, i: int, target: np.ndarray, limit: float | None) -> int | None:
        """Grow `tree` from node i towards target (at most `limit` far); new node index or None."""
        q_from = tree.nodes[i]
        q_to = target if limit is None else _steer(q_from, target, limit)[0]
        if steer is not None:  # a chain of nodes along the constraint set
            chain = steer(q_from, q_to)
            if chain is None:
                return None
            for q in chain:
                i = tree.add(q, i)
            return i
        if advance is not None:  # one call: the whole segment when it is free
            q_stop = advance(q_from, q_to)
        elif motion_valid(q_from, q_to):
            return tree.add(q_to, i)
        else:
            q_stop = _steer(q_from, q_to, short_step)[0]
            if not motion_valid(q_from, q_stop):
                q_stop = None
        if q_stop is None or np.linalg.norm(q_stop - q_from) < 1e-6:
            return None
        return tree.add(q_stop, i)

    for it in range(1, max_iterations + 1):
        if time.perf_counter() > deadline:
            return None, it
        ta, tb = trees[a], trees[b]
        if rng.random() < local_fraction:
            q_rand = np.clip(ta.nodes[rng.integers(ta.n)] + rng.normal(0.0, local_sigma, len(lower)), lower, upper)
        elif sample is None:
            q_rand = rng.uniform(lower, upper)
        else:
            q_rand = sample(rng)
        i_new = extend(ta, ta.nearest(q_rand), q_rand, step_size)
        if i_new is not None:
            q_new = ta.nodes[i_new]
            j = extend(tb, tb.nearest(q_new), q_new, None)
            if j is not None and np.array_equal(tb.nodes[j], q_new):
                branch_a = ta.branch(i_new)[::-1]   # root_a ... q_new
                branch_b = tb.branch(j)             # q_new ... root_b
                path = branch_a + branch_b[1:]
                if a == 1:
                    path = path[::-1]
                return np.asarray(path), it
        a, b = b, a
    return None, max_iterations


class InformedSampler:
    """Uniform samples of the configurations through which a path from `start` to `goal`
    can be shorter than `length` (Informed RRT*, Gammell et al. 2014): call it with the
    generator for one (dof,) sample.

    That set is the prolate hyperspheroid with foci `start` and `goal` (dof,) [rad] and
    transverse diameter `length` [rad] (joint-space L2): a unit-ball sample scaled by its
    radii and turned so that its first axis runs from start to goal. A sample outside the
    joint limits `lower`, `upper` (dof,) is drawn again, at most `tries` times, then clipped.
    A `length` at most the straight line's gives samples on the segment. `centre` (dof,) and
    `shape` (dof, dof) (a unit-ball sample x maps to centre + shape @ x) are what the compiled
    search (`compiled_search`) draws with.
    """

    def __init__(self, start: np.ndarray, goal: np.ndarray, length: float, lower: np.ndarray, upper: np.ndarray,
                 tries: int = 8):
        start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
        dof = len(start)
        c_min = float(np.linalg.norm(goal - start))
        self.centre = 0.5 * (start + goal)
        radii = np.full(dof, 0.5 * np.sqrt(max(length * length - c_min * c_min, 0.0)))
        radii[0] = 0.5 * max(length, c_min)
        # a Householder reflection taking the first axis onto start -> goal (any orthogonal map
        # keeps the distribution uniform)
        turn = np.eye(dof)
        if c_min > 1e-12:
            v = np.eye(dof)[0] - (goal - start) / c_min
            if float(v @ v) > 1e-24:
                turn -= 2.0 * np.outer(v, v) / float(v @ v)
        self.shape = np.ascontiguousarray(turn * radii)  # columns scaled: turn @ diag(radii)
        if int(tries) < 1:
            raise ValueError(f"tries must be >= 1; got {tries}")
        self.lower, self.upper, self.tries = lower, upper, int(tries)

    def __call__(self, rng: np.random.Generator) -> np.ndarray:
        dof = len(self.centre)
        for _ in range(self.tries):
            x = rng.normal(size=dof)
            x *= rng.random() ** (1.0 / dof) / max(float(np.linalg.norm(x)), 1e-12)
            q = self.centre + self.shape @ x
            if np.all(q >= self.lower) and np.all(q <= self.upper):
                return q
        return np.clip(q, self.lower, self.upper)


def informed_sampler(start: np.ndarray, goal: np.ndarray, length: float, lower: np.ndarray, upper: np.ndarray,
                     tries: int = 8) -> InformedSampler:
    """`InformedSampler(start, goal, length, lower, upper, tries)` (a `Sampler`)."""
    return InformedSampler(start, goal, length, lower, upper, tries)
