"""Isaac's PickPlace task: an array cube size and Isaac's defaults (issue 32, item 8)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import PickPlace, World


def test_an_array_cube_size_builds_that_box():
    world = World()
    task = PickPlace(cube_size=np.array([0.0515] * 3))  # was InvalidInputError
    world.add_task(task)
    world.reset()
    cube = task.cube
    sim = world.physics_sim_view
    half = sim.model.geom_size[cube.geom_id]
    np.testing.assert_allclose(2 * half, [0.0515] * 3)
    np.testing.assert_allclose(cube.get_local_scale(), [0.0515] * 3)  # Isaac: size 1.0 scaled
    assert cube.get_size() == 1.0


def test_isaac_defaults_cube_drops_to_the_ground_at_03_03_and_target_at_minus_03():
    world = World()
    task = PickPlace()
    world.add_task(task)
    world.reset()
    np.testing.assert_allclose(task.cube.get_world_pose()[0], [0.3, 0.3, 0.3], atol=1e-3)
    for _ in range(90):
        world.step(render=False)
    p = task.cube.get_world_pose()[0]
    np.testing.assert_allclose(p[:2], [0.3, 0.3], atol=2e-3)
    assert p[2] == pytest.approx(0.0515 / 2, abs=2e-3)  # resting on the ground
    obs = world.get_observations()[task.cube.name]
    np.testing.assert_allclose(obs["target_position"], [-0.3, -0.3, 0.0515 / 2])
    np.testing.assert_allclose(task.get_params()["cube_size"]["value"], [0.0515] * 3)


def test_a_non_uniform_cube_size_sets_the_target_height_from_its_z_edge():
    task = PickPlace(cube_size=[0.04, 0.05, 0.08])
    world = World()
    world.add_task(task)
    world.reset()
    np.testing.assert_allclose(world.get_observations()[task.cube.name]["target_position"], [-0.3, -0.3, 0.04])
    np.testing.assert_allclose(2 * world.physics_sim_view.model.geom_size[task.cube.geom_id], [0.04, 0.05, 0.08])


@pytest.mark.parametrize("bad", [[0.05, 0.05], [0.05, -0.05, 0.05], -0.05, [np.nan] * 3])
def test_bad_cube_sizes_raise_naming_the_argument(bad):
    with pytest.raises(InvalidInputError, match="cube_size"):
        PickPlace(cube_size=bad)
