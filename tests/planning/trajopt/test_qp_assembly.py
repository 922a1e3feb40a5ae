"""The optimiser's QP assembly (`planning.trajopt.qp.inequality_rows`, `sco`) and the work it does not repeat."""

from __future__ import annotations

import time

import numpy as np
import pytest
import scipy.sparse as sp

from manip import MotionGenerator
from manip.planning.trajopt import qp
from manip.planning.trajopt.optimizer import TrajOptSettings, _end_directions, optimize_trajectory
from manip.planning.trajopt.sco import SplineProblem, _csc

LEFT = np.array([0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])
RIGHT = np.array([-0.6, 0.4, 0.0, -1.9, 0.0, 2.3, 0.785])
WALL = {"cuboid": {"wall": {"dims": [0.3, 0.04, 0.5], "pose": [0.5, 0.0, 0.25, 1, 0, 0, 0]}}}


def dense_rows(prob: SplineProblem, keep, extra_col, extra_val, E: int, R: int, gradient, config) -> sp.csc_matrix:
    """The same rows the plain way: a dense [limit rows | extra; clearance rows | slacks] matrix."""
    nx = prob.limit_G.shape[1]
    T = gradient.shape[0]
    L = int(keep.sum())
    G = np.zeros((L + T, nx + E + R + T))
    G[:L, :nx] = prob.limit_G[keep]
    G[np.arange(L), nx + extra_col[keep]] = extra_val[keep]
    Bf = prob.B_free[config]
    G[L:, :nx] = -(gradient[:, :, None] * Bf[:, None, :]).reshape(T, -1)
    G[L + np.arange(T), nx + E + R + np.arange(T)] = -1.0
    return sp.csc_matrix(G)


@pytest.mark.parametrize("extra", ["limit slacks", "step h"])
@pytest.mark.parametrize("rays", [0, 2])
def test_the_inequality_rows_are_exactly_the_dense_rows(extra, rays):
    rng = np.random.default_rng(7)
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    rows = prob.limit_G.shape[0]
    for trial in range(20):
        keep = rng.random(rows) < 0.1 * (trial % 10)
        if extra == "limit slacks":
            E, extra_col, extra_val = 21, prob.limit_slack.copy(), np.full(rows, -1.0)
        else:
            E, extra_col = 1, np.zeros(rows, dtype=np.int64)
            extra_val = rng.normal(size=rows) * (rng.random(rows) < 0.9)  # some exact zeros
        T = int(rng.integers(0, 90))
        config = np.sort(rng.integers(0, prob.B.shape[0], T))
        gradient = rng.normal(size=(T, 7))
        gradient[rng.random((T, 7)) < 0.3] = 0.0  # joints after the body's own move nothing
        got = qp.inequality_rows(prob.limit_G_csc, keep, extra_col, extra_val, E, rays, gradient, config,
                                 prob.B_free)
        want = dense_rows(prob, keep, extra_col, extra_val, E, rays, gradient, config)
        assert got.shape == want.shape
        assert np.array_equal(got.indptr, want.indptr) and np.array_equal(got.indices, want.indices)
        assert np.array_equal(got.data, want.data)  # the same values in the same order: the same QP for PIQP


def test_the_objective_to_csc_keeps_scipy_s_nonzeros_and_order():
    rng = np.random.default_rng(3)
    for _ in range(10):
        P = rng.normal(size=(30, 30)) * (rng.random((30, 30)) < 0.2)
        got, want = _csc(P), sp.csc_matrix(P)
        assert np.array_equal(got.indptr, want.indptr) and np.array_equal(got.indices, want.indices)
        assert np.array_equal(got.data, want.data)


def test_the_qp_s_unchecked_csc_matrices_pass_scipy_s_full_check():
    """`qp.csc` skips scipy's checks: the matrices it builds for a QP must be what the checks accept."""
    assert qp._CSC is qp._unchecked_csc  # this scipy allows it (else `qp.csc` is scipy's constructor)
    rng = np.random.default_rng(5)
    s = TrajOptSettings()
    prob = SplineProblem(s.intervals, 7, s, LEFT, RIGHT)
    prob.set_rays(RIGHT - LEFT, LEFT - RIGHT, 1)
    rows = prob.limit_G.shape[0]
    T = 40
    config = np.sort(rng.integers(0, prob.B.shape[0], T))
    G = qp.inequality_rows(prob.limit_G_csc, rng.random(rows) < 0.5, np.zeros(rows, dtype=np.int64),
                           rng.normal(size=rows), 1, 2, rng.normal(size=(T, 7)), config, prob.B_free)
    P = _csc(np.diag(rng.random(prob.limit_G.shape[1]) + 1.0))
    A, _ = prob.ray_rows(1)
    for got, dense in ((G, None), (qp.regularised(P, 3 + T), np.diag(np.concatenate([np.diag(P.toarray()),
                                                                                      np.full(3 + T, 1e-9)]))),
                       (qp.with_columns(A, T), np.hstack([A.toarray(), np.zeros((A.shape[0], T))]))):
        got.check_format(full_check=True)
        want = sp.csc_matrix((got.data, got.indices, got.indptr), shape=got.shape)  # scipy's checked constructor
        x = rng.normal(size=got.shape[1])
        assert got.shape == want.shape and got.nnz == want.nnz
        assert np.array_equal(got @ x, want @ x) and np.array_equal(got.toarray(), want.toarray())
        if dense is not None:
            assert np.array_equal(got.toarray(), dense)


def reference_end_directions(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Walk the samples one by one: from each end to the last sample on the line through the first that moves."""

    def walk(q0, rows):
        direction, best = None, None
        for r in rows:
            v = r - q0
            if np.linalg.norm(v) < 1e-12:
                continue
            if direction is None:
                direction = v / np.linalg.norm(v)
            elif np.linalg.norm(v - (v @ direction) * direction) > 1e-6:
                break
            best = r
        return (rows[-1] - q0 if len(rows) else np.zeros_like(q0)) if best is None else best - q0

    return walk(q[0], q[1:]), walk(q[-1], q[-2::-1])


def test_the_seed_s_end_directions_follow_its_first_and_last_straight_stretches():
    rng = np.random.default_rng(11)
    for _ in range(300):
        corners = rng.normal(size=(int(rng.integers(2, 5)), 7))
        pieces = [a + (b - a) * f[:, None] for a, b in zip(corners[:-1], corners[1:])
                  for f in [np.linspace(0, 1, int(rng.integers(2, 25)), endpoint=False)]]
        q = np.concatenate([*pieces, corners[-1:]])
        if rng.random() < 0.5:  # at rest for a few samples at both ends
            q = np.concatenate([q[:1].repeat(3, 0), q, q[-1:].repeat(2, 0)])
        for got, want in zip(_end_directions(q), reference_end_directions(q)):
            assert np.array_equal(got, want)
    first, last = _end_directions(np.array([LEFT, LEFT, (LEFT + RIGHT) / 2, RIGHT, RIGHT + 0.1]))
    assert np.allclose(first, RIGHT - LEFT) and np.allclose(last, -np.full(7, 0.1))


def test_one_optimisation_evaluates_each_set_of_samples_once():
    mg = MotionGenerator("franka", WALL)
    seed = mg.plan_joints(LEFT, RIGHT, trajopt=False, seed=3).trajectory  # round the wall
    seen = []

    class Recording:
        def __init__(self, clearance):
            self.clearance = clearance

        def terms(self, Q, activation):
            seen.append((np.asarray(Q).tobytes(), activation))
            return self.clearance.terms(Q, activation)

    res = optimize_trajectory(seed.positions, seed.times, limits=mg.config.limits, clearance=Recording(mg.clearance),
                              padding=0.0, deadline=time.perf_counter() + 60.0, max_duration=seed.duration)
    assert res.success and res.solves >= 2
    assert len(seen) >= res.solves  # the clearance was evaluated along the way
    assert len(set(seen)) == len(seen)  # and never twice for the same samples
