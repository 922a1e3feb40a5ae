"""manip.sim: a MuJoCo world with the names and behaviour of Isaac Sim's core API.

An Isaac Sim tutorial script ports by changing its imports::

    from manip.sim import World, DynamicCuboid
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid(prim_path="/World/cube", name="cube", position=[0, 0, 1.0],
                                         size=0.05))
    world.reset()
    for _ in range(100):
        world.step(render=False)
    print(cube.get_world_pose())

Every `omni.isaac.core...`, `omni.isaac.wheeled_robots...`, `omni.isaac.franka...`,
`omni.isaac.examples...`, `omni.isaac.kit` and `isaacsim...` name a tutorial imports becomes
`from manip.sim import NAME`; `import carb` becomes `from manip.sim import carb` (the README's
"Porting a tutorial" has the table). Isaac asset paths such as
`get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"` load the bundled models
(`manip.sim.assets`). Quaternions are (w, x, y, z); units are SI. See `manip.sim.simulation_context` for time
stepping, `manip.sim.articulation` for the drives, `manip.sim.recording` for offscreen video.
Importing this package changes no environment variable: the offscreen GL backend is
chosen at the first render (`manip.sim.gl_backend`).
"""

from __future__ import annotations

from manip.articulation_action import ArticulationAction
from manip.sim import carb
from manip.sim.app import SimulationApp
from manip.sim.articulation import DOF_PROPERTIES_DTYPE, Articulation, ArticulationController, Robot, SingleArticulation
from manip.sim.articulation_view import ArticulationView
from manip.sim.assets import ISAAC_ASSETS, available_assets, resolve_asset_path
from manip.sim.objects import (
    DynamicCapsule,
    DynamicCone,
    DynamicCuboid,
    DynamicCylinder,
    DynamicSphere,
    FixedCapsule,
    FixedCone,
    FixedCuboid,
    FixedCylinder,
    FixedSphere,
    GeometryPrim,
    GroundPlane,
    PhysicsMaterial,
    RigidPrim,
    VisualCapsule,
    VisualCone,
    VisualCuboid,
    VisualCylinder,
    VisualSphere,
    XFormPrim,
)
from manip.sim.recording import CameraView, OffscreenRenderingError
from manip.sim.rotations import (
    euler_angles_to_quat,
    euler_angles_to_rot_matrix,
    quat_to_euler_angles,
    quat_to_rot_matrix,
    rot_matrix_to_euler_angles,
    rot_matrix_to_quat,
)
from manip.sim.scene import CollisionObject, Scene
from manip.sim.simulation_context import SimulationContext, SimulationInstabilityError, SimulationWarning
from manip.sim.stage import (
    SimulationError,
    add_reference_to_stage,
    create_new_stage,
    create_new_stage_async,
    get_assets_root_path,
    get_current_stage,
    is_prim_path_valid,
    update_stage,
    update_stage_async,
)
from manip.sim.types import DynamicState, JointsState, XFormPrimState
from manip.sim.world import World, clear_stage

SingleXFormPrim = XFormPrim
SingleRigidPrim = RigidPrim
SingleGeometryPrim = GeometryPrim
from manip.sim.controllers import BaseController, DifferentialController, WheelBasePoseController
from manip.sim.pick_place_controller import PickPlaceController
from manip.sim.manipulator import SingleManipulator
from manip.sim.robots import (
    Franka,
    ParallelGripper,
    WheeledRobot,
    franka_model_path,
    jetbot_model_path,
    robot_model_path,
)
from manip.sim.sample import BaseSample
from manip.sim.extension import BaseSampleExtension
from manip.sim.hello_world import HelloWorld
from manip.sim.tasks import BaseTask, PickPlace, find_unique_string_name
from manip.sim.views import RigidPrimView, XFormPrimView
from manip.sim.follow_target import FollowTarget
from manip.sim.rmpflow import RMPFlowController

__all__ = [name for name in dir() if not name.startswith("_")]
