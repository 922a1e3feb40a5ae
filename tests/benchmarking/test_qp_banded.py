"""benchmarks/qp_banded.py: the structured interior-point solver against PIQP on the optimiser's own QPs."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import goal_pose, load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.errors import InvalidInputError
from manip.planning.trajopt import qp
from robot_constants import REPO_ROOT, load_script


@pytest.fixture(scope="module")
def banded_qp():
    return load_script(REPO_ROOT / "benchmarks" / "qp_banded.py", "qp_banded")


@pytest.fixture(scope="module")
def recorded():
    """The QPs of one MotionBenchMaker problem's joint and pose plans (`qp.solve`'s arguments)."""
    qps = []
    solve = qp.solve

    def recording(P, q, G, h, A, b, lb, ub, solver):
        qps.append((P.copy(), q.copy(), G.copy(), h.copy(), None if A is None else A.copy(),
                    None if b is None else b.copy(), lb.copy(), ub.copy()))
        return solve(P, q, G, h, A, b, lb, ub, solver)

    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    p = next(p for p in load_mbm_problems(limit_per_scene=1) if verifier.check_problem(p).valid)
    mg.update_world(WorldConfig.from_dict(p.world))
    qp.solve = recording
    try:
        assert mg.plan_joints(p.start, p.goal, seed=0).success
        assert mg.plan_pose(p.start, goal_pose(p), link="panda_hand", seed=0).success
    finally:
        qp.solve = solve
    return qps


def test_it_solves_the_optimisers_qps_as_piqp_does(banded_qp, recorded, monkeypatch):
    assert len(recorded) >= 6  # both plans ran the optimiser
    # the reference at PIQP's tight settings (the planner's own stop at 3e-4 since round eleven)
    monkeypatch.setattr(qp, "PIQP_EPS", 1e-6)
    monkeypatch.setattr(qp, "PIQP_SCALE_COST", False)
    monkeypatch.setattr(qp, "PIQP_PRECONDITIONER_ITER", 10)
    solved, errors = 0, []
    for P, q, G, h, A, b, lb, ub in recorded:
        m = banded_qp.points_of(P)
        status, z, iterations = banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, m)
        ref = qp.solve(P, q, G, h, A, b, lb, ub, "piqp")
        assert ref is not None
        if status != banded_qp.SOLVED:
            continue
        solved += 1
        assert iterations <= banded_qp.MAX_ITER
        # a solution of the QP itself: feasible to the tolerance, whatever PIQP says
        assert np.all(G @ z <= h + 1e-5)
        assert np.all(z >= lb - 1e-5) and np.all(z <= ub + 1e-5)
        if A is not None:
            assert np.allclose(A @ z, b, atol=1e-5)
        x, x_ref = z[: 7 * m], ref[: 7 * m]
        errors.append(np.max(np.abs(x - x_ref)) / max(1.0, np.max(np.abs(x_ref))))
        # and as good as PIQP's by the objective (both stop at 1e-6)
        f = 0.5 * z @ (P @ z) + q @ z
        f_ref = 0.5 * ref @ (P @ ref) + q @ ref
        assert f <= f_ref + 1e-4 * max(1.0, abs(f_ref))
    assert solved >= 0.9 * len(recorded)
    assert np.median(errors) < 2e-5 and max(errors) < 1e-3  # PIQP's own tolerance is 1e-6 absolute


def test_an_iteration_cap_reports_a_stall_not_a_solution(banded_qp, recorded):
    P, q, G, h, A, b, lb, ub = recorded[0]
    status, _, iterations = banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, banded_qp.points_of(P), max_iter=2)
    assert status == banded_qp.MAX_ITERATIONS and iterations == 2


def test_an_infeasible_qp_is_not_solved(banded_qp, recorded):
    P, q, G, h, A, b, lb, ub = recorded[0]
    lb, ub = lb.copy(), ub.copy()
    lb[0], ub[0] = 1.0, 0.0  # an empty box
    status, _, _ = banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, banded_qp.points_of(P))
    assert status != banded_qp.SOLVED


def test_bad_input_raises(banded_qp, recorded):
    P, q, G, h, A, b, lb, ub = recorded[0]
    m = banded_qp.points_of(P)
    with pytest.raises(InvalidInputError, match="G must be"):
        banded_qp.solve(P, q, G.toarray(), h, A, b, lb, ub, 7, m)
    with pytest.raises(InvalidInputError, match="P must be"):
        banded_qp.solve(P[:-1, :-1].tocsc(), q, G, h, A, b, lb, ub, 7, m)
    with pytest.raises(InvalidInputError, match="dof and points"):
        banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, 10 * m)
    with pytest.raises(InvalidInputError, match="lb must have shape"):
        banded_qp.solve(P, q, G, h, A, b, lb[:-1], ub, 7, m)
    bad = q.copy()
    bad[3] = np.nan
    with pytest.raises(InvalidInputError, match="finite"):
        banded_qp.solve(P, bad, G, h, A, b, lb, ub, 7, m)
    with pytest.raises(InvalidInputError, match="max_iter"):
        banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, m, max_iter=-1)


def test_compare_reports_on_recorded_qps(banded_qp, recorded):
    qps = [{"P": P, "q": q, "G_T": G.toarray().T, "h": h, "A": A, "b": b, "lb": lb, "ub": ub}
           for P, q, G, h, A, b, lb, ub in recorded]
    result = banded_qp.compare(qps)
    assert result["qps"] == len(qps) and result["mismatched"] <= len(qps) // 10
    assert "status differs on" in result["text"] and "CPU per QP" in result["text"]


def test_another_block_size_is_compiled_for_and_solves_the_same(banded_qp, recorded):
    # the kernel is compiled per dof (the block size a constant); dof 1 over 7 * points "points" puts the
    # same variables in 1 x 1 blocks (a wide band): the same QP, the same solution
    P, q, G, h, A, b, lb, ub = recorded[0]
    m = banded_qp.points_of(P)
    status7, z7, _ = banded_qp.solve(P, q, G, h, A, b, lb, ub, 7, m)
    status1, z1, _ = banded_qp.solve(P, q, G, h, A, b, lb, ub, 1, 7 * m)
    assert banded_qp._kernel(1) is not banded_qp._kernel(7)
    assert status7 == status1 == banded_qp.SOLVED
    ref = qp.solve(P, q, G, h, A, b, lb, ub, "piqp")
    scale = max(1.0, np.max(np.abs(ref[: 7 * m])))
    assert np.max(np.abs(z1[: 7 * m] - ref[: 7 * m])) / scale < 1e-3
    assert np.max(np.abs(z1[: 7 * m] - z7[: 7 * m])) / scale < 1e-3
