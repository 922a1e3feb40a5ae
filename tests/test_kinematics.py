"""Forward kinematics and Jacobians: batched NumPy == Pinocchio, finite differences, errors."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from manip.errors import InvalidInputError, UnknownNameError
from manip.kinematics import Kinematics
from manip.pose import Pose

LINKS = ["panda_link1", "panda_link4", "panda_link7", "panda_hand", "panda_hand_tcp", "panda_leftfinger"]


def random_configs(k: Kinematics, n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(k.lower, k.upper, (n, k.dof))


def test_model_is_the_seven_arm_joints(franka_kinematics: Kinematics, franka_config):
    k = franka_kinematics
    assert k.dof == 7 and k.model.nq == 7
    assert k.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
    np.testing.assert_array_equal(k.lower, franka_config.lower_limits)
    np.testing.assert_array_equal(k.upper, franka_config.upper_limits)


def test_batched_frames_equal_pinocchio(franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 25, seed=1)
    fids = [k.frame_id(link) for link in LINKS]
    R, p = k.frame_transforms(Q, fids)
    assert R.shape == (25, len(LINKS), 3, 3) and p.shape == (25, len(LINKS), 3)
    for i, q in enumerate(Q):
        pin.framesForwardKinematics(k.model, k.data, q)
        for f, fid in enumerate(fids):
            np.testing.assert_allclose(R[i, f], k.data.oMf[fid].rotation, atol=1e-12)
            np.testing.assert_allclose(p[i, f], k.data.oMf[fid].translation, atol=1e-12)


def test_joint_transforms_start_at_identity(franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 4, seed=2)
    R, p = k.joint_transforms(Q)
    assert R.shape == (4, k.model.njoints, 3, 3) and p.shape == (4, k.model.njoints, 3)
    np.testing.assert_array_equal(R[:, 0], np.broadcast_to(np.eye(3), (4, 3, 3)))
    np.testing.assert_array_equal(p[:, 0], 0.0)
    for i, q in enumerate(Q):
        pin.forwardKinematics(k.model, k.data, q)
        for j in range(1, k.model.njoints):
            np.testing.assert_allclose(R[i, j], k.data.oMi[j].rotation, atol=1e-12)
            np.testing.assert_allclose(p[i, j], k.data.oMi[j].translation, atol=1e-12)


def test_fk_single_and_batched_agree(franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 10, seed=3)
    for link in LINKS:
        batch = k.fk(Q, link)
        assert isinstance(batch, Pose) and batch.is_batch and len(batch) == 10
        for i, q in enumerate(Q):
            single = k.fk(q, link)
            assert not single.is_batch
            assert single.isclose(batch[i], position_tol=1e-12, rotation_tol=1e-7)


def test_fk_of_the_ready_configuration(franka_kinematics: Kinematics, franka_config):
    # The Panda's ready pose: tool centre 0.307 m ahead of the base at 0.487 m, pointing down,
    # the hand flange 0.1034 m above it.
    q = franka_config.default_joint_positions
    tcp = franka_kinematics.fk(q, "panda_hand_tcp")
    hand = franka_kinematics.fk(q, "panda_hand")
    np.testing.assert_allclose(tcp.position, [0.307, 0.0, 0.487], atol=2e-3)
    np.testing.assert_allclose(tcp.rotation[:, 2], [0.0, 0.0, -1.0], atol=1e-3)
    np.testing.assert_allclose(hand.position - tcp.position, [0.0, 0.0, 0.1034], atol=1e-3)



def test_fk_without_a_link_is_the_end_effector(franka_kinematics: Kinematics, franka_config):
    # as MotionGenerator.fk and cuRobo's kin_model.get_state(q): it was a TypeError (link missing)
    q = np.asarray(franka_config.default_joint_positions)
    assert franka_kinematics.fk(q).isclose(franka_kinematics.fk(q, franka_config.ee_link))
    Q = np.stack([q, q + 0.1])
    batch = franka_kinematics.fk(Q)
    assert batch.is_batch and batch[1].isclose(franka_kinematics.fk(Q[1], franka_config.ee_link), 1e-9, 1e-9)

def test_jacobians_equal_pinocchio(franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 10, seed=4)
    for link in ("panda_hand", "panda_link5", "panda_hand_tcp"):
        fid = k.frame_id(link)
        R, p, J = k.frame_jacobians(Q, fid)
        assert J.shape == (10, 6, 7)
        for i, q in enumerate(Q):
            M = k.frame_transform(q, fid)
            np.testing.assert_allclose(R[i], M.rotation, atol=1e-12)
            np.testing.assert_allclose(p[i], M.translation, atol=1e-12)
            np.testing.assert_allclose(J[i], k.frame_jacobian(q, fid), atol=1e-12)


def test_jacobian_matches_finite_differences(franka_kinematics: Kinematics):
    k = franka_kinematics
    fid = k.frame_id("panda_hand_tcp")
    h = 1e-6
    for q in random_configs(k, 5, seed=5):
        _, _, J = k.frame_jacobians(q[None], fid)
        J_fd = np.empty((6, 7))
        for j in range(7):
            dq = np.zeros(7)
            dq[j] = h
            Rp, pp = k.frame_transforms((q + dq)[None], [fid])
            Rm, pm = k.frame_transforms((q - dq)[None], [fid])
            J_fd[:3, j] = (pp[0, 0] - pm[0, 0]) / (2 * h)
            # world angular velocity: log(R(q + h) R(q - h)^T) / 2h
            J_fd[3:, j] = pin.log3(Rp[0, 0] @ Rm[0, 0].T) / (2 * h)
        np.testing.assert_allclose(J[0], J_fd, atol=1e-7)


def test_large_batches(franka_kinematics: Kinematics):
    k = franka_kinematics
    Q = random_configs(k, 20_000, seed=6)
    fid = k.frame_id("panda_hand")
    R, p = k.frame_transforms(Q, [fid])
    idx = [0, 1234, 19_999]
    for i in idx:
        M = k.frame_transform(Q[i], fid)
        np.testing.assert_allclose(p[i, 0], M.translation, atol=1e-12)
    # chunked evaluation of large batches equals the small-batch evaluation
    Rj, pj = k.joint_transforms(Q)
    Rj_small, pj_small = k.joint_transforms(Q[idx])
    np.testing.assert_array_equal(Rj[idx], Rj_small)
    np.testing.assert_array_equal(pj[idx], pj_small)
    Rf, pf, J = k.frame_jacobians(Q, fid)
    np.testing.assert_array_equal(J[idx], k.frame_jacobians(Q[idx], fid)[2])
    np.testing.assert_array_equal(pf, p[:, 0])
    # rotations stay orthonormal
    RtR = np.einsum("nji,njk->nik", R[:, 0], R[:, 0])
    assert np.abs(RtR - np.eye(3)).max() < 1e-12


def test_unknown_frame_lists_the_frames(franka_kinematics: Kinematics):
    with pytest.raises(UnknownNameError) as exc:
        franka_kinematics.frame_id("panda_gripper")
    msg = str(exc.value)
    assert "panda_gripper" in msg and "panda_hand" in msg and "panda_link7" in msg
    with pytest.raises(KeyError):
        franka_kinematics.fk(np.zeros(7), "tool0")


@pytest.mark.parametrize(
    "q, match",
    [
        (np.zeros(6), "panda_joint1"),
        (np.zeros((3, 8)), r"\(7,\)"),
        (np.zeros((2, 2, 7)), "shape"),
        (np.array([0, 0, 0, np.nan, 0, 0, 0]), "non-finite"),
        (np.array([0, 0, 0, np.inf, 0, 0, 0]), "non-finite"),
    ],
)
def test_bad_configurations(franka_kinematics: Kinematics, q: np.ndarray, match: str):
    with pytest.raises(InvalidInputError, match=match):
        franka_kinematics.fk(q, "panda_hand")


def test_limits_helpers(franka_kinematics: Kinematics):
    k = franka_kinematics
    inside = (k.lower + k.upper) / 2
    outside = inside.copy()
    outside[3] = k.upper[3] + 0.1
    assert k.within_limits(inside) and not k.within_limits(outside)
    np.testing.assert_array_equal(k.within_limits(np.stack([inside, outside])), [True, False])
    assert k.within_limits(outside, tolerance=0.2)
    assert k.limit_violations(inside) == []
    (msg,) = k.limit_violations(outside)
    assert "panda_joint4" in msg


@pytest.mark.parametrize("robot", ["franka", "ur5", "kinova", "xarm7", "dual_franka"])
def test_lanes_frames_are_the_per_configuration_frames(robot: str):
    """`_joint_frames_lanes` (what `joint_transforms` runs for batches) gives `_joint_frames`'s
    frames bit for bit, for every batch size around its block size, and `joint_transforms`
    answers the same below and above `FK_LANES_FROM`."""
    from manip import kinematics as km
    from manip.robot_config import load_robot_config

    k = Kinematics(load_robot_config(robot))
    tables = (k._sb_q, k._sb_parent_a, k._sb_table)
    Q = random_configs(k, 3000, seed=7)
    for N in (1, 2, 15, 16, 63, 64, 65, 200, 3000):
        ref = km._joint_frames(Q[:N], *tables)
        for lanes in (1, 8, km.FK_LANES):
            got = km._joint_frames_lanes(Q[:N], *tables, lanes)
            np.testing.assert_array_equal(got[0], ref[0])
            np.testing.assert_array_equal(got[1], ref[1])
    few, many = k.joint_transforms(Q[:km.FK_LANES_FROM - 1]), k.joint_transforms(Q[:200])
    np.testing.assert_array_equal(few[0], many[0][:km.FK_LANES_FROM - 1])
    np.testing.assert_array_equal(few[1], many[1][:km.FK_LANES_FROM - 1])


def test_lanes_frames_of_prismatic_joints():
    """The prismatic term (a fourth table row, times q) too: random tables of a branching chain."""
    from manip import kinematics as km

    rng = np.random.default_rng(8)
    J = 6
    table = rng.normal(size=(J, 4, 16))
    parent = np.array([0, 1, 2, 2, 4, 1], dtype=np.int64)
    q_index = np.array([0, 1, 2, 3, 4, 5], dtype=np.int64)
    Q = rng.uniform(-3.0, 3.0, (150, J))
    ref = km._joint_frames(Q, q_index, parent, table)
    got = km._joint_frames_lanes(Q, q_index, parent, table, 64)
    np.testing.assert_array_equal(got[0], ref[0])
    np.testing.assert_array_equal(got[1], ref[1])
    assert not np.array_equal(ref[1], km._joint_frames(Q, q_index, parent, table[:, :3].copy())[1])
