"""`World.get_physics_context()` (it raised NotImplementedError): gravity and the physics step map
to MuJoCo; PhysX's solver and GPU settings are checked, kept for their getters, and change nothing."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import DynamicSphere, PhysicsContext, World


def _fall(world, ball, seconds: float) -> float:
    z0 = ball.get_world_pose()[0][2]
    for _ in range(round(seconds / world.get_physics_dt())):
        world.step(render=False)
    return z0 - ball.get_world_pose()[0][2]


def test_set_gravity_changes_how_far_a_ball_falls_at_once_and_after_resets():
    world = World()
    ball = world.scene.add(DynamicSphere("/World/ball", name="ball", position=[0, 0, 10.0], radius=0.05))
    ctx = world.get_physics_context()
    assert isinstance(ctx, PhysicsContext) and ctx is world.get_physics_context()
    assert ctx.get_gravity() == ([0.0, 0.0, -1.0], pytest.approx(9.81))
    ctx.set_gravity(-1.62)  # the Moon, before the first reset
    world.reset()
    drop = _fall(world, ball, 1.0)  # from rest (the reset restores the default state after its warm-up)
    assert drop == pytest.approx(0.5 * 1.62 * 1.0**2, rel=0.01)
    ctx.set_gravity(-9.81)  # at once, while running
    v0 = ball.get_linear_velocity()[2]
    for _ in range(30):
        world.step(render=False)
    assert ball.get_linear_velocity()[2] - v0 == pytest.approx(-9.81 * 0.5, rel=0.02)
    ctx.set_gravity(0.0)
    world.reset()  # kept across resets (recompiles too)
    assert _fall(world, ball, 0.5) == pytest.approx(0.0, abs=1e-9)
    assert ctx.get_gravity()[1] == 0.0
    with pytest.raises(InvalidInputError, match="gravity"):
        ctx.set_gravity([0, 0, -9.81])


def test_set_physics_dt_is_the_worlds_step():
    world = World()
    ctx = world.get_physics_context()
    ctx.set_physics_dt(dt=1 / 120, substeps=1)
    assert world.get_physics_dt() == pytest.approx(1 / 120) == ctx.get_physics_dt()
    world.reset()
    world.step(render=False)
    assert world.current_time == pytest.approx(1 / 60 + 1 / 120)  # the warm-up (one rendering_dt), then a step
    assert world.current_time_step_index == 3
    ctx.set_physics_dt(0.0)  # Isaac: physics does not simulate
    assert ctx.get_physics_dt() == 0.0
    world.step(render=True)
    assert world.current_time == pytest.approx(1 / 60 + 1 / 120)
    for bad in (-0.01, 2.0, "fast", True):
        with pytest.raises(InvalidInputError, match="dt"):
            ctx.set_physics_dt(bad)


def test_physx_settings_are_checked_and_kept_without_effect(caplog):
    world = World()
    ctx = world.get_physics_context()
    ctx.enable_ccd(True)
    ctx.set_solver_type("PGS")
    ctx.set_broadphase_type("GPU")
    ctx.set_gpu_max_rigid_contact_count(2 ** 20)
    assert ctx.is_ccd_enabled() and ctx.get_solver_type() == "PGS" and ctx.get_broadphase_type() == "GPU"
    assert ctx.get_gpu_max_rigid_contact_count() == 2 ** 20 and ctx.get_bounce_threshold() == pytest.approx(0.2)
    with caplog.at_level(logging.WARNING):
        ctx.enable_gpu_dynamics(flag=True)
    assert "CPU" in caplog.text and ctx.is_gpu_dynamics_enabled()
    with pytest.raises(InvalidInputError, match="TGS"):
        ctx.set_solver_type("Newton")
    with pytest.raises(InvalidInputError, match="True or False"):
        ctx.enable_ccd("yes")
    with pytest.raises(InvalidInputError, match="integer"):
        ctx.set_gpu_heap_capacity(-1)
    with pytest.raises(NotImplementedError, match="World.model.opt"):
        ctx.get_current_physics_scene_prim()
    assert ctx.device == "cpu" and not ctx.use_gpu_pipeline and ctx.prim_path == "/physicsScene"
