"""The self-filter's compiled test against a direct one: a point is on the robot when a ball of
the robot's sphere cover holds it and it lies within the margin of that ball's part's 26-DOP."""

from __future__ import annotations

import numpy as np

from manip import MotionGenerator
from manip.perception.integrate import SELF_CELL, _robot
from manip.perception.kernels import on_robot, sphere_index
from robot_constants import FRANKA_READY


def _on_robot_directly(X: np.ndarray, rob) -> np.ndarray:
    """(N,) bool: the definition, over every ball and every part (NumPy, no index)."""
    in_ball = np.linalg.norm(X[:, None, :] - rob.centres[None], axis=2) <= rob.radii[None]          # (N, S)
    # (N, G): every face of the part's 26-DOP within the margin
    faces = np.einsum("nj,gjf->ngf", X, rob.dop[:, :3]) - rob.dop[None, :, 3]
    in_dop = (faces <= rob.margin).all(axis=2)
    return (in_ball & in_dop[:, rob.part]).any(axis=1)


def test_points_on_the_robot_are_those_of_the_definition():
    mg = MotionGenerator("franka")
    rng = np.random.default_rng(3)
    for q in (np.array(FRANKA_READY), rng.uniform(mg.lower_limits, mg.upper_limits)):
        rob = _robot(mg.checker, q, 0.01)
        index = sphere_index(rob.centres, rob.radii, rob.part, rob.dop.shape[0], SELF_CELL)
        # points near the balls' surfaces and inside them (both answers occur), and far away
        s = rng.integers(0, rob.centres.shape[0], 6000)
        d = rng.normal(size=(6000, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        X = rob.centres[s] + d * (rob.radii[s] * rng.uniform(0.0, 1.6, 6000))[:, None]
        X = np.vstack([X, rng.uniform(-1.5, 1.5, (2000, 3))])
        got = on_robot(np.ascontiguousarray(X), rob.centres, rob.radii, rob.part, rob.dop, rob.margin, SELF_CELL,
                       *index)
        want = _on_robot_directly(X, rob)
        assert np.array_equal(got, want)
        assert 1000 < want.sum() < 7000   # both answers are tested
