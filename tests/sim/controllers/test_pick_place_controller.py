"""PickPlaceController: Isaac's ten phases, run in a real World with friction-only grasping."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, PickPlaceController, SimulationError, World
from manip.sim.controllers.pick_place_controller import FRANKA_EVENTS_DT
from robot_constants import REPO_ROOT, load_script

CUBE_START = np.array([0.4, 0.2, 0.025])
PLACE = np.array([0.4, -0.3, 0.025])


def make_scene():
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/Cube", name="cube", position=CUBE_START, size=0.05, mass=0.03))
    return world, franka, cube


def calls_per_phase(events_dt) -> list[int]:
    """Calls each phase lasts: progress accumulates events_dt per call up to 1."""
    return [math.ceil(1.0 / dt - 1e-9) for dt in events_dt]


def test_picks_and_places_the_cube_by_friction():
    world, franka, cube = make_scene()
    world.reset()
    controller = PickPlaceController("pick_place", franka.gripper, franka)
    arm = np.arange(7)
    events, targets, lag = [], [], 0.0
    z_at_event = {}
    budget = sum(calls_per_phase(FRANKA_EVENTS_DT))
    calls = 0
    while not controller.is_done() and calls < budget + 10:
        event = controller.get_current_event()
        if not events or events[-1] != event:
            events.append(event)
            z_at_event[event] = cube.get_world_pose()[0][2]
        position, _ = cube.get_world_pose()
        action = controller.forward(position, PLACE, franka.get_joint_positions())
        assert len(action.joint_positions) == franka.num_dof
        franka.apply_action(action)
        world.step(render=False)
        calls += 1
        target = franka.get_applied_action().joint_positions[arm]
        targets.append(target)
        lag = max(lag, float(np.max(np.abs(franka.get_joint_positions()[arm] - target))))

    assert controller.is_done() and controller.get_current_event() == 10
    assert calls == budget  # Isaac's timing: phase k lasts ceil(1 / events_dt[k]) calls
    assert events == list(range(10))
    assert controller.ik_failures == 0
    # The cube was carried (lifted with the hand, h1 = 0.3 m) and put down at the place position.
    assert z_at_event[5] > 0.25 and z_at_event[6] > 0.25
    for _ in range(30):
        world.step(render=False)
    final, _ = cube.get_world_pose()
    assert np.linalg.norm(final - PLACE) < 0.02
    assert final[2] == pytest.approx(0.025, abs=0.003)  # resting on the ground
    # Smooth targets: no jump between calls; the drives track them closely.
    steps = np.abs(np.diff(np.array(targets), axis=0))
    assert steps.max() < 0.02
    assert lag < 0.02
    # Done: empty actions (every target kept), the phase stays at 10.
    action = controller.forward(cube.get_world_pose()[0], PLACE, franka.get_joint_positions())
    assert np.all(np.isnan(np.asarray(action.joint_positions, dtype=float)))
    assert controller.get_current_event() == 10


def run(world, franka, cube, controller, n: int) -> None:
    for _ in range(n):
        action = controller.forward(cube.get_world_pose()[0], PLACE, franka.get_joint_positions())
        franka.apply_action(action)
        world.step(render=False)


def test_reset_pause_and_custom_events_dt():
    world, franka, cube = make_scene()
    world.reset()
    events_dt = [0.02, 0.02, 0.5, 0.5, 0.02, 0.02, 0.02, 1.0, 0.02, 0.5]
    controller = PickPlaceController("pick_place", franka.gripper, franka, end_effector_initial_height=0.25,
                                     events_dt=events_dt)
    run(world, franka, cube, controller, 50)
    assert controller.get_current_event() == 1
    controller.pause()
    assert controller.is_paused()
    action = controller.forward(cube.get_world_pose()[0], PLACE, franka.get_joint_positions())
    assert np.all(np.isnan(np.asarray(action.joint_positions, dtype=float)))
    assert controller.get_current_event() == 1
    controller.resume()
    run(world, franka, cube, controller, 49)
    assert controller.get_current_event() == 1
    run(world, franka, cube, controller, 1)
    assert controller.get_current_event() == 2
    # The end of phase 1: the hand at the cube (a 5 cm cube's centre), pointing down.
    tcp, q_tcp = franka.end_effector.get_world_pose()
    assert np.linalg.norm(tcp[:2] - CUBE_START[:2]) < 0.01
    assert abs(abs(q_tcp[1]) - 1.0) < 0.01
    controller.reset(events_dt=FRANKA_EVENTS_DT)
    assert controller.get_current_event() == 0 and not controller.is_done() and not controller.is_paused()
    run(world, franka, cube, controller, calls_per_phase(FRANKA_EVENTS_DT)[0] - 1)
    assert controller.get_current_event() == 0
    run(world, franka, cube, controller, 1)
    assert controller.get_current_event() == 1
    # After the reset, phase 0 went up again to h1 = 0.25 m above the cube.
    assert franka.end_effector.get_world_pose()[0][2] == pytest.approx(0.25, abs=0.01)


def test_bad_input_raises_and_leaves_the_state():
    world, franka, cube = make_scene()
    controller = PickPlaceController("pick_place", franka.gripper, franka)
    with pytest.raises(SimulationError, match="world.reset"):
        controller.forward(CUBE_START, PLACE, np.zeros(9))
    world.reset()
    q = franka.get_joint_positions()
    bad_calls = [
        dict(picking_position=[np.nan, 0.2, 0.025], placing_position=PLACE, current_joint_positions=q),
        dict(picking_position=[0.4, 0.2], placing_position=PLACE, current_joint_positions=q),
        dict(picking_position=CUBE_START, placing_position=[0.4, -0.3, 0.025, 1.0], current_joint_positions=q),
        dict(picking_position=CUBE_START, placing_position=PLACE, current_joint_positions=q[:7]),
        dict(picking_position=CUBE_START, placing_position=PLACE, current_joint_positions=np.full(9, np.inf)),
        dict(picking_position=CUBE_START, placing_position=PLACE, current_joint_positions=q,
             end_effector_offset=[0.0, 0.005]),
        dict(picking_position=CUBE_START, placing_position=PLACE, current_joint_positions=q,
             end_effector_orientation=[0.0, 1.0, 0.0]),
    ]
    for kwargs in bad_calls:
        with pytest.raises(InvalidInputError):
            controller.forward(**kwargs)
    assert controller.get_current_event() == 0
    for events_dt in ([0.1] * 9, [0.1] * 9 + [0.0], [0.1] * 9 + [np.nan], [0.1] * 9 + [2.0]):
        with pytest.raises(InvalidInputError, match="events_dt"):
            PickPlaceController("p", franka.gripper, franka, events_dt=events_dt)
        with pytest.raises(InvalidInputError, match="events_dt"):
            controller.reset(events_dt=events_dt)
    with pytest.raises(InvalidInputError, match="height"):
        PickPlaceController("p", franka.gripper, franka, end_effector_initial_height=float("nan"))
    # A valid call after the errors runs phase 0 from the start.
    action = controller.forward(CUBE_START, PLACE, q)
    assert np.all(np.isfinite(np.asarray(action.joint_positions, dtype=float)[:7]))
    assert np.all(np.isnan(np.asarray(action.joint_positions, dtype=float)[7:]))


def test_example_runs_headless():
    """The tutorial port (cube dropped at (0.3, 0.3), goal (-0.3, -0.3)) exits 0: placed within 2 cm."""
    script = REPO_ROOT / "examples" / "pick_place_controller.py"
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
    assert "done picking and placing" in proc.stdout


def test_a_cube_moved_away_before_the_grasp_is_reported_instead_of_carried():
    """Issue 17, item 9: the grasp is checked before carrying; the real reason is reported."""
    world, franka, cube = make_scene()
    world.reset()
    controller = PickPlaceController("pick_place", franka.gripper, franka)
    budget = sum(calls_per_phase(FRANKA_EVENTS_DT))
    moved_to = np.array([0.3, -0.4, 0.025])
    action = None
    for _ in range(budget):
        if controller.get_current_event() == 3 and not np.allclose(cube.get_world_pose()[0], moved_to, atol=0.01):
            cube.set_world_pose(moved_to)  # someone takes the cube away while the fingers close
        action = controller.forward(cube.get_world_pose()[0], PLACE, franka.get_joint_positions())
        franka.apply_action(action)
        world.step(render=False)
        if controller.is_done():
            break
    assert controller.is_done() and controller.get_current_event() == 10
    failure = controller.failure
    assert failure is not None and failure.startswith("the grasp failed")
    assert "not between the fingers" in failure and "nothing is between them" in failure
    # It stopped there: the gripper opens, nothing was carried, no misleading IK failure.
    np.testing.assert_allclose(np.asarray(action.joint_positions, dtype=float)[7:], 0.04)
    assert controller.ik_failures == 0
    for _ in range(30):
        world.step(render=False)
    assert np.all(franka.gripper.get_joint_positions() > 0.035)
    assert np.linalg.norm(cube.get_world_pose()[0] - moved_to) < 0.01
    assert franka.end_effector.get_world_pose()[0][2] < 0.1  # still down at the pick position
    # reset() clears the failure; check_grasp=False carries on as Isaac's controller does.
    controller.reset()
    assert controller.failure is None and not controller.is_done()
    with pytest.raises(InvalidInputError, match="check_grasp"):
        PickPlaceController("p", franka.gripper, franka, check_grasp="yes")


def test_the_flagship_reports_a_failed_grasp_and_picks_the_cube_again_where_it_is():
    """Issue 17, item 9, in examples/pick_and_place.py: a cube moved away while the hand
    descends is not attached to the planner's hand 30 cm away; the episode says why and
    picks it up again where it now lies."""
    pp = load_script(REPO_ROOT / "examples" / "pick_and_place.py", "pick_and_place_grasp_check")
    demo = pp.PickAndPlace(seed=3, verbose=False)
    run_stage, attached = demo.run_stage, []
    moved_to = np.array([0.45, 0.3, 0.025])
    attach = demo.mg.attach_object

    def record_attach(obj, *args, **kwargs):
        attached.append(obj.name)
        return attach(obj, *args, **kwargs)

    def descend_then_take_the_cube(phase, result):
        # the descent is a stage of the grasp plan (`plan_grasp`), executed by run_stage
        run_stage(phase, result)
        if phase == "descend" and len([line for line in demo._ep.log if line.startswith("descend")]) == 1:
            demo.task.set_params(cube_position=moved_to)

    demo.run_stage = descend_then_take_the_cube
    demo.mg.attach_object = record_attach
    r = demo.run_episode(0)
    failed = [line for line in r.log if line.startswith("FAILED")]
    assert len(failed) == 1 and "grasp failed after closing" in failed[0]
    assert "not between the fingers" in failed[0] and "from where the grasp was planned" in failed[0]
    assert "IK_FAIL" not in " ".join(r.log)
    assert len(attached) == 1  # only the real grasp attached the cube
    assert r.placed and r.picks == 2, r.reason
    demo.close()


def _run(world, franka, cube, controller, place, **kwargs) -> None:
    for _ in range(sum(calls_per_phase(FRANKA_EVENTS_DT)) + 10):
        if controller.is_done():
            break
        franka.apply_action(controller.forward(cube.get_world_pose()[0], place, franka.get_joint_positions(), **kwargs))
        world.step(render=False)
    for _ in range(60):
        world.step(render=False)


def test_isaacs_end_effector_orientation_is_the_same_grasp_turned_half_a_turn():
    # Isaac's scripts pass euler_angles_to_quat([0, pi, 0]) = (0, 0, 1, 0): the Franka's wrist
    # could not carry it round to the place position (the cube was dropped 0.38 m from it).
    world, franka, cube = make_scene()
    world.reset()
    controller = PickPlaceController("pick_place", franka.gripper, franka)
    place = np.array([-0.3, -0.3, 0.025])
    _run(world, franka, cube, controller, place, end_effector_orientation=np.array([0.0, 0.0, 1.0, 0.0]))
    assert controller.failure is None and controller.ik_failures == 0
    assert np.linalg.norm(cube.get_world_pose()[0] - place) < 0.01
    # As given, the orientation is the one Isaac's wrist reaches near its limit: it cannot follow.
    world.reset()
    strict = PickPlaceController("strict", franka.gripper, franka, symmetric_grasp=False)
    _run(world, franka, cube, strict, place, end_effector_orientation=np.array([0.0, 0.0, 1.0, 0.0]))
    assert strict.ik_failures > 0 and "could not reach the place position" in strict.failure


def test_an_unreachable_place_stops_with_the_object_held_and_says_why():
    world, franka, cube = make_scene()
    world.reset()
    controller = PickPlaceController("pick_place", franka.gripper, franka)
    _run(world, franka, cube, controller, np.array([1.5, 0.0, 0.025]))
    assert controller.is_done() and "could not reach the place position [1.5, 0.0, 0.025]" in controller.failure
    # Still in the hand, not dropped wherever the arm stopped.
    assert cube.get_world_pose()[0][2] > 0.2
    assert np.linalg.norm(cube.get_world_pose()[0] - franka.end_effector.get_world_pose()[0]) < 0.02


def test_isaac5s_franka_pick_up_example_with_the_right_finger_as_end_effector():
    """Isaac 5's standalone franka_pick_up.py: a SingleManipulator whose end effector is the right
    finger. Isaac's controller places its RMPflow end effector (right_gripper, between the
    fingertips) at the targets whatever the articulation's end effector; manip's drove the finger
    onto the cube, pushed it 14 cm away and reported a failed grasp."""
    from manip.sim import ParallelGripper, SingleManipulator, add_reference_to_stage, get_assets_root_path

    world = World()
    world.scene.add_default_ground_plane()
    add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/FrankaRobotics/FrankaPanda/franka.usd",
                           "/World/Franka")
    gripper = ParallelGripper(end_effector_prim_path="/World/Franka/panda_rightfinger",
                              joint_prim_names=["panda_finger_joint1", "panda_finger_joint2"],
                              joint_opened_positions=np.array([0.05, 0.05]),
                              joint_closed_positions=np.array([0.02, 0.02]), action_deltas=np.array([0.01, 0.01]))
    franka = world.scene.add(SingleManipulator(prim_path="/World/Franka", name="my_franka",
                                               end_effector_prim_path="/World/Franka/panda_rightfinger",
                                               gripper=gripper))
    cube = world.scene.add(DynamicCuboid("/World/Cube", name="cube", position=np.array([0.3, 0.3, 0.3]),
                                         scale=np.array([0.0515, 0.0515, 0.0515]), size=1.0))
    franka.gripper.set_default_state(franka.gripper.joint_opened_positions)
    world.reset()
    controller = PickPlaceController(name="pick_place_controller", gripper=franka.gripper, robot_articulation=franka)
    place = np.array([-0.3, -0.3, 0.0515 / 2.0])
    for _ in range(sum(calls_per_phase(FRANKA_EVENTS_DT)) + 60):
        world.step(render=True)
        franka.apply_action(controller.forward(picking_position=cube.get_local_pose()[0], placing_position=place,
                                               current_joint_positions=franka.get_joint_positions(),
                                               end_effector_offset=np.array([0, 0.005, 0])))
        if controller.is_done():
            break
    assert controller.is_done()
    assert np.linalg.norm(cube.get_world_pose()[0][:2] - place[:2]) < 0.015
