"""The Isaac Sim tutorial wrapper's names: what the tutorial's pick-and-place expects."""

from __future__ import annotations

import numpy as np
import pytest

from manip import InvalidInputError, MotionGenerator, Pose, TutorialMotionGen
from manip.sim import FixedCuboid, Franka, World, create_new_stage
from robot_constants import DOWN_XYZW, FRANKA_READY

READY = list(FRANKA_READY)


@pytest.fixture(scope="module")
def mg() -> TutorialMotionGen:
    m = TutorialMotionGen("franka")
    m.init_motion_gen()
    return m


def test_tutorial_wrapper_holds_a_motion_generator_and_exposes_its_facts(mg):
    assert isinstance(mg.motion_gen, MotionGenerator)
    assert not isinstance(mg, MotionGenerator)  # composition, not inheritance
    assert mg.joint_names == mg.motion_gen.joint_names
    wrapped = TutorialMotionGen(motion_gen=mg.motion_gen)
    assert wrapped.motion_gen is mg.motion_gen
    with pytest.raises(InvalidInputError, match="MotionGenerator"):
        TutorialMotionGen(motion_gen="franka")


def test_tutorial_names_on_motion_generator_are_deprecated_but_work():
    m = MotionGenerator("franka")
    with pytest.warns(DeprecationWarning, match="TutorialMotionGen"):
        sol = m.motion_generate(READY, goal_joint_angles=np.array(READY) + 0.1)
    assert sol is not None and sol["success"]
    with pytest.warns(DeprecationWarning):
        m.set_constraint([1, 1, 1, 0, 0, 0])
    assert m._tutorial_view._hold_vec_weight is not None  # one wrapper keeps the state between calls
    with pytest.raises(AttributeError):
        m.no_such_method


def test_motion_generate_to_a_pose_returns_the_tutorial_dict(mg):
    goal = [0.45, 0.2, 0.3, *DOWN_XYZW]
    sol = mg.motion_generate(READY, goal_end_effector_pose=goal)
    assert sol is not None and sol["success"]
    assert sol["joint_names"] == mg.joint_names
    assert sol["interpolation_dt"] == pytest.approx(1 / 60)
    n = len(sol["positions"])
    assert all(len(sol[k]) == n for k in ("velocities", "accelerations", "jerks"))
    np.testing.assert_allclose(sol["positions"][0], READY, atol=1e-9)
    reached = Pose.from_xyz_xyzw(mg.fk(sol["positions"][-1]))
    dp, dr = reached.distance(Pose.from_xyz_xyzw(goal))
    assert dp <= 1e-3 and dr <= 0.01


def test_motion_generate_joint_goal_and_failures(mg):
    goal = np.array(READY) + 0.3
    sol = mg.motion_generate(READY, goal_joint_angles=goal)
    np.testing.assert_allclose(sol["positions"][-1], goal, atol=1e-6)
    assert mg.motion_generate(READY, goal_end_effector_pose=[2.0, 0, 0.3, *DOWN_XYZW]) is None
    with pytest.raises(InvalidInputError, match="exactly one"):
        mg.motion_generate(READY)


def test_fk_ik_in_xyzw_order():
    t = TutorialMotionGen("franka")
    pose = t.fk(READY)
    assert len(pose) == 7
    typed = MotionGenerator.fk(t, np.array(READY))
    np.testing.assert_allclose(pose, typed.to_xyz_xyzw())
    q = t.ik(pose)
    assert q is not None
    np.testing.assert_allclose(t.fk(q)[:3], pose[:3], atol=1e-3)
    assert t.ik([2.0, 0.0, 0.3, *DOWN_XYZW]) is None
    batch = t.ik_batch([pose, [2.0, 0.0, 0.3, *DOWN_XYZW]])
    assert batch[0] is not None and batch[1] is None
    assert t.wxyz_to_xyzw([1, 0, 0, 0]) == [0, 0, 0, 1] and t.xyzw_to_wxyz([0, 0, 0, 1]) == [1, 0, 0, 0]
    assert t.wxzy_to_xyzw([0.0, 1.0, 0.0, 0.0]) == [1.0, 0.0, 0.0, 0.0]


def test_set_constraint_holds_the_orientation(mg):
    start = np.asarray(mg.ik([0.45, 0.0, 0.35, *DOWN_XYZW], seed_joint_angles=READY))
    tilted = Pose([0.45, 0.1, 0.30], [0.0, 0.9659, 0.2588, 0.0])  # asks for a 30 degree yaw too
    mg.set_constraint([1, 1, 1, 0, 0, 0])
    try:
        sol = mg.motion_generate(start, goal_end_effector_pose=tilted.to_xyz_xyzw())
    finally:
        mg.reset_constraint()
    assert sol is not None
    poses = mg.motion_gen.fk(np.asarray(sol["positions"]))
    held = mg.motion_gen.fk(start).quaternion
    _, rot = poses.distance(Pose(poses.position, np.tile(held, (len(poses), 1))))
    assert rot.max() < 0.01
    with pytest.raises(InvalidInputError, match="6 finite weights"):
        mg.set_constraint([1, 1, 1])


def test_world_sync_and_actions_drive_the_simulated_franka(mg):
    World.clear_instance()
    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.scene.add(FixedCuboid("/World/wall", name="wall", position=[0.5, 0.0, 0.25], size=1.0, scale=[0.3, 0.04, 0.5]))
    world.reset()
    mg.update_obstacle_from_world(world, "/World/Franka", ignore_prim_paths=["/World/defaultGroundPlane"])
    assert mg.world.names == ["wall"]
    with pytest.raises(InvalidInputError, match="prim paths"):
        mg.update_obstacle_from_world(world, "/World/Nope")
    start = franka.get_joint_positions()[:7]
    goal = np.asarray(mg.ik([0.45, -0.3, 0.3, *DOWN_XYZW], seed_joint_angles=start))
    sol = mg.motion_generate(start, goal_joint_angles=goal)
    actions = mg.convert_solution_to_actions(sol, franka)
    assert len(actions) == len(sol["positions"]) - 1
    controller = franka.get_articulation_controller()
    for action in actions:
        controller.apply_action(action)
        world.step(render=False)
    for _ in range(60):
        world.step(render=False)
    np.testing.assert_allclose(franka.get_joint_positions()[:7], goal, atol=0.02)
    mg.update_world({})
    World.clear_instance()
