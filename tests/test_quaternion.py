"""Quaternion helpers (w, x, y, z): conversions, products, angles, validation."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from manip import quaternion as quat
from manip.errors import InvalidInputError

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
vec4 = arrays(np.float64, 4, elements=finite).filter(lambda v: np.linalg.norm(v) > 0.1)
vec3 = arrays(np.float64, 3, elements=finite).filter(lambda v: np.linalg.norm(v) > 0.1)


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def same_rotation(a: np.ndarray, b: np.ndarray, atol: float = 1e-9) -> bool:
    """q and -q are the same rotation."""
    return bool(np.allclose(a, b, atol=atol) or np.allclose(a, -b, atol=atol))


def test_reordering():
    q = np.array([0.1, 0.2, 0.3, 0.4])
    np.testing.assert_array_equal(quat.wxyz_to_xyzw(q), [0.2, 0.3, 0.4, 0.1])
    np.testing.assert_array_equal(quat.xyzw_to_wxyz(quat.wxyz_to_xyzw(q)), q)
    batch = np.arange(12.0).reshape(3, 4)
    np.testing.assert_array_equal(quat.xyzw_to_wxyz(quat.wxyz_to_xyzw(batch)), batch)


def test_to_matrix_matches_pinocchio():
    rng = np.random.default_rng(0)
    for _ in range(20):
        q = unit(rng.normal(size=4))
        # pinocchio's Quaternion takes (w, x, y, z) in its constructor
        R_pin = pin.Quaternion(*q).toRotationMatrix()
        np.testing.assert_allclose(quat.to_matrix(q), R_pin, atol=1e-12)


@given(vec4)
def test_matrix_round_trip(v: np.ndarray):
    q = unit(v)
    R = quat.to_matrix(q)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    q2 = quat.from_matrix(R)
    assert q2[0] >= 0.0
    assert same_rotation(q, q2, atol=1e-9)


def test_from_matrix_every_branch_and_batch():
    # identity, and half-turns about x, y, z (trace = -1: the non-w branches)
    cases = [np.eye(3), np.diag([1.0, -1, -1]), np.diag([-1.0, 1, -1]), np.diag([-1.0, -1, 1])]
    expected = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    q = quat.from_matrix(np.stack(cases))
    assert q.shape == (4, 4)
    for a, b in zip(q, expected):
        assert same_rotation(a, np.array(b, dtype=float))
    # rotations near pi about a skewed axis
    axis = unit(np.array([0.3, -0.5, 0.8]))
    for angle in (np.pi - 1e-9, np.pi, 3.0):
        q0 = quat.from_axis_angle(axis, np.array(angle))
        assert same_rotation(quat.from_matrix(quat.to_matrix(q0)), q0, atol=1e-8)


@given(vec4, vec4)
def test_product_is_matrix_product(a: np.ndarray, b: np.ndarray):
    a, b = unit(a), unit(b)
    np.testing.assert_allclose(
        quat.to_matrix(quat.multiply(a, b)), quat.to_matrix(a) @ quat.to_matrix(b), atol=1e-12
    )


@given(vec4)
def test_conjugate_is_inverse(v: np.ndarray):
    q = unit(v)
    np.testing.assert_allclose(quat.multiply(q, quat.conjugate(q)), [1, 0, 0, 0], atol=1e-12)


@given(vec3, st.floats(0.0, np.pi))
def test_axis_angle_and_angle_between(axis: np.ndarray, angle: float):
    axis = unit(axis)
    q = quat.from_axis_angle(axis, np.array(angle))
    R = quat.to_matrix(q)
    np.testing.assert_allclose(R @ axis, axis, atol=1e-12)  # the axis is fixed
    np.testing.assert_allclose(R, pin.exp3(axis * angle), atol=1e-12)
    assert quat.angle_between(np.array([1.0, 0, 0, 0]), q) == pytest.approx(angle, abs=1e-6)
    assert quat.angle_between(q, -q) == pytest.approx(0.0, abs=1e-6)  # sign invariant


def test_normalize():
    q = np.array([1.0, 0.0, 0.0, 0.0005])  # small drift: normalised
    n = quat.normalize(q)
    assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-15)
    batch = quat.normalize(np.array([[0.0, 1.0, 0, 0], [0.9995, 0, 0, 0]]))
    np.testing.assert_allclose(np.linalg.norm(batch, axis=1), 1.0)
    with pytest.raises(InvalidInputError, match="norm"):
        quat.normalize(np.array([2.0, 0, 0, 0]))
    with pytest.raises(InvalidInputError, match="norm"):
        quat.normalize(np.zeros(4))
    with pytest.raises(InvalidInputError, match="non-finite"):
        quat.normalize(np.array([np.nan, 0, 0, 1.0]))
    with pytest.raises(InvalidInputError, match="4 components"):
        quat.normalize(np.array([1.0, 0, 0]))


@settings(max_examples=50)
@given(arrays(np.float64, (5, 4), elements=finite).filter(lambda v: np.all(np.linalg.norm(v, axis=1) > 0.1)))
def test_batched_equals_single(v: np.ndarray):
    Q = v / np.linalg.norm(v, axis=1, keepdims=True)
    R = quat.to_matrix(Q)
    assert R.shape == (5, 3, 3)
    back = quat.from_matrix(R)
    for i in range(5):
        np.testing.assert_allclose(R[i], quat.to_matrix(Q[i]), atol=1e-15)
        np.testing.assert_allclose(back[i], quat.from_matrix(R[i]), atol=1e-15)


def test_from_axis_angle_takes_unit_axes_and_refuses_others():
    q = quat.from_axis_angle([0, 0, 1], np.pi / 2)
    np.testing.assert_allclose(q, [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)], atol=1e-15)
    batch = quat.from_axis_angle(np.array([[1.0, 0, 0], [0, 1.0, 0]]), np.array([0.3, -0.4]))
    np.testing.assert_allclose(np.linalg.norm(batch, axis=-1), 1.0)
    np.testing.assert_allclose(quat.to_matrix(batch[1]), pin.utils.rotate("y", -0.4), atol=1e-12)
    # an axis of norm 2 gave (0.71, 0, 0, 1.41): no rotation, and an error far from its cause
    with pytest.raises(InvalidInputError, match=r"axis must be a unit vector .*axis / \|axis\|"):
        quat.from_axis_angle([0, 0, 2], np.pi / 2)
    with pytest.raises(InvalidInputError, match="axis must be a unit vector"):
        quat.from_axis_angle([0, 0, 0], np.pi / 2)
    with pytest.raises(InvalidInputError, match="axis must have 3 components"):
        quat.from_axis_angle([0, 1], 0.1)
    with pytest.raises(InvalidInputError, match="finite"):
        quat.from_axis_angle([0, 0, 1], np.nan)
