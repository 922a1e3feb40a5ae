"""`Pose`: round trips, composition, inverse, batches, validation (with property tests)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from manip.errors import InvalidInputError
from manip.pose import Pose

coord = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
comp = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
positions = arrays(np.float64, 3, elements=coord)
quats = arrays(np.float64, 4, elements=comp).filter(lambda v: np.linalg.norm(v) > 0.1).map(lambda v: v / np.linalg.norm(v))


@st.composite
def poses(draw) -> Pose:
    return Pose(draw(positions), draw(quats))


@st.composite
def pose_batches(draw, n: int = 4) -> Pose:
    return Pose.stack([draw(poses()) for _ in range(n)])


def assert_same(a: Pose, b: Pose, atol: float = 1e-9) -> None:
    np.testing.assert_allclose(a.as_matrix(), b.as_matrix(), atol=atol)


# ---------------------------------------------------------------------- round trips
@given(poses())
def test_matrix_round_trip(T: Pose):
    M = T.as_matrix()
    assert M.shape == (4, 4)
    np.testing.assert_array_equal(M[3], [0, 0, 0, 1])
    back = Pose.from_matrix(M)
    np.testing.assert_allclose(back.position, T.position, atol=1e-12)
    assert back.isclose(T, position_tol=1e-12, rotation_tol=1e-6)


@given(poses())
def test_vector_round_trips(T: Pose):
    v = T.to_xyz_xyzw()
    assert v.shape == (7,)
    np.testing.assert_allclose(v[3:], [*T.quaternion[1:], T.quaternion[0]])
    assert_same(Pose.from_xyz_xyzw(v), T)
    w = T.to_xyz_wxyz()
    np.testing.assert_allclose(w[3:], T.quaternion)
    assert_same(Pose.from_xyz_wxyz(w), T)


def test_xyzw_order_is_scalar_last():
    # a quarter turn about z, written [x, y, z, qx, qy, qz, qw]
    s = np.sqrt(0.5)
    T = Pose.from_xyz_xyzw([1.0, 2.0, 3.0, 0.0, 0.0, s, s])
    np.testing.assert_allclose(T.quaternion, [s, 0, 0, s])
    np.testing.assert_allclose(T.rotation @ [1.0, 0, 0], [0, 1.0, 0], atol=1e-12)


# ---------------------------------------------------------------------- algebra
@given(poses(), poses())
def test_composition_is_matrix_product(A: Pose, B: Pose):
    np.testing.assert_allclose((A @ B).as_matrix(), A.as_matrix() @ B.as_matrix(), atol=1e-9)


@given(poses(), poses(), poses())
def test_composition_is_associative(A: Pose, B: Pose, C: Pose):
    assert_same((A @ B) @ C, A @ (B @ C), atol=1e-8)


@given(poses())
def test_inverse(T: Pose):
    assert_same(T @ T.inverse(), Pose.identity(), atol=1e-9)
    assert_same(T.inverse() @ T, Pose.identity(), atol=1e-9)
    assert_same(T.inverse().inverse(), T)
    np.testing.assert_allclose(T.inverse().as_matrix(), np.linalg.inv(T.as_matrix()), atol=1e-9)


@given(poses(), arrays(np.float64, (5, 3), elements=coord))
def test_transform_points(T: Pose, pts: np.ndarray):
    expected = (T.as_matrix() @ np.c_[pts, np.ones(5)].T).T[:, :3]
    np.testing.assert_allclose(T.transform_points(pts), expected, atol=1e-9)
    np.testing.assert_allclose(T.inverse().transform_points(T.transform_points(pts)), pts, atol=1e-9)


def test_frames_naming_example():
    T_world_base = Pose(np.array([1.0, 0.0, 0.0]))
    T_base_tcp = Pose(np.array([0.0, 0.0, 0.5]), np.array([0.0, 1.0, 0.0, 0.0]))  # half turn about x
    T_world_tcp = T_world_base @ T_base_tcp
    np.testing.assert_allclose(T_world_tcp.position, [1.0, 0.0, 0.5])
    np.testing.assert_allclose(T_world_tcp.rotation @ [0, 0, 1.0], [0, 0, -1.0], atol=1e-12)


# ---------------------------------------------------------------------- batches
@settings(max_examples=30)
@given(pose_batches(), pose_batches())
def test_batched_algebra_equals_single(A: Pose, B: Pose):
    AB = A @ B
    Ainv = A.inverse()
    assert AB.is_batch and len(AB) == 4
    for i in range(4):
        assert_same(AB[i], A[i] @ B[i])
        assert_same(Ainv[i], A[i].inverse())
    M = A.as_matrix()
    assert M.shape == (4, 4, 4)
    assert_same(Pose.from_matrix(M), A)
    assert_same(Pose.from_xyz_xyzw(A.to_xyz_xyzw()), A)


@settings(max_examples=30)
@given(poses(), pose_batches())
def test_single_broadcasts_over_batch(T: Pose, B: Pose):
    left, right = T @ B, B @ T
    for i in range(4):
        assert_same(left[i], T @ B[i])
        assert_same(right[i], B[i] @ T)


def test_batch_access_and_construction():
    P = np.arange(6.0).reshape(2, 3)
    B = Pose(P)  # identity rotation broadcast over the batch
    assert B.is_batch and len(B) == 2 and B.quaternion.shape == (2, 4)
    np.testing.assert_array_equal(B[1].position, [3, 4, 5])
    assert [p.position[0] for p in B] == [0.0, 3.0]
    assert len(B[0:1]) == 1
    one = Pose(np.zeros(3), np.tile([1.0, 0, 0, 0], (3, 1)))  # single position broadcast
    assert one.position.shape == (3, 3)
    assert len(Pose.stack([B, Pose(np.ones(3))])) == 3
    assert len(Pose.identity(5)) == 5
    single = Pose(np.zeros(3))
    assert not single.is_batch
    with pytest.raises(TypeError):
        len(single)
    with pytest.raises(TypeError):
        single[0]


def test_distance_and_isclose():
    a = Pose(np.zeros(3))
    s = np.sqrt(0.5)
    b = Pose(np.array([0.3, 0.4, 0.0]), np.array([s, s, 0.0, 0.0]))  # quarter turn about x
    dp, dr = a.distance(b)
    assert dp == pytest.approx(0.5) and dr == pytest.approx(np.pi / 2)
    assert not a.isclose(b) and a.isclose(Pose(np.array([1e-12, 0, 0])))


def test_pose_is_immutable():
    T = Pose(np.array([1.0, 2.0, 3.0]))
    with pytest.raises(ValueError):
        T.position[0] = 5.0
    src = np.array([1.0, 2.0, 3.0])
    T2 = Pose(src)
    src[0] = 9.0  # the pose keeps its own copy
    assert T2.position[0] == 1.0


# ---------------------------------------------------------------------- validation
def test_small_quaternion_drift_is_normalised():
    T = Pose(np.zeros(3), np.array([1.0002, 0.0, 0.0, 0.0]))
    assert np.linalg.norm(T.quaternion) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize(
    "position, quaternion, match",
    [
        (np.array([np.nan, 0, 0]), (1.0, 0, 0, 0), "non-finite"),
        (np.array([np.inf, 0, 0]), (1.0, 0, 0, 0), "non-finite"),
        (np.zeros(3), (np.nan, 0, 0, 0), "non-finite"),
        (np.zeros(3), (2.0, 0, 0, 0), "norm"),
        (np.zeros(3), (0.0, 0, 0, 0), "norm"),
        (np.zeros(3), (0.9, 0, 0, 0), "norm"),
        (np.zeros(2), (1.0, 0, 0, 0), r"\(3,\)"),
        (np.zeros((2, 2, 3)), (1.0, 0, 0, 0), r"\(N, 3\)"),
        (np.zeros(3), (1.0, 0, 0), r"\(w, x, y, z\)"),
        (np.zeros((2, 3)), np.tile([1.0, 0, 0, 0], (3, 1)), "batch sizes"),
    ],
)
def test_invalid_poses(position, quaternion, match):
    with pytest.raises(InvalidInputError, match=match):
        Pose(position, quaternion)


def test_invalid_conversions():
    with pytest.raises(InvalidInputError, match="orthonormal"):
        Pose.from_matrix(np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(InvalidInputError, match="4, 4"):
        Pose.from_matrix(np.eye(3))
    with pytest.raises(InvalidInputError, match="non-finite"):
        Pose.from_matrix(np.full((4, 4), np.nan))
    with pytest.raises(InvalidInputError, match="qx, qy, qz, qw"):
        Pose.from_xyz_xyzw([0.0, 0.0, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match="qw, qx, qy, qz"):
        Pose.from_xyz_wxyz(np.zeros((2, 6)))
    with pytest.raises(InvalidInputError, match="empty"):
        Pose.stack([])
    with pytest.raises(InvalidInputError, match="single pose"):
        Pose.identity(2).transform_points(np.zeros(3))


def test_pose_at_points_points_to_transform_points():
    pose = Pose([0.1, 0.2, 0.3], [0, 1, 0, 0])
    # numpy's own error was "matmul: Input operand 0 does not have enough dimensions"
    for points in (np.array([0.0, 0.0, 0.1]), [0.0, 0.0, 0.1], np.zeros((2, 3))):
        with pytest.raises(InvalidInputError, match="transform_points"):
            pose @ points
    np.testing.assert_allclose(pose.transform_points([0.0, 0.0, 0.1]), [0.1, 0.2, 0.2], atol=1e-15)
