"""World, Scene and objects: physics behaviour, lifecycle, callbacks, errors."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError, UnknownNameError
from manip.sim import (
    ArticulationAction,
    BaseTask,
    DynamicCuboid,
    DynamicSphere,
    FixedCuboid,
    Franka,
    GeometryPrim,
    PhysicsMaterial,
    PickPlace,
    RigidPrim,
    RigidPrimView,
    SimulationError,
    VisualCuboid,
    World,
    XFormPrim,
    XFormPrimView,
)


def test_dropped_cube_comes_to_rest_at_half_its_size():
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.0, 0.0, 1.0], size=0.05))
    world.reset()
    zs = []
    for _ in range(120):
        world.step(render=False)
        zs.append(cube.get_world_pose()[0][2])
    # Free fall first: after 0.25 s it fell g t^2 / 2 = 0.31 m (within one step of drift).
    assert zs[14] == pytest.approx(1.0 - 0.5 * 9.81 * 0.25**2, abs=0.01)
    p, q = cube.get_world_pose()
    assert p[2] == pytest.approx(0.025, abs=1e-3)
    assert np.allclose(p[:2], 0.0, atol=1e-6)
    assert np.linalg.norm(cube.get_linear_velocity()) < 1e-3
    assert np.allclose(np.abs(q), [1, 0, 0, 0], atol=1e-6)


def test_defaults_are_isaacs_and_render_steps_several_physics_steps():
    world = World()
    assert world.get_physics_dt() == pytest.approx(1 / 60)
    assert world.get_rendering_dt() == pytest.approx(1 / 60)
    assert world.physics_substeps == 9
    world.set_simulation_dt(physics_dt=1 / 120, rendering_dt=1 / 30)
    steps = []
    world.add_physics_callback("count", lambda dt: steps.append(dt))
    world.scene.add(DynamicSphere("/World/ball", name="ball", radius=0.05))
    world.reset()
    # Isaac's reset plays and takes one rendered step (4 physics steps here), without callbacks
    assert world.is_playing() and world.current_time_step_index == 4 and steps == []
    assert world.model.opt.timestep == pytest.approx(1 / 120 / 5)
    world.step(render=True)
    assert len(steps) == 4 and all(dt == pytest.approx(1 / 120) for dt in steps)
    world.step(render=False)
    assert len(steps) == 5
    assert world.current_time_step_index == 9
    assert world.current_time == pytest.approx(9 / 120)


def test_physics_callbacks_fire_once_per_step_with_step_size():
    world = World()
    calls = []
    world.add_physics_callback("cb", lambda step_size: calls.append((step_size, world.current_time_step_index)))
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    world.reset()
    for _ in range(10):
        world.step(render=True)
    assert [c[0] for c in calls] == [pytest.approx(1 / 60)] * 10
    assert [c[1] for c in calls] == list(range(1, 11))  # before each physics step (1: the reset's warm-up)
    assert world.physics_callback_exists("cb")


def test_callback_name_errors_are_logged_like_isaac(caplog):
    world = World()
    first = []
    world.add_physics_callback("cb", lambda s: first.append(s))
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    world.reset()
    with caplog.at_level(logging.ERROR, logger="manip.sim.carb"):
        world.add_physics_callback("cb", lambda s: None)  # Isaac: carb.log_error, the first one stays
        world.remove_physics_callback("nope")
        world.remove_timeline_callback("nope")
    errors = [r.getMessage() for r in caplog.records if r.levelno == logging.ERROR]
    assert any("`cb` already exists" in m for m in errors)
    assert any("`nope` doesn't exist" in m and "'cb'" in m for m in errors)  # lists the names
    assert len(errors) == 3
    world.step()
    assert len(first) == 1
    world.remove_physics_callback("cb")
    world.step()
    assert len(first) == 1 and not world.physics_callback_exists("cb")
    with pytest.raises(InvalidInputError, match="callable"):
        world.add_physics_callback("bad", 3)
    # A callback that cannot take the step size fails when added, not inside world.step().
    with pytest.raises(InvalidInputError, match=r"physics callback 'noarg' must take one argument \(step_size"):
        world.add_physics_callback("noarg", lambda: None)
    with pytest.raises(InvalidInputError, match="timeline callback 'tl' must take one argument"):
        world.add_timeline_callback("tl", lambda a, b: None)
    world.add_physics_callback("default_ok", lambda step_size, extra=1: None)
    world.add_physics_callback("varargs_ok", lambda *args: None)
    world.step()


def test_clear_one_kind_of_callbacks_as_isaac():
    """Isaac 4.x's clear_physics/render/stage/timeline_callbacks() each remove one kind only;
    render_callback_exists(name) as the other *_exists."""
    world = World()
    calls = {"physics": 0, "render": 0, "stage": 0, "timeline": 0}

    def count(kind):
        return lambda arg: calls.__setitem__(kind, calls[kind] + 1)

    def add_all():
        world.add_physics_callback("p", count("physics"))
        world.add_render_callback("r", count("render"))
        world.add_stage_callback("s", count("stage"))
        world.add_timeline_callback("t", count("timeline"))

    def exists():
        return (world.physics_callback_exists("p"), world.render_callback_exists("r"),
                world.stage_callback_exists("s"), world.timeline_callback_exists("t"))

    add_all()
    assert exists() == (True, True, True, True) and not world.render_callback_exists("other")
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    world.reset()
    world.step(render=True)
    assert all(calls.values()), calls
    for k, clear in enumerate((world.clear_physics_callbacks, world.clear_render_callbacks,
                               world.clear_stage_callbacks, world.clear_timeline_callbacks)):
        clear()
        assert exists() == tuple(i > k for i in range(4))
    before = dict(calls)
    world.pause()
    world.play()
    world.step(render=True)
    world.scene.add(DynamicCuboid("/World/d", name="d", position=[1, 0, 0.1], size=0.1))
    assert calls == before  # none of them is called any more
    add_all()  # the names are free again
    assert exists() == (True, True, True, True)


def test_pause_stop_play_and_timeline_events():
    world = World()
    events = []
    world.add_timeline_callback("tl", lambda e: events.append(e.type))
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
    world.reset()
    world.step()
    world.pause()
    z = cube.get_world_pose()[0][2]
    world.step()
    assert cube.get_world_pose()[0][2] == z and world.current_time_step_index == 2
    world.play()
    world.step()
    assert cube.get_world_pose()[0][2] < z
    world.stop()
    assert world.is_stopped() and world.current_time == 0 and world.current_time_step_index == 0
    assert cube.get_world_pose()[0][2] == pytest.approx(1.0)   # Isaac's Stop: back to the initial state
    world.play()  # physics restarts from the initial state
    assert cube.get_world_pose()[0][2] == pytest.approx(1.0)
    world.step()
    world.stop()
    cube.set_world_pose([0.2, 0.0, 0.5])   # set while stopped: where the next play starts
    world.play()
    assert np.allclose(cube.get_world_pose()[0], [0.2, 0.0, 0.5])
    assert events == ["PLAY", "PAUSE", "PLAY", "STOP", "PLAY", "STOP", "PLAY"]


def test_reset_restores_default_states():
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0.3, 0.0, 0.5], size=0.05))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    q0 = franka.get_joint_positions()
    franka.apply_action(ArticulationAction(joint_positions=q0 + 0.2 * np.r_[np.ones(7), 0, 0] * 0.5))
    cube.set_linear_velocity([1.0, 0.0, 0.0])
    for _ in range(30):
        world.step(render=False)
    assert not np.allclose(cube.get_world_pose()[0], [0.3, 0.0, 0.5])
    world.reset()
    # Isaac: the reset plays and steps once, then restores the default states
    assert world.current_time == pytest.approx(1 / 60) and world.current_time_step_index == 1
    assert np.allclose(cube.get_world_pose()[0], [0.3, 0.0, 0.5])
    assert np.allclose(cube.get_linear_velocity(), 0.0)
    assert np.allclose(franka.get_joint_positions(), q0)
    assert np.allclose(franka.get_applied_action().joint_positions, q0)
    # A new default state is used by the next reset.
    cube.set_default_state(position=[0.0, 0.4, 0.2])
    world.reset()
    assert np.allclose(cube.get_world_pose()[0], [0.0, 0.4, 0.2])


def test_adding_after_a_reset_then_resetting_again():
    world = World()
    world.scene.add_default_ground_plane()
    a = world.scene.add(DynamicCuboid("/World/a", name="a", position=[0, 0, 0.5], size=0.05))
    world.reset()
    nbody = world.model.nbody
    b = world.scene.add(DynamicCuboid("/World/b", name="b", position=[0.5, 0, 0.5], size=0.05))
    assert b.get_world_pose()[0][0] == 0.5  # not compiled yet: the pending pose
    world.reset()
    assert world.model.nbody == nbody + 1
    for _ in range(60):
        world.step(render=False)
    assert b.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)
    assert a.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)
    world.scene.remove_object("b")
    world.reset()
    assert world.model.nbody == nbody
    assert not world.scene.object_exists("b") and world.scene.get_object("b") is None


def test_a_removed_object_or_robot_says_so_instead_of_returning_stale_values(caplog):
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.5], size=0.05))
    cube.set_world_pose([0.5, 0.1, 0.5])  # before the first reset: the pending pose
    world.reset()
    for _ in range(60):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)
    world.scene.remove_object("cube")
    world.scene.remove_object("franka")
    # the cube answered the pose set before the reset ([0.5, 0.1, 0.5]) and the robot warned
    # that it was used "before the first World.reset()": getters now return None (as a removed
    # robot's do) saying why, setters raise
    for get in (cube.get_world_pose, cube.get_linear_velocity, franka.get_joint_positions):
        with caplog.at_level(logging.WARNING):
            caplog.clear()
            assert get() is None
        assert "is no longer on the stage (removed by scene.remove_object" in caplog.text
        assert "before the first" not in caplog.text
    for call in (lambda: cube.set_world_pose([0, 0, 1.0]), lambda: cube.set_linear_velocity([0, 0, 1.0]),
                 lambda: franka.set_joint_positions(np.zeros(9))):
        with pytest.raises(SimulationError, match="'/World/(cube|Franka)' is no longer on the stage"):
            call()
    # a new robot at the same path works; the old wrapper still has no model
    again = world.scene.add(Franka("/World/Franka", name="franka", position=[0.0, 0.5, 0.0]))
    world.reset()
    assert again.get_joint_positions().shape == (9,)
    np.testing.assert_allclose(again.get_world_pose()[0], [0.0, 0.5, 0.0])
    assert franka.get_joint_positions() is None


def test_name_and_prim_path_errors():
    world = World()
    world.scene.add(DynamicCuboid("/World/c", name="c"))
    with pytest.raises(InvalidInputError, match="already in the scene"):
        world.scene.add(DynamicCuboid("/World/c2", name="c"))
    with pytest.raises(InvalidInputError, match="already exists"):
        DynamicCuboid("/World/c", name="other")
    with pytest.raises(InvalidInputError, match="absolute"):
        DynamicCuboid("World/x")
    with pytest.raises(InvalidInputError, match="not both"):
        DynamicCuboid("/World/y", position=[0, 0, 0], translation=[0, 0, 0])
    with pytest.raises(InvalidInputError):
        VisualCuboid("/World/z", mass=1.0)
    with pytest.raises(InvalidInputError, match="finite"):
        DynamicCuboid("/World/w", position=[0, np.nan, 0])
    assert world.scene.get_object("missing") is None
    with pytest.raises(InvalidInputError):
        world.scene.remove_object("missing")


def test_prim_names_that_usd_refuses_are_refused_with_the_rule():
    """USD prim names are identifiers (a letter or '_', then letters, digits, '_'): Isaac's stage
    refuses '/World/my cube'; manip accepted it (and '-', '.', a leading digit) silently."""
    from manip.sim import XFormPrim, add_reference_to_stage

    World()
    for path in ("/World/my cube", "/World/cube-1", "/World/2cube", "/World/a.b", "/World/x:y"):
        with pytest.raises(InvalidInputError, match="not a valid USD prim name.*letter or '_'"):
            DynamicCuboid(path, name="c")
    with pytest.raises(InvalidInputError, match="'my_robot'"):
        add_reference_to_stage("Isaac/Robots/Franka/franka.usd", "/World/my robot")
    with pytest.raises(InvalidInputError, match="'_1st'"):
        XFormPrim("/World/1st")
    assert DynamicCuboid("/World/_cube_2", name="ok").prim_path == "/World/_cube_2"


def test_a_second_world_is_the_same_instance(caplog):
    w1 = World()
    with caplog.at_level(logging.WARNING):
        w2 = World(physics_dt=0.01)
    assert w2 is w1 and World.instance() is w1
    assert w1.get_physics_dt() == pytest.approx(1 / 60)
    assert "ignored" in caplog.text


def test_the_world_is_the_simulation_context_as_in_isaac():
    """Isaac keeps one SimulationContext per process and World is one: SimulationContext.instance()
    and SimulationContext() after World() are that World (they were None and a second,
    separate simulation of the same stage)."""
    from manip.sim import SimulationContext, SimulationError

    world = World(physics_dt=1 / 120)
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0, 0, 0.5], size=0.1))
    assert SimulationContext.instance() is world
    assert SimulationContext() is world
    world.reset()
    ctx = SimulationContext.instance()
    assert ctx.get_physics_dt() == pytest.approx(1 / 120)
    ctx.step(render=False)
    assert world.current_time_step_index == 2 and cube.get_linear_velocity()[2] < 0
    SimulationContext.clear_instance()  # clears the World too
    assert World.instance() is None and SimulationContext.instance() is None
    SimulationContext()
    assert World.instance() is None  # a plain SimulationContext is not a World
    with pytest.raises(SimulationError, match="clear_instance"):
        World()
    SimulationContext.clear_instance()
    assert isinstance(World(), World)


def test_world_arguments_isaac_has_and_manip_cannot_mirror(caplog):
    for kwargs, message in (({"stage_units_in_meters": 0.01}, "must be 1.0; got 0.01: manip.sim works in metres"),
                            ({"backend": "torch"}, "runs MuJoCo on the CPU"),
                            ({"device": "cuda:0"}, "device must be None or 'cpu'; got 'cuda:0'")):  # was ignored
        with pytest.raises(InvalidInputError, match=message):
            World(**kwargs)
        assert World.instance() is None
    with caplog.at_level(logging.WARNING):
        world = World(sim_params={"gravity": [0.0, 0.0, -1.62], "use_gpu_pipeline": False})
    assert "['use_gpu_pipeline'] are PhysX settings manip.sim does not mirror" in caplog.text
    ball = world.scene.add(DynamicSphere("/World/ball", name="ball", position=[0, 0, 1.0], radius=0.02))
    world.reset()  # the ball is back at its default state after the warm-up step
    for _ in range(60):
        world.step(render=False)
    assert ball.get_world_pose()[0][2] == pytest.approx(1.0 - 0.5 * 1.62 * 1.0**2, abs=5e-3)  # the Moon's gravity


def test_families_fixed_visual_dynamic_and_materials():
    world = World()
    world.scene.add_default_ground_plane()
    table = world.scene.add(FixedCuboid("/World/table", name="table", position=[0, 0, 0.1], size=0.2))
    ghost = world.scene.add(VisualCuboid("/World/ghost", name="ghost", position=[0.5, 0, 0.1], size=0.2))
    on_table = world.scene.add(DynamicCuboid("/World/a", name="a", position=[0, 0, 0.4], size=0.05))
    through = world.scene.add(DynamicCuboid("/World/b", name="b", position=[0.5, 0, 0.4], size=0.05))
    world.reset()
    for _ in range(90):
        world.step(render=False)
    assert np.allclose(table.get_world_pose()[0], [0, 0, 0.1])
    assert on_table.get_world_pose()[0][2] == pytest.approx(0.225, abs=2e-3)  # rests on the fixed box
    assert through.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)  # falls through the visual box
    # Fixed and visual objects are moved by set_world_pose.
    ghost.set_world_pose(position=[1.0, 1.0, 1.0])
    assert np.allclose(ghost.get_world_pose()[0], [1, 1, 1])
    # Friction from a physics material: a sliding cube stops sooner on a rough floor.
    assert on_table.get_mass() == pytest.approx(0.02)


def _slide_distance(friction: float) -> float:
    World.clear_instance()
    from manip.sim import create_new_stage

    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane(static_friction=friction, dynamic_friction=friction)
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 0.025], size=0.05,
                                         physics_material=PhysicsMaterial(dynamic_friction=friction),
                                         linear_velocity=[1.0, 0, 0]))
    world.reset()
    for _ in range(120):
        world.step(render=False)
    return float(cube.get_world_pose()[0][0])


def test_friction_decides_how_far_a_cube_slides():
    # v^2 / (2 mu g): 0.51 m at mu = 0.1, 0.051 m at mu = 1.
    low, high = _slide_distance(0.1), _slide_distance(1.0)
    assert low == pytest.approx(1.0 / (2 * 0.1 * 9.81), rel=0.1)
    assert high == pytest.approx(1.0 / (2 * 1.0 * 9.81), rel=0.2)


def test_collision_objects_and_aabb():
    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(Franka("/World/Franka", name="franka"))
    world.scene.add(FixedCuboid("/World/box", name="box", position=[0.5, 0.1, 0.2], size=0.1, scale=[1, 2, 3]))
    world.scene.add(VisualCuboid("/World/ghost", name="ghost", position=[0.5, 0.5, 0.2], size=0.1))
    from manip.sim import FixedCylinder, DynamicCone

    world.scene.add(FixedCylinder("/World/cyl", name="cyl", position=[-0.5, 0, 0.3], radius=0.05, height=0.4))
    world.scene.add(DynamicCone("/World/cone", name="cone", position=[-0.5, 0.5, 0.05], radius=0.05, height=0.1))
    with pytest.raises(SimulationError):
        world.scene.get_collision_objects()
    world.reset()
    objs = {o.name: o for o in world.scene.get_collision_objects()}
    assert "ghost" not in objs
    box = objs["box"]
    assert box.shape == "cuboid" and np.allclose(box.dimensions, [0.1, 0.2, 0.3])
    assert np.allclose(box.position, [0.5, 0.1, 0.2]) and not box.is_robot and not box.is_dynamic
    assert objs["cyl"].shape == "cylinder" and np.allclose(objs["cyl"].dimensions, [0.05, 0.4])
    cone = objs["cone"]
    assert cone.shape == "cone" and cone.is_dynamic and cone.vertices.shape[1] == 3
    assert objs["default_ground_plane"].shape == "plane"
    robot = [o for o in objs.values() if o.is_robot]
    assert len(robot) >= 10 and all(o.robot_prim_path == "/World/Franka" for o in robot)
    assert all(o.vertices is not None and o.faces.shape[1] == 3 for o in robot if o.shape == "mesh")
    # Cone mesh: apex at +h/2 in the shape frame, base disc at -h/2.
    z = cone.pose.transform_points(cone.vertices)[:, 2] - cone.position[2]
    assert z.max() == pytest.approx(0.05, abs=1e-6) and z.min() == pytest.approx(-0.05, abs=1e-6)
    aabb = world.scene.compute_object_AABB("box")
    assert np.allclose(aabb, [[0.45, 0.0, 0.05], [0.55, 0.2, 0.35]], atol=1e-9)


def test_views_match_objects():
    world = World()
    cubes = [world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube{i}", position=[i * 0.2, 0, 0.5],
                                           size=0.05)) for i in range(3)]
    view = world.scene.add(RigidPrimView("/World/Cube_[0-9]+", name="cubes"))
    with pytest.raises(SimulationError):
        view.get_world_poses()
    world.reset()
    assert view.count == 3
    p, q = view.get_world_poses()
    assert np.allclose(p[:, 0], [0, 0.2, 0.4])
    view.set_world_poses(positions=np.array([[0, 1, 1], [0, 2, 1], [0, 3, 1]]), indices=[0, 1, 2])
    assert np.allclose(cubes[2].get_world_pose()[0], [0, 3, 1])
    view.set_velocities(np.tile([0.0, 0, 0, 0, 0, 1.0], (3, 1)))
    assert np.allclose(view.get_velocities()[:, 5], 1.0)
    assert np.allclose(cubes[0].get_angular_velocity(), [0, 0, 1])
    assert np.allclose(view.get_masses(), 0.02)


def test_view_expressions_match_per_path_segment_and_a_view_of_nothing_raises_as_in_isaac():
    world = World()
    world.scene.add_default_ground_plane()
    for i in range(2):
        world.scene.add(DynamicCuboid(f"/World/Cube_{i}", name=f"cube{i}", position=[i * 0.3, 0.8, 0.5], size=0.05,
                                      scale=[1.0, 1.0 + i, 1.0]))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    # The glob a tutorial reader writes first: Isaac raises at construction, so does manip.
    with pytest.raises(InvalidInputError, match=r"matches no prim.*'/World/Cube_\.\*'.*not the glob"):
        RigidPrimView(prim_paths_expr="/World/Cube_*", name="cubes")
    with pytest.raises(InvalidInputError, match="absolute path expression"):
        XFormPrimView("World/Cube_.*")
    # Isaac options manip cannot honour raise instead of being dropped.
    with pytest.raises(InvalidInputError, match="scales and visibilities are not supported"):
        XFormPrimView("/World/Cube_.*", scales=np.ones((2, 3)))
    with pytest.raises(InvalidInputError, match=r"masses=\[1.0, 1.0\]\) is not supported"):
        RigidPrimView("/World/Cube_.*", masses=[1.0, 1.0])
    with pytest.raises(InvalidInputError, match="unknown argument 'mass'"):
        RigidPrimView("/World/Cube_.*", mass=1.0)
    cubes = world.scene.add(RigidPrimView(prim_paths_expr="/World/Cube_.*", name="cubes", track_contact_forces=False))
    links = world.scene.add(XFormPrimView("/World/Franka/panda_link[0-9]", name="links"))  # inside the model
    everything = XFormPrimView("/World/.*")  # one segment: the top prims, not the Franka's links
    world.reset()
    assert cubes.prim_paths == ["/World/Cube_0", "/World/Cube_1"]
    assert links.count == 8 and links.prim_paths[0] == "/World/Franka/panda_link0"
    assert "/World/Cube_1" in everything.prim_paths and not any(p.count("/") > 2 for p in everything.prim_paths)
    for _ in range(60):
        world.step(render=False)
    np.testing.assert_allclose(cubes.get_world_poses()[0][:, 2], 0.025, atol=2e-3)
    np.testing.assert_allclose(cubes.get_local_scales(), [[1, 1, 1], [1, 2, 1]])  # Isaac's getter (was missing)
    np.testing.assert_allclose(links.get_world_scales(), np.ones((8, 3)))
    np.testing.assert_allclose(links.get_world_poses()[0][0], franka.get_world_pose()[0], atol=1e-9)
    # A view whose prims were removed says so instead of failing on array shapes.
    world.scene.remove_object("cube0")
    world.scene.remove_object("cube1")
    world.reset()
    with pytest.raises(SimulationError, match="matches no prim of the compiled world"):
        cubes.set_world_poses(positions=np.zeros((2, 3)))


class CountingTask(BaseTask):
    def __init__(self):
        super().__init__("counting")
        self.pre_steps = []
        self.resets = 0
        self.setups = 0

    def set_up_scene(self, scene):
        super().set_up_scene(scene)
        self.setups += 1
        self._task_objects["ball"] = scene.add(DynamicSphere("/World/ball", name="ball", radius=0.02))

    def pre_step(self, time_step_index, simulation_time):
        self.pre_steps.append((time_step_index, simulation_time))

    def post_reset(self):
        self.resets += 1

    def get_observations(self):
        return {"ball": {"position": self._task_objects["ball"].get_world_pose()[0]}}


def test_tasks_are_set_up_once_and_stepped():
    world = World()
    task = CountingTask()
    world.add_task(task)
    with pytest.raises(InvalidInputError):
        world.add_task(CountingTask())
    world.reset()
    world.reset()
    assert task.setups == 1 and task.resets == 2
    for _ in range(3):
        world.step()
    # the reset's warm-up step runs no pre_step (Isaac); the first world.step() is index 1
    assert task.pre_steps == [(1, pytest.approx(1 / 60)), (2, pytest.approx(2 / 60)), (3, pytest.approx(3 / 60))]
    assert "ball" in world.get_observations()
    assert world.get_task("counting") is task
    with pytest.raises(UnknownNameError):
        world.get_task("nope")
    # Methods a task did not override say which and what to return (was a bare NotImplementedError).
    with pytest.raises(NotImplementedError, match=r"CountingTask.get_params\(\) is not implemented: override it"):
        task.get_params()
    with pytest.raises(NotImplementedError, match=r"CountingTask.is_done\(\) is not implemented.*a bool"):
        world.is_done()


class SpawningTask(BaseTask):
    """Adds cubes during an episode; its cleanup removes them (Isaac: before every reset)."""

    def __init__(self):
        super().__init__("spawning")
        self.spawned: list[str] = []
        self.cleanups = 0

    def spawn(self) -> DynamicCuboid:
        name = f"tmp_{len(self.spawned)}"
        self.spawned.append(name)
        return self.scene.add(DynamicCuboid(f"/World/{name}", name=name, position=[0.3 * len(self.spawned), 0, 0.5],
                                            size=0.05))

    def cleanup(self):
        self.cleanups += 1
        for name in self.spawned:
            self.scene.remove_object(name)
        self.spawned = []


def test_every_reset_calls_the_tasks_cleanup_first_as_isaac():
    world = World()
    task = SpawningTask()
    world.add_task(task)
    world.reset()
    assert task.cleanups == 1
    cube = task.spawn()
    world.reset()
    for _ in range(30):
        world.step(render=False)
    # The cube spawned during the episode is gone: not in the scene, not in the compiled model.
    assert task.cleanups == 2 and not world.scene.object_exists(cube.name)
    assert all(world.model.body(b).name != cube.prim_path for b in range(world.model.nbody))
    task.spawn()
    world.reset(soft=True)
    assert task.cleanups == 3 and task.spawned == []


def test_pick_place_task_scene_and_observations():
    world = World()
    world.add_task(PickPlace(cube_initial_position=[0.45, 0.1, 0.025], target_position=[0.3, -0.3, 0.025]))
    world.reset()
    obs = world.get_observations()
    params = world.get_task("franka_pick_place").get_params()
    cube_name, robot_name = params["cube_name"]["value"], params["robot_name"]["value"]
    assert (cube_name, robot_name) == ("cube", "my_franka")  # Isaac's names (the robot was "franka")
    assert set(obs[cube_name]) == {"position", "orientation", "target_position"}
    assert set(obs[robot_name]) == {"joint_positions", "end_effector_position"}
    assert np.allclose(obs[cube_name]["position"], [0.45, 0.1, 0.025])
    assert obs[robot_name]["joint_positions"].shape == (9,)
    assert np.allclose(obs[robot_name]["joint_positions"][7:], 0.04)
    cube = world.scene.get_object(cube_name)
    assert np.allclose(cube.get_size() * cube.get_local_scale(), 0.0515) and 0.01 <= cube.get_mass() <= 0.05  # Isaac: size 1 scaled
    for _ in range(30):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.025, abs=1e-3)  # rests on the ground
    assert not world.is_done()
    world.get_task("franka_pick_place").set_params(cube_position=[0.3, -0.3, 0.025])
    assert world.is_done()


def test_a_world_without_tasks_is_done_as_isaacs(fresh_world):
    world = fresh_world()
    world.reset()
    assert world.is_done()   # Isaac: all() of no task's is_done()


def _trajectory() -> np.ndarray:
    World.clear_instance()
    from manip.sim import create_new_stage

    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0.4, 0.0, 0.3], size=0.05,
                                         angular_velocity=[1.0, 2.0, 0.5]))
    world.reset()
    target = franka.get_joint_positions() + np.r_[0.3, 0.2, -0.2, 0.3, 0.2, -0.2, 0.3, -0.02, -0.02]
    franka.apply_action(ArticulationAction(joint_positions=target))
    out = []
    for _ in range(60):
        world.step(render=False)
        out.append(np.concatenate([franka.get_joint_positions(), *cube.get_world_pose()]))
    return np.array(out)


def test_determinism_same_script_same_trajectory():
    a, b = _trajectory(), _trajectory()
    assert np.array_equal(a, b)


def test_recording_writes_an_mp4(tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    from manip.sim import OffscreenRenderingError

    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 0.5], size=0.1, color=[1, 0, 0]))
    world.reset()
    path = tmp_path / "drop.mp4"
    try:
        world.start_recording(path, width=160, height=120, fps=30)
    except OffscreenRenderingError as exc:  # pragma: no cover - machines without EGL/OSMesa
        pytest.skip(str(exc))
    for _ in range(30):
        world.step(render=True)
    assert world.stop_recording() == path
    import imageio.v2 as imageio

    reader = imageio.get_reader(str(path))
    frames = [f for f in reader]
    assert len(frames) == 16  # the first frame, then one every 2 steps of 1/60 s
    assert frames[0].shape == (120, 160, 3)
    assert not np.array_equal(frames[0], frames[-1])  # the cube fell


def test_removing_a_robot_removes_its_frames_and_the_world_resets_without_it():
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0, 0.3], size=0.05))
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    assert franka.num_dof == 9
    world.scene.remove_object("franka")  # its end-effector frame /World/Franka/panda_hand_tcp goes with it
    world.reset()
    assert world.model.njnt == 1  # the cube's free joint only
    assert franka.num_dof is None and franka.end_effector.get_world_pose() is None
    for _ in range(30):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.025, abs=2e-3)
    # A new Franka at the same prim path is a robot again.
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    world.reset()
    assert franka.num_dof == 9 and franka.end_effector.get_world_pose()[0][2] > 0.3
    world.scene.clear()
    world.reset()
    assert world.model.nbody == 1  # the world body only


def test_changing_the_physics_step_mid_run_keeps_time_continuous():
    world = World()
    ball = world.scene.add(DynamicSphere("/World/ball", name="ball", position=[0, 0, 10.0], radius=0.05))
    world.reset()
    for _ in range(59):
        world.step(render=False)
    assert world.current_time == pytest.approx(1.0)
    with pytest.raises(InvalidInputError, match="rendering_dt"):
        world.set_simulation_dt(physics_dt=1 / 120, rendering_dt=-1.0)
    assert world.get_physics_dt() == pytest.approx(1 / 60)  # nothing changed
    world.set_simulation_dt(physics_dt=1 / 120, rendering_dt=1 / 120)
    z0, v0 = ball.get_world_pose()[0][2], ball.get_linear_velocity()[2]
    for _ in range(120):
        world.step(render=False)
    assert world.current_time == pytest.approx(2.0)  # was 121 / 120 s: the past recomputed with the new step
    assert ball.get_world_pose()[0][2] - z0 == pytest.approx(v0 - 0.5 * 9.81, abs=0.02)  # 1 s of free fall


def test_zero_physics_or_rendering_dt_as_isaacs_time_stepping_example():
    """Isaac's time_stepping example: physics_dt=0 stops physics (a step only renders) until a
    positive dt is set; rendering_dt=0 makes step(render=True) run one physics step; render
    callbacks get Isaac's payload {"dt": rendering_dt} (all raised)."""
    world = World()
    ball = world.scene.add(DynamicSphere("/World/ball", name="ball", position=[0, 0, 10.0], radius=0.05))
    events = []
    world.add_render_callback("r", lambda event: events.append(event.payload["dt"]))
    world.reset()
    world.set_simulation_dt(physics_dt=0.0, rendering_dt=1 / 60)
    t, z = world.current_time, ball.get_world_pose()[0][2]
    for _ in range(5):
        world.step(render=True)
    assert world.current_time == t and ball.get_world_pose()[0][2] == z and world.get_physics_dt() == 0.0
    assert events[-1] == pytest.approx(1 / 60) and len(events) >= 5
    world.set_simulation_dt(physics_dt=1 / 60, rendering_dt=0.0)
    world.step(render=True)
    assert world.current_time == pytest.approx(t + 1 / 60) and ball.get_world_pose()[0][2] < z
    assert events[-1] == 0.0
    world.set_simulation_dt(physics_dt=1 / 600)  # the rendering_dt stays 0: one 1/600 s step per render
    world.step(render=True)
    assert world.current_time == pytest.approx(t + 1 / 60 + 1 / 600)


def test_xform_rigid_and_geometry_prims_wrap_an_existing_object_as_in_isaac():
    world = World()
    world.scene.add_default_ground_plane()
    DynamicCuboid(prim_path="/World/cube", position=[0, 0, 0.5], size=0.1, mass=0.3)  # not added to the scene
    FixedCuboid(prim_path="/World/table", position=[1, 0, 0.2], size=0.4, color=np.array([0.2, 0.4, 0.6]))
    cube = world.scene.add(RigidPrim(prim_path="/World/cube", name="cube"))  # was: "a prim already exists"
    table = world.scene.add(GeometryPrim(prim_path="/World/table", name="table"))
    frame = XFormPrim(prim_path="/World/cube", name="cube_frame")
    assert cube.get_mass() == pytest.approx(0.3) and np.allclose(table.get_color(), [0.2, 0.4, 0.6])
    np.testing.assert_allclose(frame.get_world_pose()[0], [0, 0, 0.5])
    with pytest.raises(InvalidInputError, match="wraps the existing DynamicCuboid there; position cannot be given"):
        XFormPrim(prim_path="/World/cube", name="moved", position=[0, 0, 1.0])
    world.reset()
    for _ in range(60):
        world.step(render=False)
    assert cube.get_world_pose()[0][2] == pytest.approx(0.05, abs=2e-3)  # the one cube fell onto the ground
    np.testing.assert_allclose(frame.get_world_pose()[0], cube.get_world_pose()[0])
    cube.set_world_pose(position=[0.0, 0.5, 0.3])
    cube.set_linear_velocity([0.5, 0.0, 0.0])
    world.step(render=False)
    assert frame.get_world_pose()[0][1] == pytest.approx(0.5) and cube.get_linear_velocity()[0] > 0.4
    np.testing.assert_allclose(world.scene.compute_object_AABB("table"), [[0.8, -0.2, 0.0], [1.2, 0.2, 0.4]])
    world.reset()  # the wrapper's default pose is the object's pose when it was wrapped
    np.testing.assert_allclose(cube.get_world_pose()[0], [0, 0, 0.5])
