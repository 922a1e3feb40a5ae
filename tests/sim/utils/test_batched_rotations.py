"""Isaac's batched rotations (`isaacsim.core.utils.numpy.rotations` names) against the single ones."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (
    deg2rad,
    euler_angles_to_quat,
    euler_angles_to_quats,
    quat_to_rot_matrix,
    quats_to_euler_angles,
    quats_to_rot_matrices,
    quats_to_rotvecs,
    rad2deg,
    rot_matrices_to_quats,
    rotvecs_to_quats,
    wxyz2xyzw,
    xyzw2wxyz,
)


@pytest.mark.parametrize("extrinsic", [True, False])
def test_batched_match_the_single_conversions(extrinsic):
    rng = np.random.default_rng(1)
    angles = rng.uniform([-3, -1.5, -3], [3, 1.5, 3], size=(20, 3))
    q = euler_angles_to_quats(angles, extrinsic=extrinsic)
    assert q.shape == (20, 4)
    for a, qi in zip(angles, q):
        single = euler_angles_to_quat(a, extrinsic=extrinsic)
        assert np.allclose(qi, single) or np.allclose(qi, -single)
    assert np.allclose(quats_to_euler_angles(q, extrinsic=extrinsic), angles, atol=1e-9)
    R = quats_to_rot_matrices(q)
    assert R.shape == (20, 3, 3)
    assert np.allclose(R[3], quat_to_rot_matrix(q[3]))
    assert np.allclose(quats_to_rot_matrices(rot_matrices_to_quats(R)), R)


def test_one_item_in_gives_one_item_out_and_degrees():
    q = euler_angles_to_quats(np.array([0, 90, 0]), degrees=True)
    assert q.shape == (4,)
    assert np.allclose(q, [np.sqrt(0.5), 0, np.sqrt(0.5), 0])
    assert np.allclose(quats_to_euler_angles(q, degrees=True), [0, 90, 0])
    assert np.allclose(deg2rad(rad2deg(np.array([0.3, -2.0]))), [0.3, -2.0])


def test_rotation_vectors_round_trip():
    rng = np.random.default_rng(2)
    v = rng.normal(size=(10, 3))
    v *= (rng.uniform(0, np.pi, 10) / np.linalg.norm(v, axis=1))[:, None]
    q = rotvecs_to_quats(v)
    assert np.allclose(quats_to_rotvecs(q), v)
    assert np.allclose(rotvecs_to_quats(np.zeros(3)), [1, 0, 0, 0])
    assert np.allclose(rotvecs_to_quats([0, 0, 90], degrees=True), euler_angles_to_quat([0, 0, 90], degrees=True))
    assert np.allclose(xyzw2wxyz(wxyz2xyzw(q)), q)
    assert np.allclose(wxyz2xyzw([1, 0, 0, 0]), [0, 0, 0, 1])


def test_bad_input_names_the_argument():
    with pytest.raises(InvalidInputError, match="euler_angles"):
        euler_angles_to_quats(np.zeros((5, 2)))
    with pytest.raises(InvalidInputError, match="quaternions"):
        quats_to_rot_matrices(np.array([[1.0, 0, 0, 0], [2.0, 0, 0, 0]]))   # not unit
    with pytest.raises(InvalidInputError, match="rotation_matrices"):
        rot_matrices_to_quats(np.full((3, 3), np.nan))
