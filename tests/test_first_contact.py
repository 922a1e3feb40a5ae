"""What a new user meets first (issue 27, "what a new user hits next"), tried as they try it:
the simulated ground under the robot, the robot's own 9-value state, why a pose goal has no
IK solution, robot and cuRobo file names, the quaternion order, the viewer on a machine
without a display, and the examples' output."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from manip import MotionGenerator, Pose, TutorialMotionGen
from manip.errors import InvalidInputError, UnknownNameError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TABLE = {"cuboid": {"table": {"dims": [0.8, 1.2, 0.04], "pose": [0.55, 0, -0.02, 1, 0, 0, 0]}}}
DOWN = [0, 1, 0, 0]  # (w, x, y, z): the Franka's hand pointing down
ARM = [f"panda_joint{i}" for i in range(1, 8)]


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka", TABLE)


def franka_on_the_ground():
    from manip.sim import DynamicCuboid, Franka, World

    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0, 0.3], size=0.05))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    return world, franka


# ---------------------------------------------------------------------------- the simulated ground
def test_the_ground_the_robot_stands_on_reads_into_the_planner_without_ignore(fresh_world):
    world, franka = franka_on_the_ground()
    world.reset()
    for _ in range(30):
        world.step(render=False)
    mg = MotionGenerator("franka")
    cfg = mg.update_world_from_sim(world, franka)
    assert set(cfg.names) == {"default_ground_plane", "cube"}  # nothing dropped
    q = franka.get_joint_positions()
    assert q.shape == (9,)
    assert not mg.check_collision(q) and mg.distance(q) > 0.05
    result = mg.plan_pose(q, Pose([0.4, 0.2, 0.3], DOWN))
    assert result.success, result.message
    assert list(result.trajectory.joint_names) == ARM  # the arm's motion
    # the ground is still an obstacle for every moving link: a hand below it is refused, saying why
    below = mg.plan_pose(q, Pose([0.4, 0.2, -0.05], DOWN))
    assert below.status.name == "IK_FAIL"
    assert "touches default_ground_plane" in below.message, below.message


def test_reading_the_world_before_its_first_reset_says_to_reset(fresh_world):
    world, franka = franka_on_the_ground()
    with pytest.raises(InvalidInputError, match=r"world\.reset\(\)"):
        MotionGenerator("franka").update_world_from_sim(world, franka)


def test_only_obstacles_below_the_base_are_exempt_from_the_base_link():
    """A box under the base frame's z = 0 touches panda_link0 and is no collision; the same
    box 1 cm higher, into panda_link0, is one (no real obstacle is dropped)."""
    support = {"cuboid": {"floor": {"dims": [2.0, 2.0, 0.1], "pose": [0, 0, -0.05, 1, 0, 0, 0]}}}
    into_base = {"cuboid": {"floor": {"dims": [2.0, 2.0, 0.1], "pose": [0, 0, -0.04, 1, 0, 0, 0]}}}
    q = MotionGenerator("franka").default_joint_positions
    on_floor = MotionGenerator("franka", support)
    assert not on_floor.check_collision(q)
    assert on_floor.plan_joints(q, q + 0.1).success
    sunk = MotionGenerator("franka", into_base)
    assert sunk.check_collision(q)
    result = sunk.plan_joints(q, q + 0.1)
    assert result.status.name == "INVALID_START_WORLD_COLLISION"
    assert "panda_link0 touches floor" in result.message


# ---------------------------------------------------------------------------- the robot's full state
def test_a_full_franka_state_of_9_values_plans_the_arm(mg):
    q7 = mg.default_joint_positions
    q9 = np.r_[q7, 0.04, 0.04]
    assert mg.fk(q9).isclose(mg.fk(q7))
    result = mg.plan_joints(q9, np.r_[q7 + 0.2, 0.0, 0.0])
    assert result.success, result.message
    np.testing.assert_allclose(result.trajectory.positions[0], q7)
    assert result.trajectory.positions.shape[1] == 7
    assert mg.plan_pose(q9, Pose([0.5, 0.2, 0.3], DOWN)).success


@pytest.mark.parametrize("n", [8, 10])
def test_another_length_names_the_arm_joints_to_pass(mg, n):
    with pytest.raises(InvalidInputError, match=re.escape("start_q[:7]")):
        mg.plan_pose(np.zeros(n), Pose([0.5, 0.2, 0.3], DOWN))


# ---------------------------------------------------------------------------- why IK failed
def test_a_goal_out_of_reach_says_how_far_the_arm_reaches(mg):
    result = mg.plan_pose(mg.default_joint_positions, Pose([2.0, 0.0, 0.3], DOWN))
    assert result.status.name == "IK_FAIL"
    assert "OUT_OF_REACH" in result.message and "reaches at most 0.986 m" in result.message, result.message


def test_a_goal_inside_the_table_says_what_it_touches(mg):
    result = mg.plan_pose(mg.default_joint_positions, Pose([0.5, 0.0, 0.0], DOWN))
    assert result.status.name == "IK_FAIL"
    assert re.search(r"panda_hand touches table \(\d+\.\d mm deep", result.message), result.message


def test_collision_free_ik_inside_the_table_says_what_it_touches(mg):
    """`ik(collision_free=True)` names the contact as `plan_pose` does, not only "rejected"."""
    result = mg.ik(Pose([0.5, 0.0, 0.0], DOWN), collision_free=True)
    assert not result.success and result.status.name == "REJECTED_BY_VALIDITY"
    assert re.search(r"nearest seed_q: goal in collision: panda_hand touches table \(\d+\.\d mm deep",
                     result.message), result.message
    # a validity_fn of the caller's own is not second-guessed: its message stays generic
    own = mg.ik(Pose([0.5, 0.0, 0.0], DOWN), validity_fn=lambda Q: np.zeros(len(Q), dtype=bool))
    assert own.status.name == "REJECTED_BY_VALIDITY" and "touches" not in own.message, own.message


# ---------------------------------------------------------------------------- names
def test_robot_names_in_any_case():
    assert MotionGenerator("Franka").config.name == "franka"
    with pytest.raises(UnknownNameError, match="available: dual_franka, dual_ur5, franka, kinova, ur10, ur5, xarm7"):
        MotionGenerator("Frank")


def test_the_tutorial_wrapper_takes_curobos_franka_file():
    curobo = TutorialMotionGen("franka.yml")
    assert curobo.joint_names == ARM + ["panda_finger_joint1", "panda_finger_joint2"]
    start = curobo.default_joint_positions
    # cuRobo's franka.yml: ee_link is panda_hand; poses are [x, y, z, qx, qy, qz, qw]
    hand = curobo.motion_gen.fk(start[:7])
    assert np.allclose(curobo.fk(start), hand.to_xyz_xyzw())
    goal = Pose([0.45, 0.2, 0.35], DOWN).to_xyz_xyzw().tolist()
    solution = curobo.motion_generate(start, goal)
    assert solution is not None
    end = np.asarray(solution["positions"][-1])
    assert curobo.motion_gen.fk(end[:7]).isclose(Pose([0.45, 0.2, 0.35], DOWN), 1e-3, 1e-2)


def test_curobos_file_of_another_ur_version_says_what_to_use():
    with pytest.raises(UnknownNameError, match="robot='ur5'"):
        TutorialMotionGen("ur5e.yml")


# ---------------------------------------------------------------------------- the viewer without a display
def run_example(script: str, *args: str, env: dict | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(EXAMPLES / script), *args], capture_output=True, text=True,
                          timeout=timeout, env=env)


def no_display_env() -> dict:
    return {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}


def test_the_viewer_without_a_display_points_to_the_web_viewer():
    proc = run_example("pick_and_place.py", "--viewer", "--episodes", "1", env=no_display_env())
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "no display" in proc.stderr and "--viewer web" in proc.stderr, proc.stderr


def test_pick_and_place_in_the_browser_serves_after_its_episodes_until_ctrl_c(tmp_path):
    pytest.importorskip("viser", reason="the web viewer needs the viz extra")
    proc = subprocess.Popen([sys.executable, str(EXAMPLES / "pick_and_place.py"), "--viewer", "web", "--episodes",
                             "1", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        lines = []
        for line in proc.stdout:  # until the example says the episodes are done and the page stays up
            lines.append(line)
            if "press Ctrl-C" in line:
                break
        text = "".join(lines)
        assert "press Ctrl-C" in text, text + proc.stderr.read()
        assert "served until Ctrl-C" in text  # said when it starts
        url = re.search(r"http://localhost:\d+", text).group(0)
        with urllib.request.urlopen(url, timeout=30) as page:  # still serving after the episodes
            assert page.status == 200
        assert proc.poll() is None
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, out + err
    assert "placed 1/1 episodes" in out


# ---------------------------------------------------------------------------- the examples' output
def test_forward_kinematics_prints_quaternions_in_one_labelled_order():
    proc = run_example("forward_kinematics.py", "--batch", "2")
    assert proc.returncode == 0, proc.stderr
    assert "qx, qy, qz, qw" not in proc.stdout
    assert "quaternion (w, x, y, z)" in proc.stdout and "[x, y, z, qw, qx, qy, qz]" in proc.stdout


def test_inverse_kinematics_uses_no_deprecated_call():
    proc = run_example("inverse_kinematics.py", "--batch", "20")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Warning" not in proc.stderr, proc.stderr


def test_the_tutorial_port_is_quiet_headless_unless_verbose():
    quiet = run_example("tutorial_pick_and_place.py", "--steps", "30")
    assert "Please click PLAY" not in quiet.stdout
    assert len(quiet.stdout.splitlines()) <= 3, quiet.stdout
    assert "--verbose" in quiet.stdout and "from the place position" in quiet.stdout
    verbose = run_example("tutorial_pick_and_place.py", "--steps", "30", "--verbose")
    assert "Please click PLAY to start." in verbose.stdout
