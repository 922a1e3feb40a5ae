"""PickPlaceController: Isaac's ten phases, run in a real World with friction-only grasping."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, Franka, PickPlaceController, SimulationError, World
from manip.sim.pick_place_controller import FRANKA_EVENTS_DT

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
    script = Path(__file__).resolve().parents[2] / "examples" / "pick_place_controller.py"
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}"
    assert "done picking and placing" in proc.stdout
