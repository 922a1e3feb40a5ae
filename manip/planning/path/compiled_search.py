"""RRT-Connect's coarse search in compiled code: the loop, the trees and the sphere screens of
the configurations checked in one numba kernel; only the configurations the sphere covers cannot
clear go back to Python, for the checker's exact answer.

The kernel is `rrt_connect.rrt_connect` with `advance=Validity.coarse_advance`, step for step: it
draws from the caller's `np.random.Generator` (numba's Generator support shares its state and its
streams), in the same order, so a search makes the same samples, trees and path as the Python one
(up to the last bits of a few sums: norms and nearest-node distances are summed in another
order). An advance checks its samples in order from the one after its start; a sample whose
robot balls keep clear of every obstacle and of each other (the broadphase kernels find no
candidate) is free for certain (`manip.collision.broadphase`); at any other the kernel decides
the candidates of convex pairs itself (`compiled_narrowphase`, with `KERNEL_NARROWPHASE`: GJK on
the parts' hulls against boxes, spheres, capsules, cylinders) and calls back into Python
(`numba.objmode`) with the candidates left, ordered deepest first, for coal to decide
(`CollisionState.collides_given`, the checker's narrowphase). Coal's answers are the exact
checker's; the kernel's may differ from them in rare near-touch cases (`compiled_narrowphase`),
and the search may then take another path, which goes through the same fine repairs, shortcut,
optimiser and certificate (the exact checker). The kernel returns to Python every `PAUSE_EVERY`
iterations to look at the clock (the Python search looks at every iteration).

The constrained search (`steer`), strict validities checking their search at the fine
resolution, worlds with occupancy maps (whose candidates come from their own kernels) and
samplers other than the uniform one and `rrt_connect.InformedSampler` keep the Python search.
"""

from __future__ import annotations

import threading
import time

import numba
import numpy as np

from manip.collision.broadphase import self_candidates, world_candidates
from manip.jit import kernel
from manip.kinematics import chain_frames
from manip.planning.path.compiled_narrowphase import NarrowTables, decide

#: Iterations between the kernel's returns to Python to look at the clock (the deadline).
PAUSE_EVERY = 64

#: The coarse search decides the candidates of convex pairs in the kernel (`compiled_narrowphase`:
#: GJK on the parts' hulls against boxes, spheres, capsules, cylinders), coal only the rest.
KERNEL_NARROWPHASE = True

# what the kernel returns
FOUND, EXHAUSTED, PAUSE = 0, 1, 2
# slots of the kernel's integer state (`ints`)
_IT, _A, _PHASE, _TREE, _FROM, _S, _STEPS, _INEW, _HIT, _MAXIT, _TRIES, _PAUSE_AT, _JOIN, _WORLD, _SELF, \
    _SCREENED, _NARROW, _DECIDED = range(18)
_NONE = -2  # `_HIT` with no answer pending (-1: the unsure sample is free; 1: it collides)


#: The checks of the search running in this thread (`compiled_rrt_connect`), for `_exact_answer`.
_RUNNING = threading.local()


def _exact_answer(R, p, kind, i, j) -> int:
    """1 when the configuration with joint frames R, p and these broadphase candidates collides
    (coal, `CollisionState.collides_given`), else -1: called from the kernel (object mode)."""
    checks = _RUNNING.checks
    checks.counts[0] += 1
    return 1 if checks.state.collides_given(R, p, kind, i, j) else -1


@kernel
def _candidates_at(q, Qb, R, p, fk, wot, st, pairs, wmargin, smargin, world, self_):
    """The broadphase candidates of configuration q (dof,), deepest first (T,) each: kind (0 =
    world, 1 = self), i (the part), j (the obstacle, or the other part): those of
    `world_candidates` with margin `wmargin` and of `self_candidates` with `smargin` [m], whose
    pair indices map to parts by `pairs` (P, 2); none at all: free for certain. R, p, Qb:
    buffers (q's joint frames after)."""
    chain_frames(q, fk[0], fk[1], fk[2], R[0], p[0])
    e = np.empty(0, dtype=np.int64)
    wg, wo, wd = e, e, np.empty(0)
    sk, sd = e, np.empty(0)
    if world:
        _, wg, wo, wd = world_candidates(R, p, wmargin, *wot)
    if self_:
        for j in range(q.shape[0]):
            Qb[0, j] = q[j]
        _, sk, sd = self_candidates(R, p, Qb, smargin, *st)
    nw = wg.size
    T = nw + sk.size
    depth = np.empty(T)
    depth[:nw] = wd
    depth[nw:] = sd
    order = np.argsort(depth, kind="mergesort")   # stable: the checker's order (`_candidates`)
    kind = np.empty(T, dtype=np.int64)
    a = np.empty(T, dtype=np.int64)
    b = np.empty(T, dtype=np.int64)
    for t in range(T):
        k = order[t]
        if k < nw:
            kind[t], a[t], b[t] = 0, wg[k], wo[k]
        else:
            kind[t], a[t], b[t] = 1, pairs[sk[k - nw], 0], pairs[sk[k - nw], 1]
    return kind, a, b


@kernel
def _no_candidates():
    """Empty `_candidates_at` results."""
    e = np.empty(0, dtype=np.int64)
    return e, e, e


@kernel
def _nearest(nodes, n, q):
    """Index of the row of nodes[:n] (n, dof) nearest to q (dof,) (squared L2; the first on a tie)."""
    best = np.inf
    out = 0
    for i in range(n):
        s = 0.0
        for j in range(q.shape[0]):
            d = nodes[i, j] - q[j]
            s += d * d
        if s < best:
            best = s
            out = i
    return out


@kernel
def _norm(a, b):
    """|a - b| (joint-space L2) of two (dof,) arrays."""
    s = 0.0
    for j in range(a.shape[0]):
        d = a[j] - b[j]
        s += d * d
    return np.sqrt(s)


@kernel
def _sample(rng, ints, nodes, counts, a, lower, upper, local_fraction, local_sigma, centre, shape, x, out):
    """`rrt_connect`'s sample into out (dof,): near a random node of tree a, else uniform within
    the limits or, with ints[_TRIES] > 0, `InformedSampler`'s (centre (dof,), shape (dof, dof))."""
    dof = lower.shape[0]
    if rng.random() < local_fraction:
        k = rng.integers(0, counts[a])
        for j in range(dof):
            out[j] = min(max(nodes[a, k, j] + rng.normal(0.0, local_sigma), lower[j]), upper[j])
        return
    tries = ints[_TRIES]
    if tries == 0:
        for j in range(dof):
            out[j] = lower[j] + (upper[j] - lower[j]) * rng.random()
        return
    for _ in range(tries):
        s = 0.0
        for j in range(dof):
            x[j] = rng.normal(0.0, 1.0)
            s += x[j] * x[j]
        scale = rng.random() ** (1.0 / dof) / max(np.sqrt(s), 1e-12)
        for j in range(dof):
            x[j] *= scale
        inside = True
        for r in range(dof):
            v = centre[r]
            for c in range(dof):
                v += shape[r, c] * x[c]
            out[r] = v
            inside = inside and lower[r] <= v <= upper[r]
        if inside:
            return
    for j in range(dof):
        out[j] = min(max(out[j], lower[j]), upper[j])


@kernel
def _begin(ints, buf, tree, i, resolution):
    """Start the advance of `tree` from node i along buf[1] -> buf[2] (from, to)."""
    m = 0.0
    for j in range(buf.shape[1]):
        m = max(m, abs(buf[2, j] - buf[1, j]))
    ints[_TREE] = tree
    ints[_FROM] = i
    ints[_STEPS] = max(1, int(np.ceil(m / resolution - 1e-12)))
    ints[_S] = 1
    ints[_HIT] = _NONE


@kernel
def _screen(ints, buf, Qb, R, p, fk, wot, st, pairs, wmargin, smargin):
    """Go on with the advance: (-1 when its samples are free to the end, else the first colliding
    sample's index, or -2 when sample ints[_S] needs the exact checker; then its candidates
    (`_candidates_at`), R and p holding its joint frames)."""
    hit = ints[_HIT]
    ints[_HIT] = _NONE
    if hit == 1:
        return ints[_S], _no_candidates()
    if hit == -1:
        ints[_S] += 1
    steps = ints[_STEPS]
    dof = buf.shape[1]
    q = buf[4]
    s = ints[_S]
    while s <= steps:
        t = s / steps
        for j in range(dof):
            q[j] = buf[1, j] + t * (buf[2, j] - buf[1, j])
        c = _candidates_at(q, Qb, R, p, fk, wot, st, pairs, wmargin, smargin, ints[_WORLD] != 0, ints[_SELF] != 0)
        ints[_SCREENED] += 1
        if c[0].size:
            ints[_S] = s
            return -2, c
        s += 1
    return -1, _no_candidates()


@kernel(nogil=False)  # it calls coal through Python (`_exact_answer`)
def _search(rng, nodes, parents, counts, ints, buf, lower, upper, params, centre, shape, fk, wot, st, pairs, R, p,
            Qb, nt, ot):
    """Run the search (`rrt_connect`'s loop) from the state in `ints` until it is FOUND (the
    joining nodes in ints[_INEW], ints[_JOIN]), EXHAUSTED (ints[_MAXIT] iterations) or PAUSEs
    (every PAUSE_EVERY iterations, for the clock; call again to go on). A configuration the
    balls cannot clear is decided by `compiled_narrowphase.decide` (with ints[_NARROW]) and
    by `_exact_answer` (coal, through Python) for the candidates it leaves.

    nodes (2, cap, dof), parents (2, cap), counts (2,): the start (0) and goal (1) trees.
    buf (6, dof): sample, advance start and end, stop, scratch. params: step size [rad], local
    fraction, local spread [rad], resolution [rad], world and self margins [m], backoff steps.
    """
    step_size, local_fraction, local_sigma, resolution = params[0], params[1], params[2], params[3]
    wmargin, smargin, backoff = params[4], params[5], params[6]
    dof = lower.shape[0]
    while True:
        phase = ints[_PHASE]
        if phase == 0:  # a new iteration: sample, extend tree a towards it
            it = ints[_IT]
            if it > ints[_MAXIT]:
                return EXHAUSTED
            if it >= ints[_PAUSE_AT]:
                ints[_PAUSE_AT] = it + PAUSE_EVERY
                return PAUSE
            a = ints[_A]
            _sample(rng, ints, nodes, counts, a, lower, upper, local_fraction, local_sigma, centre, shape, buf[5], buf[0])
            i = _nearest(nodes[a], counts[a], buf[0])
            dist = _norm(buf[0], nodes[a, i])
            for j in range(dof):
                buf[1, j] = nodes[a, i, j]
                if dist <= step_size:
                    buf[2, j] = buf[0, j]
                else:
                    buf[2, j] = nodes[a, i, j] + (buf[0, j] - nodes[a, i, j]) * (step_size / dist)
            _begin(ints, buf, a, i, resolution)
            ints[_PHASE] = 1
            continue
        s_hit, c = _screen(ints, buf, Qb, R, p, fk, wot, st, pairs, wmargin, smargin)
        if s_hit == -2:  # decided here or by coal (in Python), then the advance goes on
            kind, a, b = c
            if ints[_NARROW] != 0:
                hit, left = decide(kind, a, b, R, p, nt, ot)
                if hit != 0:
                    ints[_DECIDED] += 1
                    ints[_HIT] = hit
                    continue
                kind, a, b = kind[left], a[left], b[left]
            with numba.objmode(hit="int64"):
                hit = _exact_answer(R, p, kind, a, b)
            ints[_HIT] = hit
            continue
        # the advance's stop (`Validity.advance`), and the node it adds
        steps = ints[_STEPS]
        t_stop = 1.0 if s_hit == -1 else s_hit / steps - backoff / steps
        tree = ints[_TREE]
        new = -1
        if t_stop > 0:
            for j in range(dof):
                buf[3, j] = buf[2, j] if t_stop >= 1.0 else buf[1, j] + t_stop * (buf[2, j] - buf[1, j])
            if _norm(buf[3], buf[1]) >= 1e-6:
                new = counts[tree]
                nodes[tree, new, :] = buf[3]
                parents[tree, new] = ints[_FROM]
                counts[tree] = new + 1
        a = ints[_A]
        if phase == 1 and new >= 0:  # extended: pull the other tree towards the new node
            ints[_INEW] = new
            b = 1 - a
            j0 = _nearest(nodes[b], counts[b], nodes[a, new])
            for j in range(dof):
                buf[1, j] = nodes[b, j0, j]
                buf[2, j] = nodes[a, new, j]
            _begin(ints, buf, b, j0, resolution)
            ints[_PHASE] = 2
            continue
        if phase == 2 and new >= 0:
            joined = True
            for j in range(dof):
                joined = joined and nodes[tree, new, j] == buf[2, j]
            if joined:  # the other tree reached the new node
                ints[_JOIN] = new
                return FOUND
        ints[_A] = 1 - a
        ints[_IT] += 1
        ints[_PHASE] = 0


class CompiledChecks:
    """What the kernel checks with: one collision state's tables at one resolution.

    Args:
        state: the checker's `CollisionState` (no occupancy maps, not always colliding).
        resolution: the advances' check resolution [rad] > 0.
        backoff: check steps an advance stops short of its first contact
            (`validity.ADVANCE_BACKOFF_STEPS`).
        narrowphase: decide convex candidates in the kernel (`compiled_narrowphase`; the
            coarse search only, never the repairs).
    """

    def __init__(self, state, resolution: float, backoff: int, narrowphase: bool = False):
        if state.occupancy_maps or state.every_configuration_collides:
            raise ValueError("the compiled search needs a world without occupancy maps whose fixed parts collide "
                             "with nothing; use rrt_connect")
        if not resolution > 0:
            raise ValueError(f"resolution must be > 0 rad; got {resolution}")
        self.state = state
        self.resolution = float(resolution)
        self.backoff = float(backoff)
        self.fk = state.kinematics.fk_tables()
        self.wot = tuple(state.world_tables) + tuple(state.obstacle_tables)
        self.st = tuple(state.self_tables)
        self.pairs = np.ascontiguousarray(state.self_pairs, dtype=np.int64).reshape(-1, 2)
        self.world = bool(len(state.obstacles) and state.moving_world_parts)
        self.self_ = bool(state.self_tables[3].shape[0])
        J = self.fk[2].shape[0]
        dof = state.kinematics.dof
        self.R, self.p, self.Qb = np.empty((1, J + 1, 3, 3)), np.empty((1, J + 1, 3)), np.empty((1, dof))
        self.narrow = bool(narrowphase)
        self.nt = NarrowTables(state if narrowphase else None).arrays()
        self.ot = tuple(state.obstacle_tables)[:4]
        #: (configurations decided by the exact checker, kernel calls, configurations screened by
        #: the kernel, those included, configurations decided by `compiled_narrowphase`) of the
        #: searches so far
        self.counts = [0, 0, 0, 0]


def compiled_rrt_connect(
    start: np.ndarray, goals: np.ndarray, lower: np.ndarray, upper: np.ndarray, checks: CompiledChecks,
    rng: np.random.Generator, deadline: float, *, step_size: float, local_fraction: float, local_sigma: float,
    max_iterations: int, sample=None,
) -> tuple[np.ndarray | None, int]:
    """`rrt_connect.rrt_connect` with `advance` the checks' straight-segment advance, compiled
    (module docstring): the same arguments and result. `sample`: None (uniform) or an
    `InformedSampler`."""
    start = np.ascontiguousarray(start, dtype=np.float64)
    goals = np.atleast_2d(np.asarray(goals, dtype=np.float64))
    dof = start.shape[0]
    cap = max(1, goals.shape[0]) + max_iterations + 1
    nodes = np.empty((2, cap, dof))
    parents = np.empty((2, cap), dtype=np.int64)
    nodes[0, 0] = start
    nodes[1, : goals.shape[0]] = goals
    parents[:, : goals.shape[0]] = -1
    counts = np.array([1, goals.shape[0]], dtype=np.int64)
    ints = np.zeros(18, dtype=np.int64)
    ints[_IT], ints[_MAXIT], ints[_PAUSE_AT], ints[_HIT] = 1, max_iterations, 1 + PAUSE_EVERY, _NONE
    ints[_WORLD], ints[_SELF], ints[_NARROW] = checks.world, checks.self_, checks.narrow
    if sample is None:
        centre, shape = np.zeros(dof), np.zeros((dof, dof))
    else:
        centre, shape = sample.centre, sample.shape
        ints[_TRIES] = sample.tries
    buf = np.empty((6, dof))
    params = np.array([step_size, local_fraction, local_sigma, checks.resolution, checks.state.padding + 1e-9,
                       checks.state.self_padding + 1e-9, checks.backoff])
    lower = np.ascontiguousarray(lower, dtype=np.float64)
    upper = np.ascontiguousarray(upper, dtype=np.float64)
    tally = checks.counts
    if time.perf_counter() > deadline:
        return None, 1
    try:
        return _run(rng, nodes, parents, counts, ints, buf, lower, upper, params, centre, shape, checks, deadline)
    finally:
        tally[2] += int(ints[_SCREENED])
        tally[3] += int(ints[_DECIDED])


def _run(rng, nodes, parents, counts, ints, buf, lower, upper, params, centre, shape, checks, deadline):
    """`compiled_rrt_connect`'s loop over the kernel's pauses."""
    tally = checks.counts
    while True:
        _RUNNING.checks = checks
        status = _search(rng, nodes, parents, counts, ints, buf, lower, upper, params, centre, shape, checks.fk,
                         checks.wot, checks.st, checks.pairs, checks.R, checks.p, checks.Qb, checks.nt, checks.ot)
        tally[1] += 1
        if status == PAUSE:
            if time.perf_counter() > deadline:
                return None, int(ints[_IT])
        elif status == FOUND:
            return _join(nodes, parents, int(ints[_A]), int(ints[_INEW]), int(ints[_JOIN])), int(ints[_IT])
        else:
            return None, int(ints[_MAXIT])


def _join(nodes: np.ndarray, parents: np.ndarray, a: int, i: int, j: int) -> np.ndarray:
    """The path root of tree 0 -> root of tree 1 through node i of tree a and node j of the other."""

    def branch(tree: int, k: int) -> list[int]:
        out = []
        while k >= 0:
            out.append(k)
            k = int(parents[tree, k])
        return out

    b = 1 - a
    path = [nodes[a, k] for k in branch(a, i)[::-1]] + [nodes[b, k] for k in branch(b, j)[1:]]
    if a == 1:
        path = path[::-1]
    return np.array(path)
