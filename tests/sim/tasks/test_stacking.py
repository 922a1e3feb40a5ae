"""Isaac's Franka stacking example with its imports changed: the Stacking task and the
StackingController stack two cubes at the target in the simulator."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import SimulationApp, Stacking, StackingController, World


def test_isaacs_stacking_example_runs_with_its_imports_changed():
    # standalone_examples/api/omni.isaac.franka/stacking.py, imports changed, loop bounded.
    simulation_app = SimulationApp({"headless": True})
    my_world = World(stage_units_in_meters=1.0)
    my_task = Stacking()
    my_world.add_task(my_task)
    my_world.reset()
    robot_name = my_task.get_params()["robot_name"]["value"]
    my_franka = my_world.scene.get_object(robot_name)
    my_controller = StackingController(
        name="stacking_controller",
        gripper=my_franka.gripper,
        robot_articulation=my_franka,
        picking_order_cube_names=my_task.get_cube_names(),
        robot_observation_name=robot_name,
    )
    articulation_controller = my_franka.get_articulation_controller()
    reset_needed = False
    steps = 0
    while simulation_app.is_running() and steps < 5000 and not my_controller.is_done():
        my_world.step(render=True)
        if my_world.is_stopped() and not reset_needed:
            reset_needed = True
        if my_world.is_playing():
            if reset_needed:
                my_world.reset()
                my_controller.reset()
                reset_needed = False
            observations = my_world.get_observations()
            actions = my_controller.forward(observations=observations)
            articulation_controller.apply_action(actions)
        steps += 1
    assert my_controller.is_done() and my_controller.failures == []
    for _ in range(60):  # settled after the release
        my_world.step(render=False)
    simulation_app.close()
    assert robot_name == "my_franka" and my_task.get_cube_names() == ["cube", "cube_1"]
    obs = my_world.get_observations()
    np.testing.assert_allclose(obs["cube_1"]["target_position"], [0.5, 0.5, 1.5 * 0.0515])
    # The second cube stands on the first, at the target (each within 1 cm).
    assert max(my_task.calculate_metrics().values()) < 0.01 and my_task.is_done()
    assert obs["cube_1"]["position"][2] - obs["cube"]["position"][2] == pytest.approx(0.0515, abs=2e-3)
    # Done: every call holds all joints.
    hold = my_controller.forward(observations=obs)
    assert hold.get_length() == 9 and all(v is None or np.isnan(v) for v in hold.joint_positions)


def test_stacking_task_and_controller_arguments():
    world = World()
    task = Stacking(cube_initial_positions=[[0.3, 0.3, 0.03], [0.3, -0.3, 0.03], [0.4, 0.0, 0.03]],
                    target_position=[0.4, 0.4, 0.0], offset=[0.0, 1.0, 0.0])
    world.add_task(task)
    world.reset()
    assert task.get_cube_names() == ["cube", "cube_1", "cube_2"]
    assert np.allclose(task.get_params()["stack_target_position"]["value"], [0.4, 1.4, 0.0])
    assert np.allclose(world.scene.get_object("cube_2").get_world_pose()[0], [0.4, 1.0, 0.03])
    assert np.allclose(task.robot.get_world_pose()[0], [0.0, 1.0, 0.0])
    with pytest.raises(InvalidInputError, match="no cube named 'cube_9'"):
        task.set_params(cube_name="cube_9", cube_position=[0, 0, 0])
    with pytest.raises(InvalidInputError, match="cube_initial_positions"):
        Stacking(cube_initial_positions=[0.3, 0.3, 0.3])
    with pytest.raises(InvalidInputError, match="picking_order_cube_names"):
        StackingController("s", task.robot.gripper, task.robot, "cube", "my_franka")
    controller = StackingController("s", task.robot.gripper, task.robot, ["cube_9"], "my_franka")
    with pytest.raises(InvalidInputError, match="no cube 'cube_9'"):
        controller.forward(world.get_observations())
