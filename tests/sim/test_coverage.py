"""The Isaac core-API coverage table (docs/isaac_coverage.md) is the code's: regenerated it is
identical, no listed member is missing, every "raises" member raises NotImplementedError
naming itself, and every other one is there on a real object."""

from __future__ import annotations

import numpy as np
import pytest
from robot_constants import REPO_ROOT

from manip import sim
from manip.sim.coverage import class_rows, function_rows, markdown

DOC = REPO_ROOT / "docs" / "isaac_coverage.md"


def test_the_document_is_the_generated_table():
    assert DOC.read_text() == markdown(), "regenerate: python -m manip.sim.coverage > docs/isaac_coverage.md"


def test_no_listed_member_is_missing():
    missing = [(r.owner, r.member) for r in class_rows() + function_rows() if r.status == "missing"]
    assert not missing


def _objects() -> dict:
    """One real object of each class of the table, after a reset."""
    app = sim.SimulationApp()
    world = sim.World()
    world.scene.add_default_ground_plane()
    # away from the PickPlace task's Franka at the origin (robots inside each other raise at reset)
    franka = world.scene.add(sim.Franka("/World/Franka", name="franka", position=[-2.0, 0.0, 0.0]))
    objs = {
        "DynamicCuboid": sim.DynamicCuboid("/World/cube", name="cube", position=[0.5, 0, 0.03], size=0.05),
        "FixedCuboid": sim.FixedCuboid("/World/wall", name="wall", position=[0, 1, 0.1], size=0.1),
        "VisualCuboid": sim.VisualCuboid("/World/mark", name="mark", position=[0, -1, 0.1], size=0.1),
        "DynamicSphere": sim.DynamicSphere("/World/ball", name="ball", position=[1, 0, 0.05], radius=0.05),
        "DynamicCylinder": sim.DynamicCylinder("/World/can", name="can", position=[1, 1, 0.05], radius=0.03,
                                               height=0.1),
    }
    for o in objs.values():
        world.scene.add(o)
    task = sim.PickPlace(name="pp", cube_initial_position=[0.4, 0.3, 0.03])
    world.add_task(task)
    stacking = sim.Stacking(name="stack", offset=[0.0, 2.0, 0.0])
    world.add_task(stacking)
    rigid_view = world.scene.add(sim.RigidPrimView("/World/cube", name="cube_view"))
    xform_view = world.scene.add(sim.XFormPrimView("/World/mark", name="mark_view"))
    geometry_view = world.scene.add(sim.GeometryPrimView("/World/(cube|wall)", name="shapes_view"))
    suction = sim.SurfaceGripper("/World/Franka/panda_hand", direction="z")
    art_view = world.scene.add(sim.ArticulationView(prim_paths_expr="/World/Franka", name="franka_view"))
    world.reset()
    rmpflow = sim.RmpFlow(**sim.interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow"))
    policy = sim.ArticulationMotionPolicy(franka, rmpflow)
    objs.update({
        "SimulationApp": app, "SimulationContext": world, "World": world, "Scene": world.scene,
        "PhysicsContext": world.get_physics_context(), "Camera": sim.Camera("/World/camera", resolution=(64, 48)),
        "XFormPrim": sim.XFormPrim("/World/target", name="target"),
        "GeometryPrim": sim.GeometryPrim("/World/cube", name="cube_geometry"),
        "GeometryPrimView": geometry_view, "SurfaceGripper": suction,
        "RigidPrim": sim.RigidPrim("/World/Franka/panda_hand", name="hand"),
        "XFormPrimView": xform_view, "RigidPrimView": rigid_view, "ArticulationView": art_view,
        "GroundPlane": world.scene.get_object("default_ground_plane"),
        "PhysicsMaterial": sim.PhysicsMaterial("/World/Physics_Materials/m", dynamic_friction=0.4),
        "PreviewSurface": sim.PreviewSurface("/World/Looks/p", color=[1, 0, 0]),
        "OmniPBR": sim.OmniPBR("/World/Looks/q", color=[0, 1, 0]),
        "Articulation": franka, "Robot": franka, "Franka": franka,
        "ArticulationController": franka.get_articulation_controller(), "ParallelGripper": franka.gripper,
        "PickPlaceController": sim.PickPlaceController(name="ppc", gripper=franka.gripper,
                                                       robot_articulation=franka),
        "BaseTask": task, "PickPlace": task,
        "RMPFlowController": sim.RMPFlowController(name="rmp", robot_articulation=franka),
        "Stacking": stacking,
        "StackingController": sim.StackingController("sc", franka.gripper, franka, stacking.get_cube_names(),
                                                     franka.name),
        "RmpFlow": rmpflow, "ArticulationMotionPolicy": policy,
        "MotionPolicyController": sim.MotionPolicyController("mpc", policy),
    })
    return objs


def test_every_member_is_there_and_every_raising_one_says_why():
    objs = _objects()
    for row in class_rows():
        obj = objs[row.owner]
        if row.status == "raises":
            with pytest.raises(NotImplementedError, match=f"{row.member} is not available in manip.sim: .+"):
                member = getattr(obj, row.member)
                member()
        else:
            assert hasattr(obj, row.member), (row.owner, row.member)
    objs["SimulationApp"].close()


def test_the_utilities_work_or_say_why():
    world = sim.World()
    cube = world.scene.add(sim.DynamicCuboid("/World/Cube_0", name="c0", size=0.1))
    world.scene.add(sim.DynamicCuboid("/World/Cube_1", name="c1", size=0.1, position=[0.5, 0, 0]))
    assert sim.find_matching_prim_paths("/World/Cube_.*") == ["/World/Cube_0", "/World/Cube_1"]
    assert sim.get_prim_at_path("/World/Cube_0") is cube and sim.get_stage_units() == 1.0
    assert not sim.is_stage_loading()
    np.testing.assert_allclose(sim.euler_to_rot_matrix([0, 0, np.pi / 2]) @ [1, 0, 0], [0, 1, 0], atol=1e-12)
    sim.delete_prim("/World/Cube_1")
    assert not sim.is_prim_path_valid("/World/Cube_1") and world.scene.get_object("c1") is None
    for row in function_rows():
        if row.status == "raises":
            with pytest.raises(NotImplementedError, match=row.member):
                getattr(sim, row.member)("x")


def test_a_robots_links_are_valid_prim_paths_as_in_isaac():
    world = sim.World()
    franka = world.scene.add(sim.Franka("/World/Franka", name="franka"))
    # before and after the first reset (it said False for every link: only scene objects counted)
    for _ in range(2):
        assert sim.is_prim_path_valid("/World/Franka") and sim.is_prim_path_valid("/World/Franka/panda_hand")
        assert sim.is_prim_path_valid("/World/Franka/panda_link0")
        assert not sim.is_prim_path_valid("/World/Franka/no_such_link")
        assert not sim.is_prim_path_valid("/World/Frankaa/panda_hand")
        world.reset()
    assert sim.RigidPrim("/World/Franka/panda_hand").get_mass() > 0
    world.scene.remove_object("franka")
    assert not sim.is_prim_path_valid("/World/Franka/panda_hand") and franka.prim_path == "/World/Franka"
