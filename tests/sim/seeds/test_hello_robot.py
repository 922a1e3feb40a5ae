"""Seed 001, 'isaac sim4.2 教程-Core API-Hello robot': the Jetbot in a BaseSample, moved by
its articulation controller, as a WheeledRobot, by a custom controller and by Isaac's
WheelBasePoseController. Each listing is loaded as the Load button does, then played."""

from __future__ import annotations

import numpy as np
import pytest

from seed_glue import Watcher, load, play, run_listing

pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")


def _sample(name: str):
    return run_listing(name, run_name="my_hello_world")["MyHelloWorld"]()


def test_add_robot_prints_dof_before_and_after_the_first_reset(capsys):
    sample = _sample("hr_add_robot.py")
    world = load(sample)
    out = capsys.readouterr().out
    assert "Num of degrees of freedom before first reset: None" in out
    assert "Num of degrees of freedom after first reset: 2" in out
    assert "Joint Positions after first reset: [0. 0.]" in out
    assert sample._jetbot is world.scene.get_object("fancy_robot")


@pytest.mark.parametrize("listing", ["hr_move_robot.py", "hr_wheeled_robot.py"])
def test_random_wheel_velocities_move_the_jetbot(listing):
    np.random.seed(0)
    sample = _sample(listing)
    world = load(sample)
    jetbot = world.scene.get_object("fancy_robot")
    start = jetbot.get_world_pose()[0]
    play(world, 300)
    wheels = jetbot.get_joint_velocities()
    assert np.all(wheels > 0) and np.all(wheels < 5.5)  # tracking 5 * rand(2) rad/s
    assert np.linalg.norm(jetbot.get_world_pose()[0][:2] - start[:2]) > 0.15


def test_cool_controller_drives_a_circle():
    sample = _sample("hr_cool_controller.py")
    world = load(sample)
    jetbot = world.scene.get_object("fancy_robot")
    positions = []
    with Watcher(lambda w: positions.append(jetbot.get_world_pose()[0][:2].copy())):
        play(world, 960)  # 16 s: two turns at pi/4 rad/s
    p = np.array(positions[120:])
    centre = (p.max(axis=0) + p.min(axis=0)) / 2
    radii = np.linalg.norm(p - centre, axis=1)
    assert 0.18 < radii.mean() < 0.3 and radii.std() < 0.03  # v / w = 0.25 m
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1).mean() * 60
    assert speed == pytest.approx(0.2, rel=0.15)


def test_wheel_base_pose_controller_reaches_the_goal():
    sample = _sample("hr_available_controllers.py")
    world = load(sample)
    jetbot = world.scene.get_object("fancy_robot")
    play(world, 900)  # 15 s
    position = jetbot.get_world_pose()[0]
    assert np.linalg.norm(position[:2] - [0.8, 0.8]) < 0.05
    assert np.all(np.abs(jetbot.get_joint_velocities()) < 0.5)  # and stopped there
