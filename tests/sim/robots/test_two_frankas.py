"""Two Frankas in one World (Isaac's multi-robot pattern) driven by one `dual_franka` plan:
each robot gets its own arm's ArticulationActions and tracks the plan; the planner reads the
World in the combined base frame, skipping both robots."""

from __future__ import annotations

import numpy as np
import pytest

from manip import MotionGenerator, Pose
from manip.errors import InvalidInputError, UnknownNameError

DOWN = [0.0, 1.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def dual() -> MotionGenerator:
    return MotionGenerator("dual_franka")


@pytest.fixture
def two_frankas(fresh_world, dual):
    from manip.sim import FixedCuboid, Franka

    world = fresh_world(gravity=(0.0, 0.0, -9.81))
    left = world.scene.add(Franka("/World/left_franka", name="left_franka",
                                  position=dual.config.arms[0].base_pose.position))
    right = world.scene.add(Franka("/World/right_franka", name="right_franka",
                                   position=dual.config.arms[1].base_pose.position))
    world.scene.add(FixedCuboid("/World/post", name="post", position=[0.8, 0.0, 0.2], size=1.0, scale=[0.1, 0.1, 0.4]))
    world.reset()
    return world, left, right


def test_each_robot_tracks_its_arm_of_one_plan(dual, two_frankas):
    from manip.sim.playback import play_trajectory

    world, left, right = two_frankas
    q0 = dual.default_joint_positions
    plan = dual.plan_poses(q0, {"left_panda_hand": Pose([0.45, 0.1, 0.3], DOWN),
                                "right_panda_hand": Pose([0.5, -0.15, 0.25], DOWN)}, seed=0)
    assert plan.success, plan.message
    traj = plan.trajectory
    actions = traj.to_articulation_actions(left)
    assert len(actions) == traj.num_samples - 1
    np.testing.assert_array_equal(actions[5].joint_positions, traj.positions[6, :7])
    np.testing.assert_array_equal(traj.to_articulation_actions(right)[5].joint_positions, traj.positions[6, 7:])
    np.testing.assert_array_equal(actions[0].joint_indices, np.arange(7))
    for robot in (left, right):
        robot.set_joint_positions(q0[:7] if robot is left else q0[7:], np.arange(7))
    played = play_trajectory(world, [left, right], traj)
    assert played.shape == traj.positions.shape
    for link in ("left_panda_hand", "right_panda_hand"):
        error = np.linalg.norm(dual.fk(played, link).position - dual.fk(traj.positions, link).position, axis=-1)
        assert error.max() < 0.02, link
    # the World's hands are where the planner's combined FK puts them
    for robot, link in ((left, "left_panda_hand_tcp"), (right, "right_panda_hand_tcp")):
        q = np.concatenate([left.get_joint_positions()[:7], right.get_joint_positions()[:7]])
        p, _ = robot.end_effector.get_world_pose()
        assert np.linalg.norm(np.asarray(p) - dual.fk(q, link).position) < 1e-3


def test_the_arm_is_chosen_by_name_or_prefix(dual, two_frankas):
    _, left, right = two_frankas
    traj = dual.plan_joints(dual.default_joint_positions, dual.default_joint_positions + 0.1, seed=0).trajectory
    by_prefix = traj.to_articulation_actions(left, prefix="right_")
    np.testing.assert_array_equal(by_prefix[3].joint_positions, traj.positions[4, 7:])

    class Unnamed:
        name = "arm_a"
        prim_path = "/World/arm_a"
        dof_names = left.dof_names

    with pytest.raises(InvalidInputError, match=r"\['left_', 'right_'\].*prefix="):
        traj.to_articulation_actions(Unnamed())
    with pytest.raises(UnknownNameError, match="prefix.*'middle_'"):
        traj.to_articulation_actions(left, prefix="middle_")


def test_the_planner_reads_the_world_in_the_combined_base_frame(dual, two_frankas):
    world, left, right = two_frankas
    mg = MotionGenerator("dual_franka")
    cfg = mg.update_world_from_sim(world, [left, right])
    names = [o.name for o in cfg]
    assert "post" in names and not any("panda" in n for n in names)
    post = next(o for o in cfg if o.name == "post")
    np.testing.assert_allclose(post.pose.position, [0.8, 0.0, 0.2], atol=1e-9)
