"""Rotation utilities: conventions (R = Rz Ry Rx extrinsic, wxyz) and round trips."""

from __future__ import annotations

import math

import numpy as np
import pytest

from manip.sim import (
    euler_angles_to_quat,
    quat_to_euler_angles,
    quat_to_rot_matrix,
    rot_matrix_to_quat,
)


def test_known_rotations():
    c = math.cos(math.pi / 4)
    assert np.allclose(euler_angles_to_quat([0, 0, math.pi / 2]), [c, 0, 0, c])
    assert np.allclose(euler_angles_to_quat([90, 0, 0], degrees=True), [c, c, 0, 0])
    assert np.allclose(quat_to_rot_matrix([c, 0, 0, c]) @ [1, 0, 0], [0, 1, 0])


def test_extrinsic_is_rz_ry_rx_and_intrinsic_is_rx_ry_rz():
    a = np.array([0.3, -0.5, 1.2])
    rx = quat_to_rot_matrix(euler_angles_to_quat([a[0], 0, 0]))
    ry = quat_to_rot_matrix(euler_angles_to_quat([0, a[1], 0]))
    rz = quat_to_rot_matrix(euler_angles_to_quat([0, 0, a[2]]))
    assert np.allclose(quat_to_rot_matrix(euler_angles_to_quat(a)), rz @ ry @ rx)
    assert np.allclose(quat_to_rot_matrix(euler_angles_to_quat(a, extrinsic=False)), rx @ ry @ rz)


@pytest.mark.parametrize("extrinsic", [True, False])
def test_round_trips(extrinsic):
    rng = np.random.default_rng(0)
    for _ in range(100):
        a = rng.uniform([-math.pi, -1.5, -math.pi], [math.pi, 1.5, math.pi])
        q = euler_angles_to_quat(a, extrinsic=extrinsic)
        assert np.allclose(quat_to_euler_angles(q, extrinsic=extrinsic), a, atol=1e-9)
        qq = rot_matrix_to_quat(quat_to_rot_matrix(q))
        assert np.allclose(qq, q if q[0] >= 0 else -q, atol=1e-9)
