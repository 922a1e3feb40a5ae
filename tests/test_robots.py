"""The shipped robots beside the Franka (UR5, UR10, Kinova Jaco2, xArm7), each from its folder.

Per robot: the SRDF's disabled pairs make the retract configuration collision-free, MuJoCo and
Pinocchio agree on the tool frame, IK solves reachable poses without wrong claims, the planner
solves seeded scenes scaled to the robot (trajectories verified against the exact meshes), and
manip.sim tracks a planned trajectory. Full counts: benchmarks/robots.py.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from manip.benchmarking.scenes import make_problems
from manip.benchmarking.verify import Verifier
from manip.errors import InvalidInputError
from manip.motion_generator import MotionGenerator
from manip.pose import Pose
from manip.robot_config import available_robots

ROBOTS = ["ur5", "ur10", "kinova", "xarm7"]


@pytest.fixture(scope="module", params=ROBOTS)
def mg(request) -> MotionGenerator:
    return MotionGenerator(request.param, seed=0)


def test_robots_are_shipped() -> None:
    assert set(ROBOTS) | {"franka"} <= set(available_robots())


def test_retract_configuration_is_free_and_srdf_pairs_are_read(mg: MotionGenerator) -> None:
    c = mg.config
    assert not mg.check_collision(c.default_joint_positions)
    if c.srdf_path is not None:
        import xml.etree.ElementTree as ET

        srdf = {frozenset((e.get("link1"), e.get("link2")))
                for e in ET.parse(c.srdf_path).getroot().iter("disable_collisions")}
        assert srdf <= {frozenset(p) for p in c.disabled_collision_pairs}


def test_mujoco_and_pinocchio_agree_on_the_tool_frame(mg: MotionGenerator) -> None:
    c = mg.config
    m = mujoco.MjModel.from_xml_path(str(c.mjcf_path))
    d = mujoco.MjData(m)
    adr = [m.joint(j).qposadr[0] for j in c.arm_joints]
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = rng.uniform(c.lower_limits, c.upper_limits)
        d.qpos[adr] = q
        mujoco.mj_kinematics(m, d)
        pose = mg.fk(q)
        np.testing.assert_allclose(d.site(c.ee_link).xpos, pose.position, atol=1e-6, rtol=0)
        R = d.site(c.ee_link).xmat.reshape(3, 3)
        assert np.linalg.norm(pin.log3(R.T @ pose.as_matrix()[:3, :3])) < 1e-6


def test_ik_solves_reachable_poses_without_wrong_claims(mg: MotionGenerator) -> None:
    rng = np.random.default_rng(2)
    c = mg.config
    Q = []
    while len(Q) < 100:
        q = rng.uniform(c.lower_limits, c.upper_limits)
        if not mg.check_collision(q):
            Q.append(q)
    solved = wrong = 0
    for q in Q:
        goal = mg.fk(q)
        r = mg.ik(goal)
        if r.success:
            solved += 1
            reached = mg.fk(r.q)
            wrong += np.linalg.norm(reached.position - goal.position) > 1e-3
        assert mg.kinematics.within_limits(r.q, 1e-9) or not r.success
    assert wrong == 0
    assert solved >= 99


@pytest.mark.parametrize("kind", ["table", "shelf", "clutter"])
def test_plans_seeded_scenes_with_verified_trajectories(mg: MotionGenerator, kind: str) -> None:
    verifier = Verifier(mg.config)
    for p in make_problems(kind, 2, seed=3, robot=mg.config.name, verifier=verifier):
        mg.update_world(p.world)
        r = mg.plan_joints(p.start, p.goal)
        assert r.success, (p.name, r.status)
        t = r.trajectory
        v = verifier.verify_trajectory(p, t.times, t.positions, t.velocities)
        assert v.valid, (p.name, v)


def test_sim_tracks_a_planned_trajectory_within_2cm(mg: MotionGenerator, fresh_world) -> None:
    from manip.sim.articulations.articulation import Robot
    from manip.sim.playback import play_trajectory
    from manip.sim.robots.robot import robot_model_path
    from manip.sim.scenes.stage import add_reference_to_stage

    c = mg.config
    mg.update_world({})
    start = c.default_joint_positions
    goal = mg.fk(start)
    target = Pose(goal.position + np.array([0.0, 0.15, -0.1]), goal.quaternion)
    plan = mg.plan_pose(start, target)
    assert plan.success, plan.status
    world = fresh_world(gravity=(0.0, 0.0, -9.81))
    add_reference_to_stage(robot_model_path(c.name), "/World/arm")
    robot = world.scene.add(Robot("/World/arm", name="arm"))
    world.reset()
    robot.set_joint_positions(start, plan.trajectory.joint_indices_for(robot))
    played = play_trajectory(world, robot, plan.trajectory)
    tool_error = np.linalg.norm(mg.fk(played).position - mg.fk(plan.trajectory.positions).position, axis=-1)
    assert tool_error.max() < 0.02
    with pytest.raises(InvalidInputError, match="physics step"):
        play_trajectory(world, robot, plan.trajectory.resample(plan.trajectory.dt / 2))


def test_mjcf_files_are_up_to_date(mg: MotionGenerator) -> None:
    from manip.sim.scenes.mjcf_builder import build_mjcf

    text, assets = build_mjcf(mg.config)
    assert mg.config.mjcf_path.read_text() == text, "rerun robots/tools/make_mjcf.py"
    for name, data in assets.items():
        assert (mg.config.mjcf_path.parent / "assets" / name).read_bytes() == data


def test_self_collision_checks_agree_with_coal_on_every_pair(mg: MotionGenerator) -> None:
    """The broadphase (bounding, coarse and fine sphere covers) only drops pairs that coal
    would call free: random configurations (a mix of free and self-colliding ones) get the
    answer of coal's exact check of every enabled pair."""
    c = mg.config
    Q = np.random.default_rng(3).uniform(c.lower_limits, c.upper_limits, size=(300, c.dof))
    got = mg.checker.in_collision_batch(Q)
    expected = np.array([mg.checker.in_collision_exact(q) for q in Q])
    assert 0.02 < expected.mean() < 0.5
    np.testing.assert_array_equal(got, expected)


def test_pairs_proved_clear_keep_their_bound_and_come_back_with_a_larger_self_padding(mg: MotionGenerator) -> None:
    """Self pairs proved clear over the whole joint range (`manip.collision.self_pairs`) keep
    at least their proved distance at random configurations (coal's exact distance), are
    left out of the checks' tables, and are checked again once the self padding exceeds
    their bound."""
    import coal

    from manip.collision.checker import CollisionChecker

    rg = mg.checker.robot
    proved = rg.proved_clear
    if mg.config.name in ("ur5", "ur10", "kinova"):
        assert proved  # e.g. the UR wrist_2 link and the flange link (one joint apart)
    c = mg.config
    Q = np.random.default_rng(4).uniform(c.lower_limits, c.upper_limits, size=(400, c.dof))
    R, p = mg.kinematics.joint_transforms(Q)
    for (a, b), bound in proved.items():
        assert bound > 0
        pa, pb = rg.parts[a], rg.parts[b]
        for n in range(0, Q.shape[0], 4):
            tfs = [coal.Transform3s(R[n, x.joint] @ x.R, p[n, x.joint] + R[n, x.joint] @ x.p) for x in (pa, pb)]
            d = coal.distance(pa.geometry, tfs[0], pb.geometry, tfs[1], coal.DistanceRequest(), coal.DistanceResult())
            assert d >= bound - 1e-9, (pa.name, pb.name, d, bound)
    checked = {tuple(map(int, pr)) for pr in mg.checker.state.self_pairs}
    assert checked.isdisjoint(proved)
    assert checked | set(proved) == set(rg.self_pairs)
    if proved:
        cc = CollisionChecker(c, mg.kinematics)
        cc.self_padding = max(proved.values()) + 1e-3
        assert {tuple(map(int, pr)) for pr in cc.state.self_pairs} == set(rg.self_pairs)


def test_clearance_maps_bound_the_pairs_distance_and_keep_the_answers(mg: MotionGenerator) -> None:
    """Self pairs moved by at most two joints that can touch get a clearance map
    (`manip.collision.pair_maps`): at random configurations (also one turn outside the
    limits) coal's exact distance of a mapped pair is at least the bound of its cell, and
    with a self padding the maps' bounds must beat, the checks still give coal's answers."""
    import coal

    from manip.collision.checker import CollisionChecker

    rg = mg.checker.robot
    maps = rg.clearance_maps
    assert set(maps).isdisjoint(rg.proved_clear)
    if mg.config.name == "ur10":
        names = {(rg.parts[a].link, rg.parts[b].link) for a, b in maps}
        assert ("forearm_link", "wrist_2_link") in names
        assert ("forearm_link", "wrist_3_link") in names  # three joints: wrist_3 swept about its axis
    c = mg.config
    Q = np.random.default_rng(6).uniform(c.lower_limits, c.upper_limits, size=(300, c.dof))
    R, p = mg.kinematics.joint_transforms(Q)
    for (a, b), m in maps.items():
        assert 0.0 < m.proved_fraction <= 1.0
        pa, pb = rg.parts[a], rg.parts[b]
        for n in range(Q.shape[0]):
            bound = m.bound_at(Q[n])
            assert bound == m.bound_at(Q[n] + 2.0 * np.pi)  # a revolute joint's turn
            if not np.isfinite(bound):
                continue
            tfs = [coal.Transform3s(R[n, x.joint] @ x.R, p[n, x.joint] + R[n, x.joint] @ x.p) for x in (pa, pb)]
            d = coal.distance(pa.geometry, tfs[0], pb.geometry, tfs[1], coal.DistanceRequest(), coal.DistanceResult())
            assert d >= bound, (pa.name, pb.name, d, bound)
    if maps:
        cc = CollisionChecker(c, mg.kinematics)
        cc.self_padding = float(np.median([np.median(m.bounds[np.isfinite(m.bounds)]) for m in maps.values()]))
        got = cc.in_collision_batch(Q[:150])
        expected = np.array([cc.in_collision_exact(q) for q in Q[:150]])
        np.testing.assert_array_equal(got, expected)


def test_ur10_forearm_and_wrist_links_reach_coal_only_where_they_can_touch() -> None:
    """The UR10's forearm and wrist_2 link are 19 mm apart at most wrist angles, closer than
    their sphere covers can tell: their clearance map drops them from the self checks at
    most configurations (they were a coal query at every check before the maps); the
    forearm and the wrist_3 link (three joints apart, covers overlapping at 42 % of random
    configurations) likewise through the map against the wrist_3 link swept about its axis."""
    from manip.collision import broadphase

    mg = MotionGenerator("ur10", seed=0)
    ck = mg.checker
    c = mg.config
    Q = np.random.default_rng(7).uniform(c.lower_limits, c.upper_limits, size=(500, c.dof))
    R, p = mg.kinematics.joint_transforms(Q)
    n, k, _ = broadphase.self_candidates(R, p, Q, ck.self_padding + 1e-9, *ck.state.self_tables)
    names = [(ck.state.parts[a].name, ck.state.parts[b].name) for a, b in ck.state.self_pairs[k]]
    share = sum(pair == ("forearm_link", "wrist_2_link") for pair in names) / Q.shape[0]
    assert share < 0.1
    share = sum(pair == ("forearm_link", "wrist_3_link") for pair in names) / Q.shape[0]
    assert share < 0.2


def test_a_swept_part_holds_the_part_at_every_angle() -> None:
    """The solid a clearance map sweeps a part into (`manip.collision.pair_maps`) holds every
    vertex of the part's mesh turned by any angle about its joint's axis."""
    import coal

    from manip.collision.pair_maps import _sweep

    mg = MotionGenerator("ur10", seed=0)
    part = next(p for p in mg.checker.robot.parts if p.link == "wrist_3_link")
    axis = mg.kinematics.joint_specs[part.joint - 1].axis
    solid, radius = _sweep(part, axis)
    V = np.array(part.geometry.vertices(), dtype=float).reshape(-1, 3) @ part.R.T + part.p
    assert radius > 0.0
    point = coal.Sphere(1e-9)
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    for angle in np.random.default_rng(8).uniform(0.0, 2.0 * np.pi, size=20):
        Rot = np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K
        for x in V @ Rot.T:
            inside = coal.collide(solid, coal.Transform3s(), point, coal.Transform3s(np.eye(3), x),
                                  coal.CollisionRequest(), coal.CollisionResult())
            assert inside, (angle, x)
