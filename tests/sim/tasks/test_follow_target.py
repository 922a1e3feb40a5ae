"""Isaac's follow-target example with its imports changed, the FollowTarget task and the
RMPFlowController (a QP controller under Isaac's name) in the simulator."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (
    ArticulationAction,
    FixedCuboid,
    FollowTarget,
    RMPFlowController,
    SimulationApp,
    SimulationError,
    World,
)
from robot_constants import REPO_ROOT

EXAMPLES = REPO_ROOT / "examples"


def contacts_between(world: World, robot_prefix: str, geom_id: int) -> int:
    m, d = world.model, world.data
    n = 0
    for c in d.contact[: d.ncon]:
        g1, g2 = int(c.geom1), int(c.geom2)
        other = g2 if g1 == geom_id else g1 if g2 == geom_id else None
        if other is not None and m.body(m.geom_bodyid[other]).name.startswith(robot_prefix):
            n += 1
    return n


def test_isaacs_follow_target_example_runs_with_its_imports_changed():
    # Isaac's standalone follow-target example (omni.isaac.franka), imports changed to
    # manip.sim; the loop is bounded because a headless app runs until closed.
    simulation_app = SimulationApp({"headless": True})
    my_world = World(stage_units_in_meters=1.0)
    my_task = FollowTarget(name="follow_target_task")
    my_world.add_task(my_task)
    my_world.reset()
    task_params = my_world.get_task("follow_target_task").get_params()
    franka_name = task_params["robot_name"]["value"]
    target_name = task_params["target_name"]["value"]
    my_franka = my_world.scene.get_object(franka_name)
    my_controller = RMPFlowController(name="target_follower_controller", robot_articulation=my_franka)
    articulation_controller = my_franka.get_articulation_controller()
    reset_needed = False
    steps = 0
    while simulation_app.is_running() and steps < 150:
        my_world.step(render=True)
        if my_world.is_stopped() and not reset_needed:
            reset_needed = True
        if my_world.is_playing():
            if reset_needed:
                my_world.reset()
                my_controller.reset()
                reset_needed = False
            observations = my_world.get_observations()
            actions = my_controller.forward(
                target_end_effector_position=observations[target_name]["position"],
                target_end_effector_orientation=observations[target_name]["orientation"],
            )
            articulation_controller.apply_action(actions)
        steps += 1
    simulation_app.close()

    assert isinstance(actions, ArticulationAction)
    assert len(actions.joint_positions) == 7 and len(actions.joint_velocities) == 7
    assert list(actions.joint_indices) == list(range(7))
    assert franka_name == "my_franka" and target_name == "target"
    assert my_task.target_reached()
    assert my_task.calculate_metrics()["end_effector_to_target_distance"] < 0.01
    assert np.allclose(my_task.target.get_color(), [0.0, 1.0, 0.0])  # turned green when reached
    obs = my_world.get_observations()
    assert set(obs[franka_name]) == {"joint_positions", "joint_velocities"}
    assert set(obs[target_name]) == {"position", "orientation"}


def test_obstacle_in_the_way_is_never_touched_and_the_arm_recovers():
    world = World()
    task = FollowTarget(target_position=[0.45, 0.0, 0.45])
    world.add_task(task)
    world.reset()
    franka = task.robot
    controller = RMPFlowController("follow", franka)
    # A wall between the hand and a target behind it; reset so that it collides in the simulation.
    wall = world.scene.add(FixedCuboid("/World/Wall", name="wall", position=[0.55, 0.0, 0.4], size=1.0,
                                       scale=[0.04, 0.6, 0.6]))
    world.reset()
    controller.add_obstacle(wall)
    behind = np.array([0.7, 0.0, 0.45])
    contacts = 0
    for _ in range(240):
        franka.apply_action(controller.forward(behind, [0.0, 1.0, 0.0, 0.0]))
        world.step(render=False)
        contacts += contacts_between(world, franka.prim_path + "/", wall.geom_id)
    assert contacts == 0
    r = controller.last_result
    assert r.solved and r.position_error > 0.1  # stopped in front of the wall
    q = franka.get_joint_positions()[:7]
    assert controller.controller.clearance(q)[0] > 0.0
    assert np.max(np.abs(franka.get_joint_velocities()[:7])) < 0.05  # at rest there
    # The target comes back in front of the wall: followed again.
    front = np.array([0.4, 0.1, 0.5])
    for _ in range(150):
        franka.apply_action(controller.forward(front, [0.0, 1.0, 0.0, 0.0]))
        world.step(render=False)
        contacts += contacts_between(world, franka.prim_path + "/", wall.geom_id)
    assert contacts == 0
    assert np.linalg.norm(franka.end_effector.get_world_pose()[0] - front) < 0.01
    controller.remove_obstacle(wall)
    assert controller.controller.collision_pair_counts[0] == 0
    with pytest.raises(InvalidInputError, match="not added"):
        controller.remove_obstacle(wall)


def test_task_obstacles_and_params(caplog):
    world = World()
    task = FollowTarget()
    world.add_task(task)
    world.reset()
    cube = task.add_obstacle()
    assert task.obstacles_exist() and task.get_obstacle_to_delete() is cube
    assert np.allclose(cube.get_world_pose()[0], [0.1, 0.1, 1.0])
    controller = RMPFlowController("follow", task.robot)
    controller.add_obstacle(cube)
    with caplog.at_level("WARNING"):
        controller.add_obstacle(cube)   # Isaac's Lula world warns and keeps it once
    assert "already added" in caplog.text
    assert controller.controller.world.names == [cube.prim_path]
    task.remove_obstacle()
    assert not task.obstacles_exist()
    with pytest.raises(InvalidInputError, match="no obstacles"):
        task.remove_obstacle()
    task.set_params(target_position=[0.4, 0.2, 0.3])
    assert np.allclose(task.get_params()["target_position"]["value"], [0.4, 0.2, 0.3])
    with pytest.raises(InvalidInputError, match="add_obstacle"):
        controller.add_obstacle(task.robot)


def test_position_only_targets_and_bad_input():
    world = World()
    task = FollowTarget()
    world.add_task(task)
    world.reset()
    franka = task.robot
    controller = RMPFlowController("follow", franka)
    goal = np.array([0.45, -0.1, 0.35])
    for _ in range(120):
        franka.apply_action(controller.forward(goal))  # orientation None: position only
        world.step(render=False)
    assert np.linalg.norm(franka.end_effector.get_world_pose()[0] - goal) < 0.01
    assert controller.last_result.orientation_error == 0.0
    with pytest.raises(InvalidInputError, match="target_end_effector_position"):
        controller.forward([np.nan, 0.0, 0.5])
    with pytest.raises(InvalidInputError, match="target_end_effector_position"):
        controller.forward([0.5, 0.0])
    with pytest.raises(InvalidInputError, match="target_end_effector_orientation"):
        controller.forward([0.5, 0.0, 0.4], [0.0, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="physics_dt"):
        RMPFlowController("x", franka, physics_dt=0.0)


def test_forward_before_reset_is_a_clear_error():
    world = World()
    task = FollowTarget()
    world.add_task(task)
    task.set_up_scene(world.scene)  # objects exist, nothing simulated yet
    controller = RMPFlowController("follow", task.robot)
    with pytest.raises(SimulationError, match="reset"):
        controller.forward([0.4, 0.0, 0.4])


def test_reactive_controller_reads_a_simulated_world():
    from manip.control import ReactiveController
    from manip.sim import Franka

    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka", position=[0.1, 0.0, 0.0]))
    world.scene.add(FixedCuboid("/World/Box", name="box", position=[0.6, 0.0, 0.3], size=0.1))
    world.reset()
    ctrl = ReactiveController("franka")
    ctrl.set_world(world, franka, ignore=["default_ground_plane"])
    assert ctrl.world.names == ["box"]
    assert np.allclose(ctrl.world.get("box").pose.position, [0.5, 0.0, 0.3])  # in the robot base frame
    with pytest.raises(InvalidInputError, match="robot"):
        ctrl.set_world(world)


def test_follow_target_example_runs_headless():
    proc = subprocess.run([sys.executable, str(EXAMPLES / "follow_target.py"), "--duration", "6"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "tracking error" in proc.stdout and "simulated contacts arm-box: 0" in proc.stdout


def test_a_reset_removes_the_tasks_obstacles_and_the_controller_forgets_them_as_isaac():
    # Isaac: World.reset() calls FollowTarget.cleanup() (its obstacles leave the scene) and
    # RMPFlowController.reset() empties its RmpFlow's world; the follow-target sample then adds
    # new obstacles to both.
    world = World()
    task = FollowTarget()
    world.add_task(task)
    world.reset()
    controller = RMPFlowController("follow", task.robot)
    cube = task.add_obstacle()
    controller.add_obstacle(cube)
    world.reset()
    controller.reset()
    assert not task.obstacles_exist() and not world.scene.object_exists(cube.name)
    assert controller.controller.world.names == []
    again = task.add_obstacle()
    controller.add_obstacle(again)  # raised "already added" when the controller kept its obstacles
    assert controller.controller.world.names == [again.prim_path]
    world.reset()
    target = world.get_observations()["target"]
    # Without controller.reset(), the removed obstacle is named at the next forward.
    with pytest.raises(SimulationError, match="remove_obstacle"):
        controller.forward(target["position"], target["orientation"])


def test_the_rmpflow_controller_places_the_tool_centre_not_a_finger_chosen_as_end_effector():
    """Isaac's Franka RMPFlowController moves its RMPflow end effector (right_gripper) to the
    target whatever the articulation's end effector; with a SingleManipulator whose end effector
    is the right finger (Isaac 5's examples) manip's put the finger on the target."""
    from manip import quaternion as quat
    from manip.sim import ParallelGripper, RigidPrim, SingleManipulator, add_reference_to_stage, get_assets_root_path

    world = World()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd", "/World/Franka")
    gripper = ParallelGripper("/World/Franka/panda_rightfinger", ["panda_finger_joint1", "panda_finger_joint2"],
                              [0.04, 0.04], [0.0, 0.0])
    robot = world.scene.add(SingleManipulator("/World/Franka", end_effector_prim_name="panda_rightfinger",
                                              name="franka", gripper=gripper))
    world.reset()
    controller = RMPFlowController(name="rmp", robot_articulation=robot)
    target, down = np.array([0.45, 0.15, 0.35]), np.array([0.0, 1.0, 0.0, 0.0])
    for _ in range(180):
        robot.apply_action(controller.forward(target_end_effector_position=target,
                                              target_end_effector_orientation=down))
        world.step(render=False)
    hand_p, hand_q = RigidPrim("/World/Franka/panda_hand", name="hand").get_world_pose()
    tcp = hand_p + 0.1034 * quat.to_matrix(hand_q)[:, 2]
    assert np.linalg.norm(tcp - target) < 0.01  # the tool centre on the target (gravity sag aside)
    assert np.linalg.norm(robot.end_effector.get_world_pose()[0] - target) > 0.03  # not the finger
