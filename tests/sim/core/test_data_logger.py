"""World.get_data_logger() (it raised NotImplementedError): Isaac's data_logging example flow, one
frame per step while started, saved and loaded as Isaac's JSON."""

from __future__ import annotations

import json

import numpy as np
import pytest

from manip.sim import ArticulationAction, Franka, SimulationError, World


def test_a_started_logger_records_each_step_and_round_trips_through_isaacs_json(tmp_path):
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="my_franka"))
    world.reset()
    logger = world.get_data_logger()
    assert logger is world.get_data_logger() and not logger.is_started()

    def frame(tasks, scene):
        robot = scene.get_object("my_franka")
        return {"joint_positions": robot.get_joint_positions().tolist(),
                "applied_joint_positions": robot.get_applied_action().joint_positions.tolist()}

    with pytest.raises(SimulationError, match="logging function"):
        logger.start()
        world.step(render=False)
    logger.reset()
    logger.add_data_frame_logging_func(frame)
    target = franka.get_joint_positions() + np.r_[0.3, np.zeros(8)]
    franka.apply_action(ArticulationAction(joint_positions=target))
    logger.start()
    for _ in range(30):
        world.step(render=True)
    logger.pause()
    world.step(render=True)  # paused: not recorded
    assert logger.get_num_of_data_frames() == 30
    frames = [logger.get_data_frame(i) for i in range(30)]
    assert [f.current_time_step for f in frames] == list(range(frames[0].current_time_step, frames[0].current_time_step + 30))
    q0 = [f.data["joint_positions"][0] for f in frames]
    assert q0[0] < 0.1 and q0[-1] == pytest.approx(target[0], abs=0.01)  # the arm turning to its target
    assert all(f.data["applied_joint_positions"][0] == pytest.approx(target[0]) for f in frames)
    path = tmp_path / "isaac_sim_data.json"
    logger.save(log_path=str(path))
    assert len(json.loads(path.read_text())["Isaac Sim Data"]) == 30
    logger.reset()
    assert logger.get_num_of_data_frames() == 0
    logger.load(log_path=str(path))
    assert not logger.is_started() and logger.get_num_of_data_frames() == 30
    assert logger.get_data_frame(2).get_dict() == frames[2].get_dict()
    world.clear()
    assert world.get_data_logger().get_num_of_data_frames() == 0  # a new logger, as Isaac's clear()
