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


def test_tutorial_names_on_motion_generator_say_where_they_went():
    # deprecated on MotionGenerator in 0.1, removed in 0.2: the error names the wrapper
    m = MotionGenerator("franka")
    for name in ("motion_generate", "set_constraint", "init_motion_gen"):
        with pytest.raises(AttributeError, match=rf"MotionGenerator\.{name} moved to manip\.TutorialMotionGen"):
            getattr(m, name)
    sol = TutorialMotionGen(motion_gen=m).motion_generate(READY, goal_joint_angles=np.array(READY) + 0.1)
    assert sol is not None and sol["success"]
    with pytest.raises(AttributeError, match="no_such_method"):
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
    assert mg.world.names == ["default_ground_plane", "wall"]  # the ground stays, ignored or not (issue 32)
    with pytest.raises(InvalidInputError, match="prim paths"):
        mg.update_obstacle_from_world(world, "/World/Nope")
    start = franka.get_joint_positions()[:7]
    goal = np.asarray(mg.ik([0.45, -0.3, 0.3, *DOWN_XYZW], seed_joint_angles=start))
    sol = mg.motion_generate(start, goal_joint_angles=goal)
    actions = mg.convert_solution_to_actions(sol, franka)
    assert len(actions) == len(sol["positions"])  # one per time step, the start included (as the wrapper)
    controller = franka.get_articulation_controller()
    for action in actions:
        controller.apply_action(action)
        world.step(render=False)
    for _ in range(60):
        world.step(render=False)
    np.testing.assert_allclose(franka.get_joint_positions()[:7], goal, atol=0.02)
    mg.update_world({})
    World.clear_instance()


# ---------------------------------------------------------------------------- the tutorial's construction
@pytest.fixture(scope="module")
def curobo() -> TutorialMotionGen:
    """Constructed as the Isaac pick-and-place tutorial does."""
    from manip import TutorialMotionGen as CuroboMotionGenerator

    m = CuroboMotionGenerator(
        robot_config_file_name="my_franka_robot_config.yml",
        world_config_file_name="collision_base.yml",
        user_config_file_name="isaac_sim_user_config.toml",
    )
    m.init_motion_gen()
    return m


def test_tutorial_construction_exposes_curobos_joint_space(curobo):
    assert curobo.joint_names == [f"panda_joint{i}" for i in range(1, 8)] + ["panda_finger_joint1", "panda_finger_joint2"]
    assert curobo.default_joint_positions == [0.0, -1.3, 0.0, -2.5, 0.0, 1.0, 0.0, 0.04, 0.04]
    assert curobo.robot_dof == 9 and curobo.base_link == "panda_link0" and curobo.end_effector_link == "ee_link"
    assert curobo.joint_names[:-2] == curobo.motion_gen.joint_names  # the tutorial's [:-2] trimming
    assert curobo.motion_gen.world.names == ["table"]  # collision_base.yml's post under the base
    assert curobo.interpolation_dt == pytest.approx(0.004)  # isaac_sim_user_config.toml
    positional = TutorialMotionGen("my_franka_robot_config.yml", "collision_base.yml")  # cuRobo's order
    assert positional.robot_dof == 9


def test_unknown_config_file_names_list_the_known_ones():
    from manip import UnknownNameError

    with pytest.raises(UnknownNameError, match="my_franka_robot_config.yml"):
        TutorialMotionGen(robot_config_file_name="ur5.yml")
    with pytest.raises(UnknownNameError, match="collision_base.yml"):
        TutorialMotionGen(robot_config_file_name="my_franka_robot_config.yml", world_config_file_name="table.yml")
    with pytest.raises(UnknownNameError, match="isaac_sim_user_config.toml"):
        TutorialMotionGen("my_franka_robot_config.yml", user_config_file_name="mine.toml")
    with pytest.raises(InvalidInputError, match="not both"):
        TutorialMotionGen("franka", robot_config_file_name="my_franka_robot_config.yml")


def test_ee_link_is_the_hand_offset_and_flipped(curobo):
    q = np.array(READY)
    hand = curobo.motion_gen.fk(q)
    ee = Pose.from_xyz_xyzw(curobo.fk(q))
    np.testing.assert_allclose(ee.position, hand.position + 0.1 * hand.rotation[:, 2], atol=1e-9)
    np.testing.assert_allclose(ee.rotation[:, 2], -hand.rotation[:, 2], atol=1e-9)  # pi about y
    assert curobo.fk(list(q) + [0.04, 0.04]) == curobo.fk(q)  # 9 values accepted
    # the identity orientation points the gripper (hand z) down
    q_down = curobo.ik([0.4, 0.1, 0.2, 0.0, 0.0, 0.0, 1.0])
    assert q_down is not None
    np.testing.assert_allclose(curobo.motion_gen.fk(q_down).rotation[:, 2], [0, 0, -1], atol=1e-3)
    np.testing.assert_allclose(curobo.fk(q_down)[:3], [0.4, 0.1, 0.2], atol=1e-3)


def test_tutorial_motion_generate_with_nine_values_and_isaac_actions(curobo):
    start = curobo.default_joint_positions  # 9 values, fingers included
    sol = curobo.motion_generate(start_joint_angles=start, goal_end_effector_pose=[0.4, 0.2, 0.25, 0, 0, 0, 1])
    assert sol is not None and sol["interpolation_dt"] == pytest.approx(0.004)
    assert sol["joint_names"] == curobo.joint_names[:7] and len(sol["positions"][0]) == 7
    assert sol["raw_data"].num_samples == len(sol["positions"])
    np.testing.assert_allclose(curobo.fk(sol["positions"][-1])[:3], [0.4, 0.2, 0.25], atol=1e-3)
    with pytest.raises(InvalidInputError, match="7 or 9"):
        curobo.motion_generate(start[:5], goal_joint_angles=start)

    World.clear_instance()
    create_new_stage()
    world = World()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    actions = curobo.convert_solution_to_isaac_sim_action(solution=sol, robot_prim=franka)
    assert len(actions) == len(sol["positions"])
    a = actions[-1]
    assert a.joint_indices.tolist() == list(range(9))  # the robot's dof order, fingers included
    np.testing.assert_allclose(a.joint_positions, sol["positions"][-1] + [0.04, 0.04])
    np.testing.assert_allclose(a.joint_velocities[7:], 0.0)
    state = curobo.get_joint_state_from_isaac_sim(franka)
    assert state.joint_names == curobo.joint_names[:7]
    np.testing.assert_allclose(state.position, franka.get_joint_positions()[:7])
    # A failed plan is None; converting it says so (was a TypeError from inside the bridge).
    failed = curobo.motion_generate(start_joint_angles=start, goal_end_effector_pose=[2.0, 0, 0.3, 0, 0, 0, 1])
    assert failed is None
    with pytest.raises(InvalidInputError, match="solution is None: motion_generate returns None when planning fails"):
        curobo.convert_solution_to_isaac_sim_action(solution=failed, robot_prim=franka)
    World.clear_instance()


def test_obstacles_from_the_simulator_point_clouds_and_reset_world(curobo, caplog):
    World.clear_instance()
    create_new_stage()
    world = World()
    ground = world.scene.add_default_ground_plane()
    world.scene.add(Franka("/World/MyRobot", name="my_robot"))
    world.scene.add(FixedCuboid("/World/wall", name="wall", position=[0.5, 0.0, 0.25], size=1.0, scale=[0.3, 0.04, 0.5]))
    world.scene.add(FixedCuboid("/World/Target", name="target", position=[0.4, 0.3, 0.05], size=0.05))
    world.reset()
    new = curobo.update_obstacle_from_isaac_sim(world=world, robot_prim_path="/World/MyRobot",
                                                ignore_prim_paths=["/World/MyRobot", ground.prim_path, "Target"])
    kept = ["default_ground_plane", "wall"]  # substrings, as the wrapper; the ground is kept (issue 32)
    assert new.names == kept and curobo.motion_gen.world.names == kept
    World.clear_instance()
    cloud = np.random.default_rng(0).uniform([0.45, -0.1, 0.2], [0.55, 0.1, 0.4], size=(500, 3))
    curobo.update_world_by_pointcloud(cloud)
    assert curobo.motion_gen.world.names == ["world_pointcloud"]
    q_in = curobo.ik([0.5, 0.0, 0.3, 0, 0, 0, 1])
    assert q_in is None  # the cloud's volume is an obstacle now
    with caplog.at_level("WARNING"):
        curobo.update_world_by_pointcloud(np.zeros((10, 2)))  # wrong shape: a warning, nothing changes
    assert "shape" in caplog.text and curobo.motion_gen.world.names == ["world_pointcloud"]
    curobo.reset_world()
    assert curobo.motion_gen.world.names == ["table"]


def test_xyzw_mistakes_are_named_in_the_callers_order(mg):
    """benchmarks/unseen.py: a non-unit [x, y, z, qx, qy, qz, qw] was refused saying "quaternions are
    (w, x, y, z)", the other order than the one the caller used; a ragged list of poses raised numpy's
    "inhomogeneous shape" ValueError."""
    with pytest.raises(InvalidInputError, match=r"\(x, y, z, w\)"):
        mg.ik([0.4, 0.0, 0.3, 0.0, 0.0, 0.0, 2.0])
    with pytest.raises(InvalidInputError, match=r"\(x, y, z, w\)"):
        Pose.from_xyz_xyzw([0.4, 0.0, 0.3, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"poses_xyzw.*pose 1 has 3 values"):
        mg.ik_batch([[0.4, 0.0, 0.3, *DOWN_XYZW], [0.4, 0.0, 0.3]])
    assert Pose.from_xyz_xyzw([0.4, 0.0, 0.3, *DOWN_XYZW]).quaternion.tolist() == [0.0, 1.0, 0.0, 0.0]
