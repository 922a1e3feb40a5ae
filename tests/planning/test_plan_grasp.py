"""plan_grasp / plan_place: the stages, what each may touch, candidate choice, constraints, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from manip import (GraspPlan, InvalidInputError, MotionGenerator, OrientationConstraint, PlanStatus, Pose,
                   UnknownNameError)
from manip import quaternion as quat

TCP = "panda_hand_tcp"
CUBE = [0.5, 0.2, 0.025]


def world():
    return {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]},
                       "cube": {"dims": [0.05, 0.05, 0.05], "pose": CUBE + [1, 0, 0, 0]},
                       "post": {"dims": [0.06, 0.06, 0.3], "pose": [0.5, 0.05, 0.15, 1, 0, 0, 0]}}}


def down(yaw: float) -> np.ndarray:
    return quat.multiply(quat.from_axis_angle([0, 0, 1], yaw), np.array([0.0, 1.0, 0.0, 0.0]))


def top_grasps(height: float = 0.003) -> Pose:
    return Pose.stack([Pose(np.add(CUBE, [0, 0, height]), down(k * np.pi / 2)) for k in range(4)])


@pytest.fixture
def mg():
    return MotionGenerator("franka", world())


def test_grasp_stages_and_the_world_left_as_it_was(mg):
    q0 = mg.default_joint_positions
    plan = mg.plan_grasp(q0, top_grasps(), "cube", link=TCP)
    assert isinstance(plan, GraspPlan) and plan.success, plan.message
    assert plan.stages == ("free", "approach", "lift") and all(s.success for s in plan.segments)
    free, approach, lift = plan.segments
    np.testing.assert_allclose(free.trajectory.positions[-1], approach.trajectory.positions[0])
    np.testing.assert_allclose(approach.trajectory.positions[-1], lift.trajectory.positions[0])
    # the approach ends at the chosen grasp pose; the lift goes 10 cm straight up
    g = top_grasps()[plan.grasp_index]
    dp, dr = mg.fk(approach.goal_q, TCP).distance(g)
    assert dp < 1e-3 and dr < 1e-2
    lifted = mg.fk(lift.goal_q, TCP).position - mg.fk(approach.goal_q, TCP).position
    np.testing.assert_allclose(lifted, [0, 0, 0.10], atol=1e-3)
    # one trajectory, at rest between the stages, through every stage's samples
    traj = plan.trajectory
    assert traj.duration == pytest.approx(sum(s.trajectory.duration for s in plan.segments), abs=3 * traj.dt)
    np.testing.assert_allclose(traj.positions[-1], lift.goal_q)
    assert np.abs(traj.velocities[[0, -1]]).max() == 0.0
    # the generator is not changed: the cube is still an obstacle, nothing is attached
    assert "cube" in mg.world and not mg.checker.attached_objects
    # the approach ends with the fingers around the cube; only they are allowed to touch it
    assert mg.checker.certify_path(approach.trajectory.positions[:2]).certified


def test_a_candidate_whose_hand_would_hit_the_object_is_not_chosen(mg):
    """Candidate 0 puts the TCP 3.5 cm below the cube's top: the palm would hit the cube; the
    others are at a normal height: one of them is chosen, and the message of a plan with only
    the bad one says the approach failed."""
    good = top_grasps()
    bad = Pose(np.add(CUBE, [0, 0, -0.06]), down(0.0))
    plan = mg.plan_grasp(mg.default_joint_positions, Pose.stack([bad] + list(good)), "cube", link=TCP)
    assert plan.success and plan.grasp_index != 0
    only_bad = mg.plan_grasp(mg.default_joint_positions, Pose.stack([bad]), "cube", link=TCP)
    assert not only_bad.success and only_bad.grasp_index is None
    assert "candidate 0" in only_bad.message and ("approach" in only_bad.message or "IK" in only_bad.message)


def test_place_with_an_upright_constraint(mg):
    q0 = mg.default_joint_positions
    grasp = mg.plan_grasp(q0, top_grasps(), "cube", link=TCP)
    assert grasp.success
    mg.attach_object("cube", q=grasp.segment("approach").goal_q, link=TCP)
    upright = OrientationConstraint(axis=(0, 0, 1), direction=(0, 0, -1), tolerance=0.1, link=TCP)
    placements = Pose.stack([Pose([0.4, -0.3, 0.025], quat.from_axis_angle([0, 0, 1], a)) for a in (0.0, 0.4)])
    plan = mg.plan_place(grasp.segment("lift").goal_q, placements, constraints=(upright,))
    assert plan.success, plan.message
    assert plan.stages == ("free", "descend", "retreat")
    carried = np.concatenate([s.trajectory.at_time(np.arange(0, s.trajectory.duration, 1e-3))[0]
                              for s in plan.segments[:2]])
    assert upright.tilt(mg.kinematics, carried).max() <= 0.1
    # the object is at the placement when released
    att = mg.checker.attached_objects["cube"]
    at = mg.fk(plan.segment("descend").goal_q, TCP) @ att.pose_in_link
    dp, _ = at.distance(placements[plan.grasp_index])
    assert dp < 2e-3
    assert mg.checker.attached_objects  # still attached: the caller detaches when it releases


def test_bad_input(mg):
    q0 = mg.default_joint_positions
    with pytest.raises(UnknownNameError, match="object_name.*mug"):
        mg.plan_grasp(q0, top_grasps(), "mug", link=TCP)
    with pytest.raises(InvalidInputError, match="grasps"):
        mg.plan_grasp(q0, np.zeros((4, 7)), "cube", link=TCP)
    with pytest.raises(InvalidInputError, match="approach"):
        mg.plan_grasp(q0, top_grasps(), "cube", approach=-0.1, link=TCP)
    with pytest.raises(InvalidInputError, match="lift"):
        mg.plan_grasp(q0, top_grasps(), "cube", lift=float("nan"), link=TCP)
    with pytest.raises(InvalidInputError, match="attached object"):
        mg.plan_place(q0, top_grasps())
    with pytest.raises(InvalidInputError, match="placements"):
        mg.attach_object("cube", q=q0, link=TCP)
        mg.plan_place(q0, [0.4, 0, 0.1, 1, 0, 0, 0])


def test_start_in_collision_is_reported_as_the_free_stage(mg):
    q = mg.default_joint_positions.copy()
    q[1], q[3] = 1.5, -0.5  # the arm down through the table
    plan = mg.plan_grasp(q, top_grasps(), "cube", link=TCP)
    assert not plan.success and plan.status is PlanStatus.INVALID_START_WORLD_COLLISION


def test_relative_pose_constraints_are_held_as_they_are_at_the_start_of_the_sequence(mg):
    """A RelativePoseConstraint without a reference holds the relative pose it has when the
    sequence starts (plan_place) or when the object is taken (plan_grasp's lift)."""
    from manip import RelativePoseConstraint

    q0 = mg.default_joint_positions
    rigid = RelativePoseConstraint("panda_link7", TCP)   # two frames of one body: always held
    grasp = mg.plan_grasp(q0, top_grasps(), "cube", link=TCP, constraints=(rigid,))
    assert grasp.success, grasp.message
    mg.attach_object("cube", q=grasp.segment("approach").goal_q, link=TCP)
    placements = Pose.stack([Pose([0.4, -0.3, 0.025], quat.from_axis_angle([0, 0, 1], 0.0))])
    plan = mg.plan_place(grasp.segment("lift").goal_q, placements, constraints=(rigid,))
    assert plan.success, plan.message


def test_a_grasp_whose_every_ik_solution_collides_says_what_it_touches():
    """A cube behind a 35 cm box (round three: benchmarks/unseen_sim.py --random-obstacles,
    episode 9): every grasp IK solution puts panda_link5 into the box. Before, the message
    was "validity_fn rejected every solution found in 100 attempt(s)", naming nothing."""
    cube = [0.645, 0.315, 0.027]
    mg = MotionGenerator("franka", {"cuboid": {
        "cube": {"dims": [0.054] * 3, "pose": cube + [1, 0, 0, 0]},
        "box0": {"dims": [0.096, 0.117, 0.346], "pose": [0.419, 0.23, 0.173, 1, 0, 0, 0]}}}, padding=0.01)
    grasps = Pose.stack([Pose(np.add(cube, [0, 0, 0.003]), down(k * np.pi / 2)) for k in range(4)])
    plan = mg.plan_grasp(mg.default_joint_positions, grasps, "cube", link=TCP, approach=0.15, lift=0.15)
    assert plan.status is PlanStatus.IK_FAIL
    assert "validity_fn" not in plan.message
    assert plan.message.count("the one nearest the start: goal in collision") == 4, plan.message
    assert "touches box0" in plan.message, plan.message


def test_a_placement_whose_every_ik_solution_collides_says_what_it_touches():
    """A 6.9 cm cube to put at the example's place position beside a 34 cm box (round four:
    benchmarks/unseen_sim.py --random-obstacles --perturb-all --seed 5500, episode 6): every
    placement's IK solutions put panda_link5 into the box. The message said "validity_fn rejected
    every solution found in 100 attempt(s)" for each of the 8 placements, naming nothing."""
    size = 0.0685
    held = [0.5, 0.2, 0.3]
    box = {"dims": [0.067, 0.1318, 0.3385], "pose": [0.3227, -0.1588, 0.1692, *quat.from_axis_angle([0, 0, 1], 0.6076)]}
    mg = MotionGenerator("franka", {"cuboid": {"cube": {"dims": [size] * 3, "pose": held + [1, 0, 0, 0]},
                                               "box0": box}}, padding=0.01)
    q = mg.ik(Pose(np.add(held, [0, 0, 0.01]), down(0.0)), TCP, seed_q=mg.default_joint_positions).q
    mg.attach_object("cube", q=q, link=TCP)
    placements = Pose.stack([Pose([0.4, -0.35, size / 2 + 0.002], quat.from_axis_angle([0, 0, 1], k * np.pi / 4))
                             for k in range(8)])
    plan = mg.plan_place(q, placements)
    assert plan.status is PlanStatus.IK_FAIL
    assert "validity_fn" not in plan.message
    assert "panda_link5 touches box0" in plan.message, plan.message
