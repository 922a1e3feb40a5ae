"""The Isaac Sim 4.x core-API members a tutorial user touches, class by class, and what
manip.sim does with each (data only; `manip.sim.coverage` renders the table in
docs/isaac_coverage.md and tests/sim/test_coverage.py keeps it true).

`ISAAC_API`: manip class name -> (Isaac's class, its documented public methods and
properties). `NOT_SUPPORTED`: members that raise NotImplementedError naming themselves and
why (installed by `manip.sim.utils.not_supported.declare`). `DIFFERS`: members implemented
with a difference a script may notice. Everything else listed is implemented as Isaac's.
"""

from __future__ import annotations

_XFORM = ("apply_visual_material", "get_applied_visual_material", "get_default_state", "get_local_pose",
          "get_local_scale", "get_visibility", "get_world_pose", "get_world_scale", "initialize", "is_valid",
          "is_visual_material_applied", "name", "post_reset", "prim", "prim_path", "set_default_state",
          "set_local_pose", "set_local_scale", "set_visibility", "set_world_pose")
_GEOMETRY = _XFORM + ("apply_physics_material", "get_applied_physics_material", "get_collision_approximation",
                      "set_collision_approximation", "get_collision_enabled", "set_collision_enabled",
                      "get_contact_offset", "set_contact_offset", "get_rest_offset", "set_rest_offset",
                      "get_torsional_patch_radius", "set_torsional_patch_radius")
_RIGID = _XFORM + ("get_linear_velocity", "set_linear_velocity", "get_angular_velocity", "set_angular_velocity",
                   "get_mass", "set_mass", "get_density", "set_density", "get_current_dynamic_state",
                   "enable_rigid_body_physics", "disable_rigid_body_physics", "set_sleep_threshold",
                   "get_sleep_threshold", "get_com", "set_com")
_XFORM_VIEW = ("apply_visual_materials", "get_applied_visual_materials", "get_default_state", "get_local_poses",
               "get_local_scales", "get_visibilities", "get_world_poses", "get_world_scales", "initialize",
               "is_valid", "post_reset", "set_default_state", "set_local_poses", "set_local_scales",
               "set_visibilities", "set_world_poses", "count", "prim_paths", "name", "prims")
_RIGID_VIEW = _XFORM_VIEW + (
    "apply_forces", "apply_forces_and_torques_at_pos", "disable_gravities", "enable_gravities",
    "get_angular_velocities", "get_linear_velocities", "get_velocities", "set_angular_velocities",
    "set_linear_velocities", "set_velocities", "get_masses", "set_masses", "get_densities", "set_densities",
    "get_coms", "set_coms", "get_inertias", "set_inertias", "get_inv_masses", "get_inv_inertias",
    "get_contact_force_matrix", "get_net_contact_forces", "get_contact_force_data", "get_friction_data",
    "get_current_dynamic_state", "get_sleep_thresholds", "set_sleep_thresholds", "num_shapes",
    "num_contact_filters", "enable_rigid_body_physics", "disable_rigid_body_physics")
_SIMULATION_CONTEXT = (
    "add_physics_callback", "add_render_callback", "add_stage_callback", "add_timeline_callback",
    "clear_all_callbacks", "clear_instance", "current_time", "current_time_step_index", "get_physics_context",
    "get_physics_dt", "get_rendering_dt", "initialize_physics", "initialize_simulation_context_async", "instance",
    "is_playing", "is_simulating", "is_stopped", "pause", "pause_async", "physics_callback_exists",
    "physics_sim_view", "play", "play_async", "remove_physics_callback", "remove_render_callback",
    "remove_stage_callback", "remove_timeline_callback", "render", "render_async", "reset", "reset_async",
    "set_camera_view", "set_simulation_dt", "stage", "step", "stop", "stop_async", "stage_callback_exists",
    "timeline_callback_exists", "get_block_on_render", "set_block_on_render", "app", "backend", "device",
    "clear_physics_callbacks", "clear_render_callbacks", "clear_stage_callbacks", "clear_timeline_callbacks",
    "render_callback_exists")
_ARTICULATION = (
    "apply_action", "disable_gravity", "enable_gravity", "dof_names", "dof_properties", "get_angular_velocity",
    "get_applied_action", "get_applied_joint_efforts", "get_articulation_body_count", "get_articulation_controller",
    "get_dof_index", "get_enabled_self_collisions", "set_enabled_self_collisions", "get_joint_positions",
    "get_joint_velocities", "get_joints_default_state", "get_joints_state", "get_linear_velocity",
    "get_measured_joint_efforts", "get_measured_joint_forces", "get_sleep_threshold", "set_sleep_threshold",
    "get_solver_position_iteration_count", "set_solver_position_iteration_count",
    "get_solver_velocity_iteration_count", "set_solver_velocity_iteration_count", "get_stabilization_threshold",
    "set_stabilization_threshold", "get_world_pose", "set_world_pose", "get_local_pose", "set_local_pose",
    "handles_initialized", "initialize", "num_bodies", "num_dof", "post_reset", "set_angular_velocity",
    "set_linear_velocity", "set_joint_efforts", "set_joint_positions", "set_joint_velocities",
    "set_joints_default_state", "get_default_state", "set_default_state", "name", "prim_path", "prim", "is_valid",
    "get_world_velocity", "set_world_velocity")
_WORLD_INTERFACE = ("update_world", "add_obstacle", "add_cuboid", "add_sphere", "add_capsule", "add_cylinder",
                    "add_cone", "add_ground_plane", "disable_obstacle", "enable_obstacle", "remove_obstacle", "reset")

ISAAC_API: dict[str, tuple[str, tuple[str, ...]]] = {
    "SimulationApp": ("omni.isaac.kit.SimulationApp", (
        "close", "is_exiting", "is_running", "update", "set_setting", "reset_render_settings", "run_coroutine",
        "app", "context")),
    "SimulationContext": ("omni.isaac.core.simulation_context.SimulationContext", _SIMULATION_CONTEXT),
    "World": ("omni.isaac.core.world.World", _SIMULATION_CONTEXT + (
        "scene", "add_task", "get_task", "get_current_tasks", "get_observations", "calculate_metrics", "is_done",
        "is_tasks_scene_built", "reset_async_set_up_scene", "reset_async_no_set_up_scene", "step_async", "clear",
        "get_data_logger")),
    "PhysicsContext": ("omni.isaac.core.physics_context.PhysicsContext", (
        "prim_path", "device", "use_gpu_sim", "use_gpu_pipeline", "use_fabric", "get_current_physics_scene_prim",
        "warm_start", "set_physics_dt", "get_physics_dt", "enable_fabric", "enable_ccd", "is_ccd_enabled",
        "enable_stablization", "is_stablization_enabled", "enable_gpu_dynamics", "is_gpu_dynamics_enabled",
        "set_broadphase_type", "get_broadphase_type", "set_solver_type", "get_solver_type", "set_gravity",
        "get_gravity", "set_physx_update_transformations_settings", "get_physx_update_transformations_settings",
        "set_invert_collision_group_filter", "get_invert_collision_group_filter", "set_bounce_threshold",
        "get_bounce_threshold", "set_friction_offset_threshold", "get_friction_offset_threshold",
        "set_friction_correlation_distance", "get_friction_correlation_distance", "set_enable_scene_query_support",
        "get_enable_scene_query_support", "set_gpu_max_rigid_contact_count", "get_gpu_max_rigid_contact_count",
        "set_gpu_max_rigid_patch_count", "get_gpu_max_rigid_patch_count", "set_gpu_found_lost_pairs_capacity",
        "get_gpu_found_lost_pairs_capacity", "set_gpu_found_lost_aggregate_pairs_capacity",
        "get_gpu_found_lost_aggregate_pairs_capacity", "set_gpu_total_aggregate_pairs_capacity",
        "get_gpu_total_aggregate_pairs_capacity", "set_gpu_max_soft_body_contacts", "get_gpu_max_soft_body_contacts",
        "set_gpu_max_particle_contacts", "get_gpu_max_particle_contacts", "set_gpu_heap_capacity",
        "get_gpu_heap_capacity", "set_gpu_temp_buffer_capacity", "get_gpu_temp_buffer_capacity",
        "set_gpu_max_num_partitions", "get_gpu_max_num_partitions", "set_gpu_collision_stack_size",
        "get_gpu_collision_stack_size", "enable_stabilization", "set_solve_articulation_contact_last",
        "get_solve_articulation_contact_last")),
    "Camera": ("omni.isaac.sensor.Camera", (
        "distort_point_rational_polynomial", "distort_point_kannala_brandt2", "supported_annotators",
        "get_render_product_path", "set_frequency", "get_frequency", "set_dt", "get_dt", "get_current_frame",
        "initialize", "post_reset", "resume", "pause", "is_paused", "set_resolution", "get_resolution",
        "get_aspect_ratio", "get_world_pose", "set_world_pose", "get_local_pose", "set_local_pose",
        "add_normals_to_frame", "remove_normals_from_frame", "add_motion_vectors_to_frame",
        "remove_motion_vectors_from_frame", "add_occlusion_to_frame", "remove_occlusion_from_frame",
        "add_distance_to_image_plane_to_frame", "remove_distance_to_image_plane_from_frame",
        "add_distance_to_camera_to_frame", "remove_distance_to_camera_from_frame",
        "add_bounding_box_2d_tight_to_frame", "remove_bounding_box_2d_tight_from_frame",
        "add_bounding_box_2d_loose_to_frame", "remove_bounding_box_2d_loose_from_frame",
        "add_bounding_box_3d_to_frame", "remove_bounding_box_3d_from_frame", "add_semantic_segmentation_to_frame",
        "remove_semantic_segmentation_from_frame", "add_instance_id_segmentation_to_frame",
        "remove_instance_id_segmentation_from_frame", "add_instance_segmentation_to_frame",
        "remove_instance_segmentation_from_frame", "add_pointcloud_to_frame", "remove_pointcloud_from_frame",
        "get_rgba", "get_rgb", "get_depth", "get_pointcloud", "get_focal_length", "set_focal_length",
        "get_focus_distance", "set_focus_distance", "get_lens_aperture", "set_lens_aperture",
        "get_horizontal_aperture", "set_horizontal_aperture", "get_vertical_aperture", "set_vertical_aperture",
        "get_clipping_range", "set_clipping_range", "get_projection_type", "set_projection_type",
        "get_projection_mode", "set_projection_mode", "get_stereo_role", "set_stereo_role",
        "set_fisheye_polynomial_properties", "set_matching_fisheye_polynomial_properties",
        "set_rational_polynomial_properties", "set_kannala_brandt_properties", "get_fisheye_polynomial_properties",
        "set_shutter_properties", "get_shutter_properties", "get_view_matrix_ros", "get_intrinsics_matrix",
        "get_image_coords_from_world_points", "get_world_points_from_image_coords", "get_horizontal_fov",
        "get_vertical_fov")),
    "Scene": ("omni.isaac.core.scenes.Scene", (
        "add", "add_default_ground_plane", "add_ground_plane", "clear", "compute_object_AABB",
        "enable_bounding_boxes_computations", "disable_bounding_boxes_computations", "get_object", "object_exists",
        "post_reset", "remove_object", "stage")),
    "XFormPrim": ("omni.isaac.core.prims.XFormPrim", _XFORM),
    "GeometryPrim": ("omni.isaac.core.prims.GeometryPrim", _GEOMETRY),
    "RigidPrim": ("omni.isaac.core.prims.RigidPrim", _RIGID),
    "XFormPrimView": ("omni.isaac.core.prims.XFormPrimView", _XFORM_VIEW),
    "GeometryPrimView": ("omni.isaac.core.prims.GeometryPrimView", _XFORM_VIEW + (
        "is_collision_enabled", "enable_collision", "disable_collision", "apply_collision_apis",
        "set_collision_approximations", "get_collision_approximations", "apply_physics_materials",
        "get_applied_physics_materials", "set_contact_offsets", "get_contact_offsets", "set_rest_offsets",
        "get_rest_offsets", "set_torsional_patch_radii", "get_torsional_patch_radii", "set_min_torsional_patch_radii",
        "get_min_torsional_patch_radii", "get_net_contact_forces", "get_contact_force_matrix")),
    "RigidPrimView": ("omni.isaac.core.prims.RigidPrimView", _RIGID_VIEW),
    "DynamicCuboid": ("omni.isaac.core.objects.DynamicCuboid", _RIGID + _GEOMETRY[len(_XFORM):] + ("get_size",
                                                                                                   "set_size")),
    "FixedCuboid": ("omni.isaac.core.objects.FixedCuboid", _GEOMETRY + ("get_size", "set_size")),
    "VisualCuboid": ("omni.isaac.core.objects.VisualCuboid", _GEOMETRY + ("get_size", "set_size")),
    "DynamicSphere": ("omni.isaac.core.objects.DynamicSphere", _RIGID + ("get_radius", "set_radius")),
    "DynamicCylinder": ("omni.isaac.core.objects.DynamicCylinder", _RIGID + ("get_radius", "set_radius",
                                                                            "get_height", "set_height")),
    "GroundPlane": ("omni.isaac.core.objects.GroundPlane", (
        "apply_physics_material", "get_applied_physics_material", "get_default_state", "get_world_pose",
        "initialize", "name", "post_reset", "prim_path", "set_default_state")),
    "PhysicsMaterial": ("omni.isaac.core.materials.PhysicsMaterial", (
        "get_dynamic_friction", "get_restitution", "get_static_friction", "set_dynamic_friction", "set_restitution",
        "set_static_friction", "name", "prim_path")),
    "PreviewSurface": ("omni.isaac.core.materials.PreviewSurface", (
        "get_color", "set_color", "get_metallic", "set_metallic", "get_roughness", "set_roughness", "name",
        "prim_path", "material", "shaders_list")),
    "OmniPBR": ("omni.isaac.core.materials.OmniPBR", (
        "get_color", "set_color", "get_metallic_constant", "set_metallic_constant", "get_reflection_roughness",
        "set_reflection_roughness", "get_texture", "set_texture", "get_texture_scale", "set_texture_scale",
        "get_texture_translate", "set_texture_translate", "get_project_uvw", "set_project_uvw")),
    "Articulation": ("omni.isaac.core.articulations.Articulation", _ARTICULATION),
    "Robot": ("omni.isaac.core.robots.Robot", _ARTICULATION + ("get_sensors",)),
    "Franka": ("omni.isaac.franka.Franka", _ARTICULATION + ("end_effector", "gripper")),
    "ArticulationView": ("omni.isaac.core.articulations.ArticulationView", (
        "apply_action", "count", "num_dof", "num_bodies", "num_joints", "dof_names", "body_names", "prim_paths",
        "get_applied_actions", "get_applied_joint_efforts", "get_measured_joint_efforts", "get_measured_joint_forces",
        "get_body_coms", "get_body_inertias", "get_body_masses", "get_body_index", "get_dof_index", "get_dof_limits",
        "get_dof_types", "get_effort_modes", "get_enabled_self_collisions", "get_friction_coefficients",
        "get_gains", "set_gains", "get_generalized_gravity_forces", "get_coriolis_and_centrifugal_forces",
        "get_jacobian_shape", "get_jacobians", "get_mass_matrices", "get_mass_matrix_shape", "get_joint_positions",
        "get_joint_velocities", "get_joints_default_state", "set_joints_default_state", "get_joints_state",
        "get_max_efforts", "set_max_efforts", "get_joint_max_velocities", "get_velocities",
        "get_linear_velocities", "get_angular_velocities", "get_world_poses", "set_world_poses", "get_local_poses",
        "set_joint_efforts", "set_joint_positions", "set_joint_position_targets", "set_joint_velocities",
        "set_joint_velocity_targets", "set_velocities", "switch_control_mode", "switch_dof_control_mode",
        "initialize", "is_physics_handle_valid", "post_reset", "name")),
    "ArticulationController": ("omni.isaac.core.controllers.ArticulationController", (
        "apply_action", "get_applied_action", "get_gains", "set_gains", "get_joint_limits", "get_max_efforts",
        "set_max_efforts", "initialize", "switch_control_mode", "switch_dof_control_mode", "get_effort_modes",
        "set_effort_modes")),
    "ParallelGripper": ("omni.isaac.manipulators.grippers.ParallelGripper", (
        "apply_action", "close", "open", "forward", "initialize", "post_reset", "get_default_state",
        "set_default_state", "get_joint_positions", "set_joint_positions", "joint_opened_positions",
        "joint_closed_positions", "joint_dof_indicies", "get_action_deltas", "set_action_deltas", "is_closed")),
    "SurfaceGripper": ("omni.isaac.manipulators.grippers.SurfaceGripper", (
        "initialize", "close", "open", "update", "is_closed", "set_translate", "set_direction", "set_force_limit",
        "set_torque_limit", "set_default_state", "get_default_state", "post_reset", "forward", "apply_action")),
    "PickPlaceController": ("omni.isaac.franka.controllers.PickPlaceController", (
        "forward", "get_current_event", "is_done", "is_paused", "pause", "reset", "resume")),
    "RMPFlowController": ("omni.isaac.franka.controllers.RMPFlowController", (
        "add_obstacle", "forward", "get_articulation_motion_policy", "get_motion_policy", "name", "remove_obstacle",
        "reset")),
    "Stacking": ("omni.isaac.franka.tasks.Stacking", (
        "calculate_metrics", "cleanup", "get_cube_names", "get_observations", "get_params", "get_task_objects",
        "is_done", "name", "post_reset", "pre_step", "scene", "set_params", "set_robot", "set_up_scene")),
    "StackingController": ("omni.isaac.franka.controllers.StackingController", (
        "forward", "is_done", "name", "reset")),
    "RmpFlow": ("omni.isaac.motion_generation.lula.RmpFlow", _WORLD_INTERFACE + (
        "set_robot_base_pose", "compute_joint_targets", "get_active_joints", "get_watched_joints",
        "set_end_effector_target", "set_cspace_target", "set_ignore_state_updates", "set_internal_robot_joint_states",
        "get_internal_robot_joint_states", "get_default_cspace_position_target", "get_end_effector_pose",
        "get_kinematics_solver", "visualize_collision_spheres", "stop_visualizing_collision_spheres",
        "get_collision_spheres_as_prims", "delete_collision_sphere_prims", "visualize_end_effector_position",
        "stop_visualizing_end_effector", "get_end_effector_as_prim", "delete_end_effector_prim")),
    "ArticulationMotionPolicy": ("omni.isaac.motion_generation.ArticulationMotionPolicy", (
        "move", "get_next_articulation_action", "get_active_joints_subset", "get_watched_joints_subset",
        "get_robot_articulation", "get_motion_policy", "get_default_physics_dt", "set_default_physics_dt")),
    "MotionPolicyController": ("omni.isaac.motion_generation.MotionPolicyController", (
        "forward", "add_obstacle", "remove_obstacle", "reset", "get_articulation_motion_policy", "get_motion_policy",
        "name")),
    "BaseTask": ("omni.isaac.core.tasks.BaseTask", (
        "calculate_metrics", "cleanup", "get_description", "get_observations", "get_params", "get_task_objects",
        "is_done", "name", "post_reset", "pre_step", "scene", "set_params", "set_up_scene")),
    "PickPlace": ("omni.isaac.franka.tasks.PickPlace", (
        "calculate_metrics", "get_observations", "get_params", "is_done", "post_reset", "pre_step", "set_params",
        "set_robot", "set_up_scene")),
}

#: Isaac members manip.sim cannot provide: calling one raises NotImplementedError with the reason.
NOT_SUPPORTED: dict[str, dict[str, str]] = {
    "Camera": {
        **{name: "MuJoCo renders pinhole cameras only (no lens distortion models)" for name in (
            "distort_point_rational_polynomial", "distort_point_kannala_brandt2", "set_fisheye_polynomial_properties",
            "set_matching_fisheye_polynomial_properties", "set_rational_polynomial_properties",
            "set_kannala_brandt_properties", "get_fisheye_polynomial_properties")},
        **{f"{verb}_{annotator}_{where}_frame": "not computed here: the semantic_segmentation and "
           "instance_id_segmentation annotators give each pixel's label and prim (labels: add_update_semantics)"
           for verb, where in (("add", "to"), ("remove", "from")) for annotator in (
               "occlusion", "bounding_box_2d_tight", "bounding_box_2d_loose", "bounding_box_3d",
               "instance_segmentation")},
        "set_shutter_properties": "rendering is instantaneous (no rolling shutter)",
        "get_shutter_properties": "rendering is instantaneous (no rolling shutter)",
        "get_render_product_path": "there are no Replicator render products: every getter renders the current state",
    },
    "PhysicsContext": {
        "get_current_physics_scene_prim": "there is no USD physics scene prim: the solver options are World.model.opt",
        "set_physx_update_transformations_settings": "there is no USD/Fabric write-back: poses are read from MuJoCo",
        "get_physx_update_transformations_settings": "there is no USD/Fabric write-back: poses are read from MuJoCo",
    },
    "SimulationApp": {
        "reset_render_settings": "manip has no RTX renderer settings",
        "run_coroutine": "there is no Kit event loop: use asyncio.run(...), or asyncio.ensure_future, run at the "
                         "next world.step() / simulation_app.update()",
        "context": "there is no Kit USD context (manip has no USD)",
    },
    "SimulationContext": {
        "get_block_on_render": "rendering is synchronous here",
        "set_block_on_render": "rendering is synchronous here",
        "app": "there is no Kit app object (use manip.sim.SimulationApp)",
        "backend": "one backend: NumPy on the CPU",
        "device": "one device: the CPU",
    },
    "XFormPrim": {
        "apply_visual_material": "a bare transform has no geometry to colour here: apply materials to shapes",
        "get_applied_visual_material": "a bare transform has no geometry to colour here: shapes carry materials",
        "is_visual_material_applied": "a bare transform has no geometry to colour here: shapes carry materials",
    },
    "GeometryPrim": {
        "get_contact_offset": "PhysX contact offsets do not exist in MuJoCo (contacts: manip.sim.scenes.contact_model)",
        "set_contact_offset": "PhysX contact offsets do not exist in MuJoCo (contacts: manip.sim.scenes.contact_model)",
        "get_rest_offset": "PhysX rest offsets do not exist in MuJoCo",
        "set_rest_offset": "PhysX rest offsets do not exist in MuJoCo",
        "get_torsional_patch_radius": "MuJoCo models torsional friction by a coefficient, not a patch radius",
        "set_torsional_patch_radius": "MuJoCo models torsional friction by a coefficient, not a patch radius",
    },
    "GeometryPrimView": {
        "set_contact_offsets": "PhysX contact offsets do not exist in MuJoCo (contacts: manip.sim.scenes.contact_model)",
        "get_contact_offsets": "PhysX contact offsets do not exist in MuJoCo (contacts: manip.sim.scenes.contact_model)",
        "set_rest_offsets": "PhysX rest offsets do not exist in MuJoCo",
        "get_rest_offsets": "PhysX rest offsets do not exist in MuJoCo",
        "set_torsional_patch_radii": "MuJoCo models torsional friction by a coefficient, not a patch radius",
        "get_torsional_patch_radii": "MuJoCo models torsional friction by a coefficient, not a patch radius",
        "set_min_torsional_patch_radii": "MuJoCo models torsional friction by a coefficient, not a patch radius",
        "get_min_torsional_patch_radii": "MuJoCo models torsional friction by a coefficient, not a patch radius",
        "get_net_contact_forces": "read contact forces with RigidPrimView(prim_paths_expr, "
                                  "contact_filter_prim_paths_expr=...)",
        "get_contact_force_matrix": "read contact forces with RigidPrimView(prim_paths_expr, "
                                    "contact_filter_prim_paths_expr=...)",
    },
    "RigidPrim": {
        "enable_rigid_body_physics": "a body's kind is fixed when the World compiles: make a Dynamic or Fixed object",
        "disable_rigid_body_physics": "a body's kind is fixed when the World compiles: make a Dynamic or Fixed object",
        "set_com": "the centre of mass follows the shape (MuJoCo computes it when the World compiles)",
    },
    "XFormPrimView": {
        "apply_visual_materials": "apply a material to each object (GeometryPrim.apply_visual_material)",
        "get_applied_visual_materials": "read each object's material (GeometryPrim.get_applied_visual_material)",
        "set_local_scales": "a scale is fixed when the World compiles: set it on each object before a reset",
    },
    "RigidPrimView": {
        "set_densities": "set each object's density before the World compiles",
        "set_coms": "the centre of mass follows the shape (MuJoCo computes it when the World compiles)",
        "set_inertias": "the inertia follows the shape (MuJoCo computes it when the World compiles)",
        "get_contact_force_data": "per-contact PhysX data: use get_contact_force_matrix / get_net_contact_forces",
        "get_friction_data": "per-contact PhysX data: use get_contact_force_matrix / get_net_contact_forces",
        "num_shapes": "one geom per object here",
        "enable_rigid_body_physics": "a body's kind is fixed when the World compiles",
        "disable_rigid_body_physics": "a body's kind is fixed when the World compiles",
    },
    "Articulation": {
        "get_measured_joint_forces": "PhysX joint-frame 6-D forces: use get_measured_joint_efforts",
    },
    "Robot": {"get_sensors": "sensors are not attached to robots here (cameras: manip.sim sensors)"},
    "ArticulationView": {
        "get_measured_joint_forces": "PhysX joint-frame 6-D forces: use get_measured_joint_efforts",
        "get_body_coms": "read World.model.body_ipos (MuJoCo) for the bodies",
        "get_body_inertias": "read World.model.body_inertia (MuJoCo) for the bodies",
        "get_effort_modes": "effort limits are always force limits here",
        "get_friction_coefficients": "joint friction is the model's (MJCF frictionloss)",
        "set_velocities": "a fixed base has no root velocity; set the joints' velocities",
    },
    "ArticulationController": {
        "get_effort_modes": "effort limits are always force limits here",
        "set_effort_modes": "effort limits are always force limits here",
    },
    "ParallelGripper": {
        "is_closed": "compare get_joint_positions() with joint_closed_positions",
    },
    "SurfaceGripper": {
        "apply_action": "a surface gripper has no joints to drive: use close() / open() or forward('close' | 'open')",
    },
    "PickPlaceController": {},
    "Stacking": {},
    "StackingController": {},
    "RmpFlow": {
        "get_end_effector_as_prim": "manip draws no debug prims: the end effector's pose is "
                                    "get_end_effector_pose(active_joint_positions)",
    },
    "RMPFlowController": {
        "get_articulation_motion_policy": "there is no ArticulationMotionPolicy (a QP controller on manip.control: "
                                          "controller.controller is its ReactiveController)",
    },
}

#: Members implemented with a difference a script may notice.
DIFFERS: dict[str, dict[str, str]] = {
    "PhysicsContext": {name: "checked and kept for its getter; changes nothing (a PhysX setting MuJoCo lacks)"
                       for name in ("enable_ccd", "enable_stablization", "enable_stabilization",
                                    "set_solve_articulation_contact_last", "enable_gpu_dynamics", "enable_fabric",
                                    "set_broadphase_type", "set_solver_type", "set_bounce_threshold",
                                    "set_friction_offset_threshold", "set_friction_correlation_distance",
                                    "set_enable_scene_query_support", "set_invert_collision_group_filter")
                       + tuple(f"set_gpu_{n}" for n in (
                           "max_rigid_contact_count", "max_rigid_patch_count", "found_lost_pairs_capacity",
                           "found_lost_aggregate_pairs_capacity", "total_aggregate_pairs_capacity",
                           "max_soft_body_contacts", "max_particle_contacts", "heap_capacity", "temp_buffer_capacity",
                           "max_num_partitions", "collision_stack_size"))},
    "SimulationApp": {"update": "steps physics only while a World plays, without the tasks' pre_step (as Kit)"},
    "XFormPrim": {"prim": "the object itself (no Usd.Prim): it answers USD's IsValid, GetPath, GetName, GetTypeName, "
                          "GetChildren, GetParent and the prim utilities take it; GetAttribute raises (no USD "
                          "attributes)"},
    "XFormPrimView": {"prims": "what get_prim_at_path returns for each path (the objects, or robots' link prims), "
                               "answering USD's reading methods; no USD attributes"},
    "GeometryPrim": {"apply_physics_material": "combined frictions with other surfaces apply from the next reset",
                     "get_collision_approximation": "the token set (default 'none'); primitives collide exactly "
                                                    "whatever it says, as PhysX's primitive shapes do",
                     "set_collision_approximation": "kept for the getter; primitives collide exactly whatever it "
                                                    "says, as PhysX's primitive shapes do"},
    "SurfaceGripper": {"close": "a MuJoCo weld to the free body the grip ray hits, pulling it in along the axis "
                                "onto the grip point (or until it touches the robot); the weld is stiff: kp / kd "
                                "are not used (other values than Isaac's 100 warn)",
                       "initialize": "the gripper binds when the World compiles; initialize() checks it did"},
    "GeometryPrimView": {"set_collision_approximations": "kept for the getter; primitives collide exactly, as "
                                                         "PhysX's primitive shapes do"},
    "RigidPrimView": {"get_net_contact_forces": "contact impulses over the step / dt, as Isaac; MuJoCo's soft "
                      "contacts, summed per body",
                      "set_sleep_thresholds": "checked (>= 0), kept for the getter, changes nothing: MuJoCo's "
                                              "sleeping is left off, nothing sleeps (a warning says so once)",
                      "get_sleep_thresholds": "the values set (PhysX's default 5e-05 m^2/s^2 until then); "
                                              "nothing sleeps"},
    "RigidPrim": {"set_sleep_threshold": "checked (>= 0), kept for the getter, changes nothing: MuJoCo's sleeping "
                                         "is left off, nothing sleeps (a warning says so once)",
                  "get_sleep_threshold": "the value set (PhysX's default 5e-05 m^2/s^2 until then); nothing sleeps"},
    "Articulation": {"set_world_pose": "after the reset, a pose inside another robot raises RobotsOverlapError "
                                       "and the robot stays where it was (PhysX would push them apart)",
                     "set_joint_positions": "a position past a limit is set with a warning; the next step puts it "
                     "back on the limit (PhysX pushes it back too)",
                     "set_enabled_self_collisions": "applies from the next world.reset() (the World recompiles); "
                                                    "False excludes every pair of the robot's bodies from contact, "
                                                    "True keeps the model's own filter (its MJCF excludes)",
                     "prim": "the referenced model's prim on the stage (no Usd.Prim): USD's reading methods, its "
                             "links as children; no USD attributes",
                     "disable_gravity": "each body's weight cancelled at its centre of mass (was a no-op: MuJoCo's "
                                        "gravcomp needs bodies compiled with it)",
                     **{f"{verb}_{name}": f"{note}; kept for the getter, changes nothing (a warning says so)"
                        for verb in ("set", "get") for name, note in (
                            ("solver_position_iteration_count", ("MuJoCo's iteration cap is the World's, not an "
                                                                 "articulation's: World.model.opt.iterations")),
                            ("solver_velocity_iteration_count", "MuJoCo has no velocity iterations"),
                            ("sleep_threshold", "MuJoCo's sleeping is left off: nothing sleeps"),
                            ("stabilization_threshold", "no MuJoCo equivalent of PhysX's stabilization"))}},
    "ArticulationView": {"get_jacobians": "MuJoCo's body-origin Jacobians in Isaac's layout",
                         "set_world_poses": "after the reset, a pose inside another robot raises RobotsOverlapError "
                                            "and the robot stays where it was"},
    "Camera": {"add_semantic_segmentation_to_frame": "labels from add_update_semantics (a prim's own or its "
                                                     "nearest labelled ancestor's); ids only (colorize=False)",
               "add_instance_id_segmentation_to_frame": "one id per MuJoCo body (a prim: an object or a robot "
                                                        "link), not per mesh; ids only (colorize=False)",
               "set_focus_distance": "kept, not rendered (no depth of field)",
               "set_lens_aperture": "kept, not rendered (no depth of field)",
               "set_stereo_role": "kept; the images are the same"},
    "Scene": {"disable_bounding_boxes_computations": "compute_object_AABB keeps working (bounds are computed on "
                                                      "demand; Isaac raises until they are enabled again)"},
    "PreviewSurface": {"set_roughness": "kept, not rendered (MuJoCo has no MDL shaders)",
                       "set_metallic": "kept, not rendered (MuJoCo has no MDL shaders)"},
    "OmniPBR": {"set_texture": "kept, not rendered (MuJoCo has no MDL shaders)"},
    "PhysicsMaterial": {"set_restitution": "kept, not simulated (MuJoCo contacts are inelastic)"},
}

#: Isaac's module-level utilities a tutorial imports, by module.
ISAAC_FUNCTIONS: dict[str, tuple[str, ...]] = {
    "omni.isaac.core.utils.stage": ("add_reference_to_stage", "clear_stage", "create_new_stage",
                                    "create_new_stage_async", "get_current_stage", "get_stage_units",
                                    "is_stage_loading", "update_stage", "update_stage_async", "open_stage",
                                    "save_stage"),
    "omni.isaac.core.utils.prims": ("is_prim_path_valid", "get_prim_at_path", "delete_prim",
                                    "find_matching_prim_paths", "create_prim", "define_prim", "get_prim_path",
                                    "get_prim_children", "get_prim_parent", "get_prim_type_name",
                                    "get_prim_object_type", "get_all_matching_child_prims",
                                    "get_first_matching_child_prim"),
    "omni.isaac.core.utils.xforms": ("get_world_pose", "get_local_pose"),
    "omni.isaac.core.utils.semantics": ("add_update_semantics", "remove_all_semantics", "get_semantics"),
    "omni.isaac.core.utils.bounds": ("create_bbox_cache", "compute_aabb", "compute_combined_aabb"),
    "omni.isaac.core.utils.rotations": ("euler_angles_to_quat", "quat_to_euler_angles", "quat_to_rot_matrix",
                                        "rot_matrix_to_quat", "euler_to_rot_matrix", "rot_matrix_to_euler_angles",
                                        "gf_quat_to_np_array"),
    "omni.isaac.core.utils.nucleus": ("get_assets_root_path",),
    "omni.isaac.core.utils.string": ("find_unique_string_name",),
    "omni.isaac.core.utils.viewports": ("set_camera_view",),
    "omni.isaac.core.utils.extensions": ("enable_extension", "disable_extension", "get_extension_path_from_name"),
    "omni.isaac.core.utils.transformations": ("tf_matrix_from_pose", "pose_from_tf_matrix", "tf_matrices_from_poses",
                                              "get_relative_transform", "get_translation_from_target",
                                              "get_world_pose_from_relative",
                                              "get_transform_with_normalized_rotation"),
    "omni.isaac.core.utils.distance_metrics": ("weighted_translational_distance", "rotational_distance_angle",
                                               "rotational_distance_identity_matrix_deviation",
                                               "rotational_distance_single_axis"),
    "omni.isaac.motion_generation.interface_config_loader": (
        "get_supported_robot_policy_pairs", "load_supported_motion_policy_config",
        "get_supported_robots_with_lula_kinematics", "load_supported_lula_kinematics_solver_config"),
}

#: Isaac modules a script imports whole, by the manip.sim module standing for each (its functions
#: are looked up there; every other module's in manip.sim itself).
ISAAC_MODULES: dict[str, str] = {
    "omni.isaac.motion_generation.interface_config_loader": "interface_config_loader",
}

#: Module-level utilities manip.sim cannot provide (they raise NotImplementedError with the reason).
FUNCTIONS_NOT_SUPPORTED: dict[str, str] = {
    "open_stage": "manip has no USD: reference MJCF/URDF files with add_reference_to_stage",
    "save_stage": "manip has no USD: World.model (MuJoCo) can be saved with mujoco.mj_saveLastXML",
    "gf_quat_to_np_array": "manip has no USD Gf types: quaternions are NumPy arrays (w, x, y, z) already",
}
