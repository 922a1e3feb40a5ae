"""Tutorial-style scripts of our own (and cuRobo examples), written as Isaac Sim 4.x users write them (only the
imports differ: omni.isaac... / isaacsim... -> manip.sim), each run as a script and checked
against the simulator's state it leaves (issue 32)."""

from __future__ import annotations

import asyncio
import runpy
from pathlib import Path

import numpy as np
import pytest

from manip import Pose

HERE = Path(__file__).resolve().parent


def run(name: str) -> dict:
    """Run a script as `python name` would: in `__main__`, with the main thread's event loop
    of a fresh interpreter (earlier tests' asyncio.run() leave none)."""
    loop = asyncio.new_event_loop()
    asyncio.set_event_loop(loop)
    try:
        return runpy.run_path(str(HERE / name), run_name="__main__")
    finally:
        asyncio.set_event_loop(None)
        loop.close()


def test_franka_picks_isaacs_default_cube_and_places_it():
    ns = run("franka_pick_place_task.py")
    assert ns["done"]
    np.testing.assert_allclose(ns["target_position"], [-0.3, -0.3, 0.0515 / 2])
    assert np.linalg.norm(ns["cube_position"][:2] - ns["target_position"][:2]) < 0.02
    assert ns["cube_position"][2] == pytest.approx(0.0515 / 2, abs=3e-3)  # resting on the ground


def test_end_effector_follows_the_target():
    ns = run("follow_target.py")
    assert max(ns["errors"]) < 0.02


def test_two_tasks_with_a_jetbot_and_a_franka_each():
    ns = run("robots_and_tasks.py")
    np.testing.assert_allclose(ns["franka_positions"][0], [1.0, -3.0, 0.0], atol=1e-9)  # moved in set_up_scene
    np.testing.assert_allclose(ns["franka_positions"][1], [1.0, -1.0, 0.0], atol=1e-9)  # and offset by its task
    for d in ns["travelled"]:
        assert d == pytest.approx(0.4, rel=0.1)  # 0.2 m/s for 2 s
    for f in ns["fingers"]:
        assert np.all(f < 0.005)  # closed
    assert len(ns["observations"]) == 4  # both tasks' robots


def test_batched_views_read_and_push_every_cube():
    ns = run("batched_views.py")
    np.testing.assert_allclose(ns["landed_heights"], 0.025, atol=5e-4)
    np.testing.assert_allclose(ns["ground_forces"][:, 2], 0.1 * 9.81, rtol=1e-3)
    moved = ns["after"] - ns["positions"]
    assert np.all(moved[:2, 0] > 0.005) and np.all(np.abs(moved[2]) < 1e-4)  # pushed, and left alone
    assert moved[3, 2] == pytest.approx(0.1, abs=1e-3)  # floated up at 0.2 m/s for 0.5 s, no gravity
    assert ns["jacobians"].shape == (1, 10, 6, 9) and ns["mass_matrices"].shape == (1, 9, 9)
    np.testing.assert_allclose(ns["joint_positions"][0, :7], [0.0, -0.5, 0.0, -2.2, 0.0, 1.8, 0.8])


def test_materials_colour_the_objects_and_friction_decides_who_slides():
    ns = run("objects_and_materials.py")
    np.testing.assert_array_equal(ns["colors"]["ice_block"], [0.1, 0.4, 0.9])
    np.testing.assert_array_equal(ns["ball_color"], [1.0, 0.8, 0.1])
    assert ns["slid"]["ice_block"] > 0.02 and ns["slid"]["rubber_block"] < 1e-3
    lo, hi = ns["ramp_box"]
    assert hi[2] - lo[2] == pytest.approx(np.sin(np.deg2rad(15)) * 2.0 + np.cos(np.deg2rad(15)) * 0.05, abs=1e-6)
    assert ns["ball_height"] == pytest.approx(0.04, abs=1e-3)


def test_stepping_callbacks_and_the_app_loop():
    ns = run("stepping_and_callbacks.py")
    assert ns["steps_rendered"] == 40 and ns["steps_unrendered"] == 10
    assert all(s == pytest.approx(1 / 120) for s in ns["physics_steps"])
    assert ns["paused_still"]
    assert ns["t_updates"] == pytest.approx(15 / 30)
    assert ns["stopped"]
    assert ns["timeline_events"] == ["PLAY", "PAUSE", "PLAY", "STOP", "PLAY"]
    assert ns["fell"] > 0.3
    assert len(ns["renders"]) >= 35


def test_new_manipulator_pattern_generic_pick_place_with_an_rmpflow_cspace_controller():
    """Isaac's generic `PickPlaceController(name, cspace_controller, gripper, ...)`, subclassed as
    in "Adding a New Manipulator" (a TypeError before: manip had only the Franka's signature)."""
    ns = run("new_manipulator_pick_place.py")
    assert ns["done"]
    assert sorted(set(ns["events"])) == list(range(11))   # every phase, then done
    assert np.linalg.norm(ns["cube_position"][:2] - ns["target_position"][:2]) < 0.02
    assert ns["cube_position"][2] == pytest.approx(0.0515 / 2, abs=3e-3)  # released on the ground


def test_isaac5_hello_world_cube_falls_and_the_callback_sees_it():
    ns = run("hello_world_isaac5.py")
    heights = [p[2] for _, p, _ in ns["states"]]
    assert heights[0] == pytest.approx(1.0) and min(np.diff(heights[:20])) < 0          # falling at first
    assert ns["final_position"][2] == pytest.approx(0.5015 / 2, abs=2e-3)               # resting on the ground
    assert all(s == pytest.approx(1 / 60) for s, _, _ in ns["states"])
    assert len(ns["states"]) == 120


def test_rmpflow_follow_target_through_an_articulation_motion_policy():
    ns = run("follow_target_rmpflow.py")
    assert max(ns["errors"]) < 0.01          # right_gripper within 1 cm of each goal (drives sag under gravity)
    assert all(ns["ik_errors"])              # Lula's IK solves each goal


def test_pick_place_two_episodes_with_world_and_controller_resets():
    ns = run("pick_place_episodes.py")
    assert len(ns["episodes"]) == 2
    for cube, target, failure in ns["episodes"]:
        assert failure is None
        assert np.linalg.norm(cube[:2] - target[:2]) < 0.02
        assert cube[2] == pytest.approx(0.0515 / 2, abs=3e-3)


def test_curobo_motion_gen_reacher_loop_reaches_each_target():
    """cuRobo's reacher loop: `result.success.item()` on each plan (an AttributeError before)."""
    ns = run("motion_gen_reacher.py")
    assert ns["plans"] == 3 and len(ns["reached"]) == 3
    assert max(ns["reached"]) < 0.01         # the TCP at the target cube after each motion


def test_ur10_with_a_suction_gripper_picks_and_places_with_the_generic_controller():
    """SurfaceGripper + Isaac's generic PickPlaceController + an RMPFlowController of the UR10."""
    ns = run("ur10_suction_pick_place.py")
    assert ns["my_controller"].is_done()
    assert sum(ns["held"]) > 100                                   # carried by suction
    np.testing.assert_allclose(ns["cube_position"], ns["goal_position"], atol=0.01)
    assert not ns["gripper"].is_closed()                           # released


def test_two_pick_place_tasks_offset_each_place_their_cube():
    ns = run("multiple_pick_place_tasks.py")
    assert ns["done"] == [True, True] and ns["tasks_done"] == [True, True] and ns["all_done"]
    for i, offset in enumerate(([0, -1, 0], [0, 1, 0])):
        np.testing.assert_allclose(ns["robot_positions"][i], offset, atol=1e-9)   # each task's Franka offset
        np.testing.assert_allclose(ns["target_positions"][i], np.add([-0.3, -0.3, 0.0515 / 2], offset))
        assert np.linalg.norm(ns["cube_positions"][i][:2] - ns["target_positions"][i][:2]) < 0.02
        assert ns["cube_positions"][i][2] == pytest.approx(0.0515 / 2, abs=3e-3)
        assert ns["hand_tilts"][i] < 0.05                                             # the hand still points down
    assert ns["metrics"]["distance_to_target"] < 0.02                                 # merged over tasks, as Isaac
    assert len(ns["physics_steps"]) > 1000 and all(s == pytest.approx(1 / 60) for s in ns["physics_steps"])


def test_a_camera_sees_the_cube_picked_and_placed():
    ns = run("camera_pick_place.py")
    for (u, v), depth, along_axis, (blue_u, blue_v) in (ns["before"], ns["after"]):
        assert depth == pytest.approx(along_axis, abs=2e-3)          # the depth image sees the cube's top
        assert abs(blue_u - u) < 1.5 and abs(blue_v - v) < 1.5       # the blue pixels are where it projects
    (u0, v0), (u1, v1) = ns["before"][0], ns["after"][0]
    assert u0 < 40 and v0 < 40 and u1 > 210 and v1 > 210             # from (0.3, 0.3) to (-0.3, -0.3)
    assert ns["after"][2] == pytest.approx(2.0 - 0.0515, abs=3e-3)   # resting on the ground
    assert all(f["rgba"] == (256, 256, 4) and f["depth"] == (256, 256) for f in ns["frames"])
    assert max(f["motion"] for f in ns["frames"]) > 0.5              # the arm moving in the images
    np.testing.assert_allclose(ns["intrinsics"][:2, 2], [127.5, 127.5])


def test_curobo_batch_plan_read_as_a_batch_and_played():
    """cuRobo's batch demo: `result.success` (2,) and `result.get_paths()` on plan_batch's result (an
    AttributeError on its list before), each path played on the simulated Franka."""
    ns = run("motion_gen_batch.py")
    assert ns["success"].tolist() == [True, True] and ns["result"].success.shape == (2,)
    assert len(ns["traj"]) == 2 and len(ns["reached"]) == 2
    assert max(ns["reached"]) < 0.005        # the simulated hand at each goal


def test_curobos_batched_ik_example_reads_curobos_shapes_and_the_sim_reaches_each_goal():
    """cuRobo's ik_example: `solution[success]` of (N, 1) `success` and (N, 1, dof) `solution`
    (an AttributeError before: manip's batch result had no `solution`, and (N,) `success`)."""
    ns = run("curobo_ik_reachability.py")
    n = len(ns["q_sample"])
    assert n == 40 and ns["result"].success.shape == (n, 1) and ns["success"].all()
    assert ns["solutions"].shape == (n, 7)
    assert float(ns["result"].position_error.max()) < 5e-3
    assert len(ns["hand_errors"]) == 4 and max(ns["hand_errors"]) < 5e-3   # the simulated hand, via its prim


def test_robot_setup_tunes_the_solver_walks_the_prims_and_drives_the_arm():
    ns = run("franka_articulation_setup.py")
    assert ns["solver_settings"] == (64, 4, 0.0)
    assert {f"/World/Franka/panda_link{i}" for i in range(8)} | {"/World/Franka/panda_hand"} <= set(ns["links"])
    assert ns["fingers"] == ["/World/Franka/panda_leftfinger", "/World/Franka/panda_rightfinger"]
    assert ns["joint_error"] < 0.01
    np.testing.assert_allclose(ns["hand_position"], ns["prim_position"], atol=1e-12)
    from manip import MotionGenerator  # the planner's kinematics agree with the simulated hand
    fk = MotionGenerator("franka").fk(ns["franka"].get_joint_positions()[:7], "panda_hand")
    np.testing.assert_allclose(ns["hand_position"], fk.position, atol=1e-3)


def test_a_task_of_ones_own_with_metrics_is_done_and_a_physics_callback():
    ns = run("reach_task_metrics.py")
    (steps0, done0, _, color0), (steps1, done1, _, color1) = ns["episodes"]
    assert done0 and done1 and steps0 == steps1 < 600   # the reset starts the same episode over
    np.testing.assert_array_equal([color0, color1], [[0.0, 1.0, 0.0]] * 2)   # turned green in pre_step
    np.testing.assert_array_equal(ns["reset_color"], [1.0, 0.0, 0.0])   # post_reset: red again
    d = np.array(ns["distances"])
    assert len(d) == steps0 + steps1 and d[0] > 0.25 and d[steps0 - 1] < 0.01


def test_a_segmented_cube_is_picked_through_a_goal_set_of_pre_grasps():
    """Isaac's semantic_segmentation finds the labelled cube; cuRobo's goal-set IK reaches one of
    four pre-grasp poses and says which; the Franka lifts the cube from there."""
    ns = run("segmented_goalset_grasp.py")
    assert ns["labels"][str(ns["cube_id"])] == {"class": "cube"} and ns["rows"].size > 100
    np.testing.assert_allclose(ns["estimate"], [0.45, 0.12, 0.0515 / 2], atol=2e-3)   # where the cube was
    assert ns["result"].success.shape == ns["result"].goalset_index.shape == (1, 1) and ns["result"].success.item()
    chosen = ns["pre_grasps"][ns["chosen"]]
    position, orientation = ns["hand_at_pre"]
    assert np.linalg.norm(position - chosen.position) < 0.01          # the simulated hand at the chosen pose
    assert Pose(position, orientation).distance(chosen)[1] < 0.05
    assert ns["cube_after"][2] > 0.12                                  # lifted (from 0.026 m)
