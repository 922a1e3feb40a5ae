"""`collision.clearance._nearest_terms`: the balls its convex lower bounds pass over never hold the
nearest one, so its terms are those of a search of every ball (issue 33, round fifteen)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from manip import MotionGenerator, WorldConfig
from manip.collision import clearance
from manip.collision.broadphase import _obstacle_sd, _place

#: a rotated box, a cylinder on its side, a ball and a capsule (rounded shapes), around the arm
WORLD = {
    "cuboid": {
        "shelf": {"dims": [0.4, 0.3, 0.03], "pose": [0.45, 0.0, 0.35, 0.9659, 0.0, 0.2588, 0.0]},
        "table": {"dims": [1.2, 1.2, 0.04], "pose": [0.3, 0.0, -0.03, 1, 0, 0, 0]},
    },
    "cylinder": {"can": {"radius": 0.04, "height": 0.3, "pose": [0.3, -0.35, 0.4, 0.7071, 0.7071, 0.0, 0.0]}},
    "sphere": {"ball": {"radius": 0.06, "position": [0.35, 0.3, 0.5]}},
    "capsule": {"rod": {"radius": 0.02, "base": [0.0, 0.0, -0.15], "tip": [0.0, 0.0, 0.15],
                        "pose": [-0.3, 0.3, 0.4, 1, 0, 0, 0]}},
}


@njit
def _every_ball(R, p, centres, radii, joint, bodies, start, count, body_centre, body_radius, activation,
                oR, oc, oh, orho, ocyl):
    """(best distance, best ball) (N, B, O) of a search of every ball of every body near an
    obstacle (the search `_nearest_terms` made before its bounds; first of equals)."""
    N, B, O = R.shape[0], bodies.shape[0], oc.shape[0]
    best_d = np.full((N, B, O), np.inf)
    best_s = np.zeros((N, B, O), dtype=np.int64)
    x = np.empty(3)
    for n in range(N):
        for b in range(B):
            _place(R, p, n, bodies[b], body_centre[b], x)
            near = np.empty(O, dtype=np.bool_)
            for o in range(O):
                near[o] = _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - body_radius[b] < activation
            for s in range(start[b], start[b] + count[b]):
                _place(R, p, n, joint[s], centres[s], x)
                for o in range(O):
                    if near[o]:
                        d = _obstacle_sd(x, o, oR, oc, oh, orho, ocyl) - radii[s]
                        if d < best_d[n, b, o]:
                            best_d[n, b, o] = d
                            best_s[n, b, o] = s
    return best_d, best_s


@pytest.fixture(scope="module")
def mg():
    return MotionGenerator("franka", WorldConfig.from_dict(WORLD))


@pytest.mark.parametrize("activation", [0.02, 0.1, 0.5])
def test_nearest_terms_are_those_of_every_ball(mg, activation):
    model = clearance.ClearanceModel(mg.checker)
    st = mg.checker.state
    moving = np.flatnonzero(st.fine.joint != 0)
    tables = model._tables(st.fine, moving)
    rng = np.random.default_rng(7)
    # random configurations and a smooth motion (consecutive configurations share the bounds' groups)
    Q = np.vstack([rng.uniform(mg.lower_limits, mg.upper_limits, (120, 7)),
                   np.linspace(mg.lower_limits * 0.8, mg.upper_limits * 0.8, 81)])
    R, p = st.joint_transforms(Q)
    n_i, s_i, o_i, dist, _, normal = clearance._nearest_terms(R, p, *tables, activation, *st.obstacle_tables)
    best_d, best_s = _every_ball(R, p, *tables, activation, *st.obstacle_tables)
    joint, bodies = tables[2], tables[3]
    b_i = np.searchsorted(bodies, joint[s_i])
    kept = np.argwhere(best_d < activation)  # (n, b, o) in order, as the terms come
    assert n_i.size == kept.shape[0] > 20
    np.testing.assert_array_equal(np.stack([n_i, b_i, o_i], axis=1), kept)
    np.testing.assert_array_equal(s_i, best_s[n_i, b_i, o_i])
    np.testing.assert_array_equal(dist, best_d[n_i, b_i, o_i])  # bit for bit
    assert np.all(np.abs(np.linalg.norm(normal, axis=1) - 1.0) < 1e-9)
    assert np.unique(o_i).size >= 4  # the box, the cylinder and a rounded shape among them


def test_convex_bound_holds_below_every_ball(mg):
    """The lower bound the kernel skips balls by, sd(x_b) + g . (x_s - x_b) - r_s with g
    `_sd_subgradient` at the body's centre, is never above a ball's distance."""
    st = mg.checker.state
    oR, oc, oh, orho, ocyl = st.obstacle_tables
    rng = np.random.default_rng(3)
    g = np.empty(3)
    worst = -np.inf
    for _ in range(4000):
        o = int(rng.integers(oc.shape[0]))
        xb = oc[o] + rng.normal(0.0, 0.25, 3)
        if not clearance._sd_subgradient.py_func(xb, o, oR, oc, oh, orho, ocyl, g):
            continue
        assert abs(np.linalg.norm(g) - 1.0) < 1e-9
        sd_b = _obstacle_sd.py_func(xb, o, oR, oc, oh, orho, ocyl)
        for y in xb + rng.normal(0.0, 0.15, (8, 3)):
            worst = max(worst, sd_b + g @ (y - xb) - _obstacle_sd.py_func(y, o, oR, oc, oh, orho, ocyl))
    assert worst <= 1e-12
