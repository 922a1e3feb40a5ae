"""RigidPrimView forces, contact forces, gravity and default states (issue 32, item 4),
checked against the simulator's state."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicCuboid, RigidPrimView, SimulationError, World

G = 9.81


@pytest.fixture
def cubes():
    world = World()
    world.scene.add_default_ground_plane()
    for i in range(3):
        world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube_{i}", position=[0.3 * i, 0, 0.05], size=0.1,
                                      mass=1.0 + i))
    view = world.scene.add(RigidPrimView("/World/Cube_.*", name="cubes", track_contact_forces=True,
                                         contact_filter_prim_paths_expr=["/World/defaultGroundPlane"]))
    world.reset()
    for _ in range(30):
        world.step(render=False)
    return world, view


def test_contact_forces_hold_each_cube_up(cubes):
    world, view = cubes
    dt = world.get_physics_dt()
    net = view.get_net_contact_forces(dt=dt)  # dt = physics_dt: forces [N]
    np.testing.assert_allclose(net, [[0, 0, G * m] for m in (1.0, 2.0, 3.0)], atol=1e-3)
    matrix = view.get_contact_force_matrix(dt=dt)
    assert matrix.shape == (3, 1, 3) and view.num_contact_filters == 1
    np.testing.assert_allclose(matrix[:, 0], net, atol=1e-9)  # all of it from the ground
    np.testing.assert_allclose(view.get_net_contact_forces(), net * dt, atol=1e-9)  # default dt=1: impulses [N s]


def test_a_force_acts_for_one_physics_step(cubes):
    world, view = cubes
    dt = world.get_physics_dt()
    view.apply_forces(np.array([[0.0, 0.0, 40.0]] * 3))
    world.step(render=False)
    vz = view.get_linear_velocities()[:, 2]
    np.testing.assert_allclose(vz, [(40.0 - G * m) / m * dt for m in (1.0, 2.0, 3.0)], rtol=1e-3)
    world.step(render=False)  # no force now: gravity only (velocity changes by -g dt)
    np.testing.assert_allclose(view.get_linear_velocities()[:, 2], vz - G * dt, rtol=1e-3)
    assert not np.any(world.data.xfrc_applied)


def test_a_force_off_centre_spins_the_body(cubes):
    world, view = cubes
    view.disable_gravities()
    view.apply_forces_and_torques_at_pos(forces=[[0, 1.0, 0]], positions=[[0.05, 0, 0.05]], indices=[0])
    world.step(render=False)
    w = view.get_angular_velocities(indices=[0])[0]
    assert w[2] > 0.1 and abs(w[0]) < 0.01 * w[2]  # a push in +y on the +x face turns it about +z
    view.apply_forces_and_torques_at_pos(torques=[[0, 0, 0.1]], indices=[1], is_global=False)
    world.step(render=False)
    assert view.get_angular_velocities(indices=[1])[0, 2] > 0


def test_disabled_gravity_lets_a_push_lift_the_cube_off_for_good(cubes):
    world, view = cubes
    view.disable_gravities(indices=[1])
    view.set_linear_velocities([[0, 0, 0.5]], indices=[1])
    for _ in range(30):
        world.step(render=False)
    z = view.get_world_poses()[0][:, 2]
    assert z[1] == pytest.approx(0.05 + 0.25, abs=0.01)  # floated up at 0.5 m/s for 0.5 s
    assert z[0] == pytest.approx(0.05, abs=1e-3) and z[2] == pytest.approx(0.05, abs=1e-3)
    view.enable_gravities(indices=[1])
    for _ in range(60):
        world.step(render=False)
    assert view.get_world_poses()[0][1, 2] == pytest.approx(0.05, abs=2e-3)  # fell back


def test_set_angular_velocities_keeps_the_linear_ones(cubes):
    world, view = cubes
    view.disable_gravities()
    view.set_linear_velocities([[0.1, 0, 0]] * 3)
    view.set_angular_velocities([[0, 0, 1.0]] * 3)
    v = view.get_velocities()
    np.testing.assert_allclose(v[:, :3], [[0.1, 0, 0]] * 3, atol=1e-12)
    np.testing.assert_allclose(v[:, 3:], [[0, 0, 1.0]] * 3, atol=1e-12)


def test_default_states_are_what_a_reset_restores(cubes):
    world, view = cubes
    state = view.get_default_state()
    np.testing.assert_allclose(state.positions[:, 0], [0.0, 0.3, 0.6])
    view.set_default_state(positions=[[0.0, 0.5, 0.05]], linear_velocities=[[0, 0, 1.0]], indices=[2])
    world.reset()
    p, _ = view.get_world_poses()
    np.testing.assert_allclose(p[2], [0.0, 0.5, 0.05], atol=1e-9)
    assert view.get_linear_velocities()[2, 2] > 0.8  # restored with its default velocity (one warm-up step)


def test_contact_matrix_needs_filters_and_bad_forces_raise(cubes):
    world, view = cubes
    plain = world.scene.add(RigidPrimView("/World/Cube_.*", name="plain"))
    with pytest.raises(SimulationError, match="contact_filter_prim_paths_expr"):
        plain.get_contact_force_matrix()
    with pytest.raises(InvalidInputError, match="finite"):
        view.apply_forces([[np.nan, 0, 0]] * 3)
    with pytest.raises(InvalidInputError):
        view.apply_forces([[1.0, 0]] * 3)
    with pytest.raises(InvalidInputError, match="dt"):
        view.get_net_contact_forces(dt=0.0)
