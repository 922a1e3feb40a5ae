"""Setting up a robot from its asset, as Isaac's robot-setup tutorials do: reference the Franka's
USD, wrap it in an Articulation, tune PhysX's articulation solver (iteration counts, sleep and
stabilization thresholds), walk its prims (the links below the robot's prim, the fingers by a
predicate), set the drive gains, drive the arm to a configuration and read the hand's pose
through `omni.isaac.core.utils.xforms` and the hand's prim. Only the imports differ from
Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import Articulation
from manip.sim import ArticulationAction
from manip.sim import add_reference_to_stage, get_assets_root_path
from manip.sim import get_prim_at_path, is_prim_path_valid, get_prim_children, get_all_matching_child_prims, get_prim_path
from manip.sim import get_world_pose

world = World(stage_units_in_meters=1.0)
world.scene.add_default_ground_plane()
asset_path = get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"
add_reference_to_stage(usd_path=asset_path, prim_path="/World/Franka")
franka = world.scene.add(Articulation(prim_path="/World/Franka", name="my_franka"))

# PhysX articulation settings, as robot-setup scripts tune them
franka.set_solver_position_iteration_count(64)
franka.set_solver_velocity_iteration_count(4)
franka.set_sleep_threshold(0.0)
franka.set_stabilization_threshold(0.001)
world.reset()
solver_settings = (franka.get_solver_position_iteration_count(), franka.get_solver_velocity_iteration_count(),
                   franka.get_sleep_threshold())

# the robot's prims
robot_prim = get_prim_at_path("/World/Franka")
links = [get_prim_path(p) for p in get_prim_children(robot_prim)]
fingers = [get_prim_path(p) for p in get_all_matching_child_prims("/World/Franka", lambda path: "finger" in path)]
hand_prim = get_prim_at_path("/World/Franka/panda_hand")
print("valid:", is_prim_path_valid("/World/Franka/panda_hand"), hand_prim.IsValid(), hand_prim.GetTypeName())
print("links:", links)

# stiffer drives for the arm, then a joint-space move
controller = franka.get_articulation_controller()
kps, kds = controller.get_gains()
kps[:7] *= 2.0
controller.set_gains(kps=kps, kds=kds)
target = np.array([0.3, -0.4, 0.1, -2.2, 0.0, 1.9, 0.8, 0.04, 0.04])
for _ in range(240):
    controller.apply_action(ArticulationAction(joint_positions=target))
    world.step(render=False)
joint_error = float(np.max(np.abs(franka.get_joint_positions() - target)))
hand_position, hand_orientation = get_world_pose("/World/Franka/panda_hand")
prim_position, prim_orientation = hand_prim.get_world_pose()
print(f"joint error {joint_error:.4f} rad; hand at {np.round(hand_position, 4)}")
simulation_app.close()
