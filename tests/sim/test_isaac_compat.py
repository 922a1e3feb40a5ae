"""Isaac behaviours the tutorials rely on: async sample hooks, reset stepping, wrappers added
after a reset, Isaac asset paths, carb logging, the articulation view, BaseSampleExtension."""

from __future__ import annotations

import asyncio
import logging

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import (
    ArticulationAction,
    ArticulationView,
    BaseSample,
    BaseSampleExtension,
    BaseTask,
    DynamicCuboid,
    HelloWorld,
    Robot,
    SimulationError,
    WheeledRobot,
    World,
    add_reference_to_stage,
    carb,
    clear_stage,
    create_new_stage_async,
    get_assets_root_path,
    get_current_stage,
    update_stage_async,
)

FRANKA_USD = "/Isaac/Robots/Franka/franka.usd"


class Hooks(BaseSample):
    """Mixed hooks: some async (as Isaac's samples), some plain."""

    def __init__(self):
        super().__init__()
        self.calls: list[str] = []

    def setup_scene(self):
        self.calls.append("setup_scene")
        world = self.get_world()
        world.scene.add_default_ground_plane()
        world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0, 0, 0.3], size=0.05))

    async def setup_post_load(self):
        await asyncio.sleep(0)
        self.calls.append(f"setup_post_load playing={self.get_world().is_playing()}")

    def setup_pre_reset(self):
        self.calls.append("setup_pre_reset")

    async def setup_post_reset(self):
        self.calls.append(f"setup_post_reset step={self.get_world().current_time_step_index}")

    async def setup_post_clear(self):
        self.calls.append("setup_post_clear")

    def world_cleanup(self):
        self.calls.append("world_cleanup")


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_sync_and_async_hooks_run_in_isaacs_order():
    sample = Hooks()
    asyncio.run(sample.load_world_async())
    world = sample.get_world()
    assert not world.is_playing()  # paused after Load, as Isaac
    world.play()
    for _ in range(10):
        world.step(render=False)
    asyncio.run(sample.reset_async())
    asyncio.run(sample.clear_async())
    assert World.instance() is None
    assert sample.calls == ["setup_scene", "setup_post_load playing=False", "setup_pre_reset",
                            "setup_post_reset step=1", "world_cleanup", "setup_post_clear"]
    sample2 = Hooks()
    sample2.load_world()  # the synchronous forms run the same coroutines
    sample2.reset()
    sample2.clear()
    assert sample2.calls == sample.calls


def test_sync_forms_refuse_a_running_loop_and_load_reuses_an_existing_world(caplog):
    sample = Hooks()

    async def inside():
        with pytest.raises(SimulationError, match="await"):
            sample.load_world()
        await sample.load_world_async()

    asyncio.run(inside())
    other = Hooks()
    with caplog.at_level(logging.WARNING):
        other.load_world()  # Isaac: the existing World is used, setup_scene is not called
    assert other.get_world() is sample.get_world() and "setup_scene" not in other.calls
    assert "setup_scene() is not called" in caplog.text
    with pytest.raises(SimulationError, match="load"):
        Hooks().reset()


def test_world_async_methods_are_awaitable():
    async def script():
        await create_new_stage_async()
        world = World()
        await world.initialize_simulation_context_async()
        world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
        await world.reset_async()
        assert world.is_playing()
        await world.pause_async()
        assert not world.is_playing()
        await world.play_async()
        await update_stage_async()
        await world.render_async()
        await world.stop_async()
        return world

    world = asyncio.run(script())
    assert world.is_stopped()


def test_reset_plays_and_steps_once_like_isaac():
    world = World()
    calls = []
    world.add_physics_callback("cb", lambda dt: calls.append(world.current_time_step_index))
    cube = world.scene.add(DynamicCuboid("/World/c", name="c", position=[0, 0, 1.0], size=0.1))
    world.reset()
    assert world.is_playing() and world.current_time_step_index == 1
    assert world.current_time == pytest.approx(1 / 60) and calls == []  # no callback in the warm-up step
    assert cube.get_world_pose()[0][2] == 1.0  # default state restored after the warm-up step
    # the pick-and-place tutorial's "if index < 2: world.reset()" loop ends
    for _ in range(5):
        world.step(render=True)
        if world.current_time_step_index < 2:
            world.reset()
    assert world.current_time_step_index == 6 and calls == [1, 2, 3, 4, 5]
    world.reset(soft=True)  # soft: default states only, time goes on
    assert world.current_time_step_index == 6 and cube.get_world_pose()[0][2] == 1.0


def test_a_robot_wrapped_after_a_reset_is_initialised_by_the_next_reset():
    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0, 0.1], size=0.05))
    world.reset()
    add_reference_to_stage(get_assets_root_path() + FRANKA_USD, "/World/Franka")
    robot = world.scene.add(Robot(prim_path="/World/Franka", name="franka"))
    assert robot.num_dof is None  # not compiled yet (Isaac: before the next reset)
    robot.initialize()  # nothing to bind to yet: no error
    world.reset()
    assert robot.num_dof == 9
    again = Robot(prim_path="/World/Franka", name="franka_again")  # a second wrapper of a compiled model
    assert again.num_dof == 9
    jetbot = WheeledRobot("/World/Jetbot", name="jetbot", wheel_dof_names=["left_wheel_joint", "right_wheel_joint"],
                          create_robot=True, usd_path=get_assets_root_path() + "/Isaac/Robots/Jetbot/jetbot.usd",
                          position=[1.0, 0.0, 0.0])  # not inside the Franka (robots inside each other raise at reset)
    world.scene.add(jetbot)
    world.reset()
    assert jetbot.wheel_dof_indices.tolist() == [0, 1]


@pytest.mark.parametrize("asset, dof", [("/Isaac/Robots/Jetbot/jetbot.usd", 2), (FRANKA_USD, 9),
                                        ("/Isaac/Robots/Franka/franka_alt_fingers.usd", 9),
                                        ("/Isaac/Robots/FrankaRobotics/FrankaPanda/franka.usd", 9),
                                        ("/Isaac/Robots/NVIDIA/Jetbot/jetbot.usd", 2)])  # Isaac 5's Jetbot
def test_isaac_asset_paths_resolve_to_the_bundled_models(asset, dof):
    world = World()
    add_reference_to_stage(usd_path=get_assets_root_path() + asset, prim_path="/World/Robot")
    robot = world.scene.add(Robot("/World/Robot", name="robot"))
    world.reset()
    assert robot.num_dof == dof
    # any prefix works (a Nucleus URL from an Isaac script)
    add_reference_to_stage("omniverse://localhost/NVIDIA/Assets/Isaac/4.0" + asset, "/World/Robot2")


def test_an_unknown_asset_lists_the_available_ones():
    with pytest.raises(FileNotFoundError, match="no USD") as info:
        add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/UR10/ur10.usd", "/World/UR10")
    message = str(info.value)
    assert "/Isaac/Robots/Franka/franka.usd" in message and "jetbot/jetbot.xml" in message
    assert get_current_stage().prim_paths() == []


def test_carb_logs_through_python_logging(caplog):
    with caplog.at_level(logging.DEBUG, logger="manip.sim.carb"):
        carb.log_info("info")
        carb.log_warn("warn")
        carb.log_error("error")
        carb.log_verbose("verbose")
    levels = [(r.levelno, r.getMessage()) for r in caplog.records]
    assert levels == [(logging.INFO, "info"), (logging.WARNING, "warn"), (logging.ERROR, "error"),
                      (logging.DEBUG, "verbose")]
    assert caplog.records[0].filename == "test_isaac_compat.py"  # the caller, not the carb module


def test_articulation_view_reads_and_sets_gains():
    world = World()
    add_reference_to_stage(get_assets_root_path() + FRANKA_USD, "/World/Franka")
    robot = world.scene.add(Robot("/World/Franka", name="franka"))
    view = robot._articulation_view
    with pytest.raises(SimulationError, match="reset"):
        view.get_gains()
    world.reset()
    kps, kds = view.get_gains()
    assert kps.shape == kds.shape == (1, 9)
    np.testing.assert_allclose(kps[0], robot.get_articulation_controller().get_gains()[0])
    assert view.num_dof == 9 and view.num_joints == 10 and view.count == 1
    view.set_gains(kps=np.full(9, 100.0), joint_indices=None)
    assert np.all(robot.dof_properties["stiffness"] == 100.0)
    assert view.get_dof_limits().shape == (1, 9, 2)
    with pytest.raises(Exception, match="one articulation"):
        view.get_gains(indices=[1])


def test_articulation_view_from_a_prim_path_expression_as_isaac_scripts_make_it():
    world = World()
    world.scene.add_default_ground_plane()
    add_reference_to_stage(get_assets_root_path() + FRANKA_USD, "/World/Franka")
    add_reference_to_stage(get_assets_root_path() + FRANKA_USD, "/World/Franka_2")
    with pytest.raises(InvalidInputError, match=r"matches 2 referenced models \['/World/Franka', '/World/Franka_2'\]"):
        ArticulationView(prim_paths_expr="/World/Franka.*", name="frankas")
    with pytest.raises(InvalidInputError, match="matches no referenced model.*'/World/Franka'"):
        ArticulationView(prim_paths_expr="/World/Panda", name="panda")
    view = world.scene.add(ArticulationView(prim_paths_expr="/World/Franka", name="franka_view"))
    robot = Robot("/World/Franka", name="franka")
    Robot("/World/Franka_2", name="franka_2", position=[0.0, 2.0, 0.0])  # out of the first one's way
    assert world.scene.get_object("franka_view") is view
    world.reset()
    view.initialize()
    assert view.count == 1 and view.num_dof == 9 and view.dof_names[7] == "panda_finger_joint1"
    q = np.array([[0.3, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8, 0.02, 0.02]])
    view.set_joint_positions(q)
    np.testing.assert_allclose(view.get_joint_positions(), q)
    np.testing.assert_allclose(robot.get_applied_action().joint_positions, q[0])  # teleport sets the targets
    view.set_joint_position_targets(np.array([[0.6]]), joint_indices=np.array([0]))
    for _ in range(60):
        world.step(render=False)
    assert view.get_joint_positions(joint_indices=[0])[0, 0] == pytest.approx(0.6, abs=2e-3)
    view.apply_action(ArticulationAction(joint_positions=[0.04, 0.04], joint_indices=[7, 8]))
    for _ in range(30):
        world.step(render=False)
    np.testing.assert_allclose(robot.get_joint_positions([7, 8]), 0.04, atol=1e-3)
    with pytest.raises(InvalidInputError, match=r"shape \(1, K\) or \(K,\)"):
        view.set_joint_positions(np.zeros((2, 9)))


def test_clear_stage_empties_the_stage_and_the_scene():
    world = World()
    world.scene.add_default_ground_plane()
    world.scene.add(DynamicCuboid("/World/c", name="c", size=0.1))
    world.reset()
    clear_stage()
    assert get_current_stage().prim_paths() == [] and world.scene.get_object_names() == []
    world.scene.add(DynamicCuboid("/World/d", name="d", size=0.1))
    world.reset()
    world.step()
    World.clear_instance()
    add_reference_to_stage(get_assets_root_path() + FRANKA_USD, "/World/Franka")
    clear_stage()  # without a World
    assert get_current_stage().prim_paths() == []


class PreStepCounter(BaseTask):
    def __init__(self):
        super().__init__("counter")
        self.indices = []

    def pre_step(self, time_step_index, simulation_time):
        self.indices.append(time_step_index)


def test_base_sample_extension_buttons_drive_the_sample():
    events = []

    class Sample(HelloWorld):
        def setup_scene(self):
            super().setup_scene()
            self.task = PreStepCounter()
            self.get_world().add_task(self.task)

    class Extension(BaseSampleExtension):
        def on_startup(self, ext_id):
            super().on_startup(ext_id)
            super().start_extension("", "", "Demo", "Demo", "", "", __file__, sample=Sample())

        def post_load_button_event(self):
            events.append("load")

        def post_reset_button_event(self):
            events.append("reset")

    ext = Extension()
    with pytest.raises(SimulationError, match="on_startup"):
        BaseSampleExtension().load_world()
    ext.on_startup("demo.ext")
    assert ext.get_buttons()["Reset"].click() is None  # disabled before loading
    ext.get_buttons()["Load World"].click()
    world = ext.get_world()
    assert world.physics_callback_exists("tasks_step") and world.timeline_callback_exists("stop_reset_event")
    world.play()
    for _ in range(3):
        world.step(render=True)
    assert ext.sample.task.indices == [1, 2, 3]  # once per physics step (World.step and "tasks_step" agree)
    ext.reset()
    assert ext.sample.task.indices[-1] == 3 and world.current_time_step_index == 1
    assert events == ["load", "reset"]
    with pytest.raises(Exception, match="extra frames"):
        ext.get_frame(1)
    ext.clear()
    assert World.instance() is None and ext.get_buttons()["Load World"].enabled
    ext.on_shutdown()


def test_isaacs_keyword_arguments_are_accepted():
    # Keywords of Isaac 4.x signatures that raised TypeError (checked against Isaac's source).
    from manip.sim import OmniGlass, RigidPrimView, SimulationApp, XFormPrimView

    app = SimulationApp({"headless": True})
    world = World()
    for i in range(2):
        world.scene.add(DynamicCuboid(f"/World/C_{i}", name=f"c{i}", position=[float(i), 0.0, 0.5], size=0.1))
    rigid = world.scene.add(RigidPrimView("/World/C_.*", name="rigid"))
    world.scene.add(XFormPrimView("/World/C_.*", name="xform", usd=False))
    world.reset()
    positions, _ = rigid.get_world_poses(indices=[1], clone=True, usd=False)
    np.testing.assert_allclose(positions, [[1.0, 0.0, 0.5]])
    rigid.set_world_poses(positions=np.array([[0.0, 0.0, 1.0]]), indices=[0], usd=False)
    assert rigid.get_world_poses()[0][0, 2] == pytest.approx(1.0)
    assert rigid.get_velocities(clone=False).shape == (2, 6) and rigid.get_linear_velocities(clone=True).shape == (2, 3)
    assert rigid.is_valid(indices=[0])
    with pytest.raises(InvalidInputError, match="out of range"):
        rigid.is_valid(indices=[5])
    glass = OmniGlass("/World/Looks/glass")
    glass.set_ior(ior=1.5)
    glass.set_thin_walled(thin_walled=True)
    assert glass.get_ior() == 1.5 and glass.get_thin_walled()
    app.set_setting(setting="/app/window/drawMouse", value=True)
    app.close(wait_for_replicator=False)


def test_isaacs_utility_keyword_arguments_are_accepted():
    import manip.sim as sim

    q = sim.euler_angles_to_quat(np.array([0.0, 0.0, 90.0]), degrees=True)
    np.testing.assert_allclose(sim.quat_to_euler_angles(quat=q, degrees=True), [0.0, 0.0, 90.0], atol=1e-9)
    np.testing.assert_allclose(sim.quat_to_rot_matrix(quat=q) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12)
    world = World()
    world.scene.add(DynamicCuboid("/World/cube", name="cube", size=0.1))
    assert sim.get_current_stage(fabric=False) is sim.get_current_stage()
    assert sim.is_prim_path_valid("/World/cube", fabric=False)
    assert sim.get_prim_at_path("/World/cube", fabric=False) is world.scene.get_object("cube")
    assert sim.find_matching_prim_paths("/World/cu.*", prim_type=None) == ["/World/cube"]
    with pytest.raises(InvalidInputError, match="no USD prim types"):
        sim.find_matching_prim_paths("/World/.*", prim_type="Mesh")
    with pytest.raises(InvalidInputError, match="delete_prim"):
        sim.clear_stage(predicate=lambda path: True)


def test_a_ground_plane_takes_isaacs_visual_material():
    from manip.sim import GroundPlane, PreviewSurface

    world = World()
    grey = PreviewSurface("/World/Looks/grey", color=np.array([0.5, 0.5, 0.5]))
    ground = world.scene.add(GroundPlane("/World/ground", z_position=0.0, visual_material=grey))  # was TypeError
    world.reset()
    assert ground.get_applied_visual_material() is grey
    np.testing.assert_allclose(ground.get_color(), [0.5, 0.5, 0.5])
