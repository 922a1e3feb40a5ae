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
`omni.isaac.examples...`, `omni.isaac.motion_generation...`, `omni.isaac.kit` and `isaacsim...`
name a tutorial imports becomes `from manip.sim import NAME` (`interface_config_loader`, a
module in Isaac, too); `import carb` becomes `from manip.sim import carb` (the README's
"Porting a tutorial" has the table). Isaac asset paths such as
`get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"` load the bundled models
(`manip.sim.assets`). Quaternions are (w, x, y, z); units are SI.

Layout, grouped as Isaac groups its API: `core/` (SimulationApp, SimulationContext, World,
callbacks, carb, rendering), `scenes/` (Scene, the stage and the MJCF it compiles to),
`prims/` (XFormPrim, RigidPrim, GeometryPrim, views), `objects/` (the shapes, the ground
plane), `articulations/` (Articulation and its view, the compiled core), `robots/` (Robot
wrappers, Franka, WheeledRobot, SingleManipulator), `controllers/`, `tasks/`, `samples/`
(BaseSample, its extension, HelloWorld), `utils/` (types, rotations), `motion_generation/`
(LulaKinematicsSolver, ArticulationKinematicsSolver, RmpFlow, ArticulationMotionPolicy); beside them
`assets` (Isaac's asset paths) and `playback` (a planned trajectory played in the World).
See `manip.sim.core.simulation_context` for time stepping, `manip.sim.articulations.articulation`
for the drives, `manip.sim.core.recording` for offscreen video.
Importing this package changes no environment variable: the offscreen GL backend is
chosen at the first render (`manip.sim.core.gl_backend`).
"""

from __future__ import annotations

from manip.articulation_action import ArticulationAction
from manip.sim.core.carb_logging import carb
from manip.sim.core.app import SimulationApp
from manip.sim.articulations.articulation import DOF_PROPERTIES_DTYPE, Articulation, ArticulationController, Robot, SingleArticulation
from manip.sim.articulations.articulation_view import ArticulationView
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
from manip.sim.materials import OmniGlass, OmniPBR, PreviewSurface, VisualMaterial
from manip.sim.core.recording import CameraView, OffscreenRenderingError
from manip.sim.sensors.camera import Camera
from manip.sim.utils.rotations import (
    deg2rad,
    euler_angles_to_quat,
    euler_angles_to_quats,
    euler_angles_to_rot_matrix,
    quat_to_euler_angles,
    quat_to_rot_matrix,
    quats_to_euler_angles,
    quats_to_rot_matrices,
    quats_to_rotvecs,
    rad2deg,
    rot_matrices_to_quats,
    rot_matrix_to_euler_angles,
    rot_matrix_to_quat,
    rotvecs_to_quats,
    wxyz2xyzw,
    xyzw2wxyz,
)
from manip.sim.scenes.scene import CollisionObject, Scene
from manip.sim.core.physics_context import PhysicsContext
from manip.sim.core.simulation_context import SimulationContext, SimulationInstabilityError, SimulationWarning
from manip.sim.scenes.stage import (
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
from manip.sim.utils.types import (
    ArticulationActions,
    DynamicState,
    DynamicsViewState,
    JointsState,
    XFormPrimState,
    XFormPrimViewState,
)
from manip.sim.utils.prims import (
    create_prim,
    delete_prim,
    euler_to_rot_matrix,
    find_matching_prim_paths,
    get_prim_at_path,
    get_stage_units,
    gf_quat_to_np_array,
    is_stage_loading,
    open_stage,
    save_stage,
)
from manip.sim.utils.semantics import add_update_semantics, get_semantics, remove_all_semantics
from manip.sim.utils.prim_bounds import BBoxCache, compute_aabb, compute_combined_aabb, create_bbox_cache
from manip.sim.utils.prim_tree import (
    define_prim,
    get_all_matching_child_prims,
    get_first_matching_child_prim,
    get_local_pose,
    get_prim_children,
    get_prim_object_type,
    get_prim_parent,
    get_prim_path,
    get_prim_type_name,
    get_world_pose,
)
from manip.sim.core.world import World, clear_stage
from manip.sim.utils.extensions import disable_extension, enable_extension
from manip.sim.utils.viewports import set_camera_view
from manip.sim.utils.transformations import (
    get_relative_transform,
    get_transform_with_normalized_rotation,
    get_translation_from_target,
    get_world_pose_from_relative,
    pose_from_tf_matrix,
    tf_matrices_from_poses,
    tf_matrix_from_pose,
)
from manip.sim.utils.distance_metrics import (
    rotational_distance_angle,
    rotational_distance_identity_matrix_deviation,
    rotational_distance_single_axis,
    weighted_translational_distance,
)

SingleXFormPrim = XFormPrim
SingleRigidPrim = RigidPrim
SingleGeometryPrim = GeometryPrim
from manip.sim.controllers.base_controller import BaseController, DifferentialController, WheelBasePoseController
from manip.sim.controllers.pick_place_controller import PickPlaceController
from manip.sim.robots.manipulator import SingleManipulator
from manip.sim.robots.surface_gripper import SurfaceGripper
from manip.sim.robots.robot import (
    Franka,
    ParallelGripper,
    WheeledRobot,
    franka_model_path,
    jetbot_model_path,
    robot_model_path,
)
from manip.sim.samples.base_sample import BaseSample
from manip.sim.samples.extension import BaseSampleExtension
from manip.sim.samples.hello_world import HelloWorld, HelloWorldExtension
from manip.sim.tasks.base_task import BaseTask, PickPlace, find_unique_string_name
from manip.sim.prims.views import RigidPrimView, XFormPrimView
from manip.sim.prims.geometry_view import GeometryPrimView
from manip.sim.tasks.follow_target import FollowTarget
from manip.sim.tasks.stacking import Stacking
from manip.sim.controllers.stacking_controller import StackingController
from manip.sim.controllers.rmpflow import RMPFlowController
from manip.sim.motion_generation import (
    ArticulationKinematicsSolver,
    ArticulationMotionPolicy,
    ArticulationSubset,
    KinematicsSolver,
    LulaKinematicsSolver,
    MotionPolicyController,
    RmpFlow,
    get_extension_path_from_name,
    interface_config_loader,
)

#: Every name a ported Isaac script imports (no submodules: `from manip.sim import *` binds names only).
__all__ = [
    "Articulation", "ArticulationAction", "ArticulationActions", "ArticulationController", "ArticulationKinematicsSolver",
    "ArticulationMotionPolicy", "ArticulationSubset", "ArticulationView", "BaseController",
    "BaseSample", "BaseSampleExtension", "BaseTask", "Camera", "CameraView", "CollisionObject", "DOF_PROPERTIES_DTYPE",
    "DifferentialController", "DynamicCapsule", "DynamicCone", "DynamicCuboid", "DynamicCylinder", "DynamicSphere",
    "DynamicState", "DynamicsViewState", "FixedCapsule", "FixedCone", "FixedCuboid", "FixedCylinder",
    "FixedSphere", "FollowTarget", "Franka", "GeometryPrim", "GeometryPrimView", "GroundPlane", "HelloWorld", "HelloWorldExtension",
    "ISAAC_ASSETS", "JointsState", "KinematicsSolver", "LulaKinematicsSolver", "MotionPolicyController", "OffscreenRenderingError", "OmniGlass", "OmniPBR",
    "ParallelGripper", "PhysicsContext",
    "PhysicsMaterial", "PickPlace", "PickPlaceController", "PreviewSurface", "RMPFlowController", "RigidPrim",
    "RigidPrimView", "RmpFlow", "Robot", "Scene", "SimulationApp", "SimulationContext", "SimulationError",
    "SimulationInstabilityError", "SimulationWarning", "SingleArticulation", "SingleGeometryPrim",
    "SingleManipulator", "SingleRigidPrim", "SingleXFormPrim", "Stacking", "StackingController", "SurfaceGripper",
    "VisualCapsule",
    "VisualCone", "VisualCuboid",
    "VisualCylinder", "VisualMaterial", "VisualSphere", "WheelBasePoseController", "WheeledRobot", "World",
    "XFormPrim", "XFormPrimState", "XFormPrimView", "XFormPrimViewState", "add_reference_to_stage",
    "available_assets", "carb", "clear_stage", "create_new_stage", "create_new_stage_async", "create_prim",
    "delete_prim", "disable_extension", "enable_extension", "euler_angles_to_quat", "euler_angles_to_rot_matrix", "euler_to_rot_matrix",
    "find_matching_prim_paths", "find_unique_string_name", "franka_model_path", "get_assets_root_path",
    "get_current_stage", "get_extension_path_from_name", "get_prim_at_path", "get_stage_units",
    "define_prim", "get_all_matching_child_prims", "get_first_matching_child_prim", "get_local_pose",
    "get_prim_children", "get_prim_object_type", "get_prim_parent", "get_prim_path", "get_prim_type_name",
    "get_world_pose", "BBoxCache", "compute_aabb", "compute_combined_aabb", "create_bbox_cache", "gf_quat_to_np_array", "is_prim_path_valid",
    "is_stage_loading", "jetbot_model_path", "open_stage", "quat_to_euler_angles", "quat_to_rot_matrix",
    "resolve_asset_path", "robot_model_path", "rot_matrix_to_euler_angles", "rot_matrix_to_quat", "save_stage",
    "set_camera_view",
    "update_stage", "update_stage_async",
    # omni.isaac.core.utils.transformations and .distance_metrics
    "get_relative_transform", "get_transform_with_normalized_rotation", "get_translation_from_target",
    "get_world_pose_from_relative", "pose_from_tf_matrix", "tf_matrices_from_poses", "tf_matrix_from_pose",
    "rotational_distance_angle", "rotational_distance_identity_matrix_deviation", "rotational_distance_single_axis",
    "weighted_translational_distance",
    # omni.isaac.core.utils.semantics
    "add_update_semantics", "get_semantics", "remove_all_semantics",
    # isaacsim.core.utils.numpy.rotations (batched)
    "deg2rad", "euler_angles_to_quats", "quats_to_euler_angles", "quats_to_rot_matrices", "quats_to_rotvecs",
    "rad2deg", "rot_matrices_to_quats", "rotvecs_to_quats", "wxyz2xyzw", "xyzw2wxyz",
]
