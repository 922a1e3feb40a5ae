"""Isaac's UR10 pick-and-place pattern: a UR10 with a suction gripper (`SurfaceGripper` on its
`ee_link`) wrapped as a `SingleManipulator`, Isaac's generic `PickPlaceController` driving an
`RMPFlowController` of the UR10. Written as for Isaac Sim 4.x; only the imports differ
(omni.isaac.core / omni.isaac.manipulators -> manip.sim), plus `robot="ur10"` for manip's
RMPFlowController (Isaac's is the UR10's own class) and manip's UR10 model path. The
controller's defaults (a 2 cm safety margin, the UR10's links 18-20 mm apart at home)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World, DynamicCuboid, SingleManipulator, SurfaceGripper, RMPFlowController
from manip.sim import PickPlaceController
from manip.sim import get_assets_root_path

my_world = World(stage_units_in_meters=1.0)
my_world.scene.add_default_ground_plane()
cube = my_world.scene.add(DynamicCuboid(prim_path="/World/cube", name="cube", position=np.array([0.6, 0.3, 0.0515 / 2]),
                                        size=0.0515, color=np.array([0, 0, 1.0])))
gripper = SurfaceGripper(end_effector_prim_path="/World/UR10/ee_link", translate=0.0, direction="x")
ur10 = my_world.scene.add(SingleManipulator(prim_path="/World/UR10", name="my_ur10", end_effector_prim_name="ee_link",
                                            gripper=gripper, usd_path=get_assets_root_path() + "/ur10/ur10.xml"))
ur10.set_joints_default_state(positions=np.array([0.0, -2.2, 1.9, -1.383, -1.57, 0.0]))
my_world.reset()

my_controller = PickPlaceController(
    name="pick_place_controller",
    cspace_controller=RMPFlowController(name="cspace_controller", robot_articulation=ur10, robot="ur10"),
    gripper=gripper,
    end_effector_initial_height=0.4,
    events_dt=[0.01, 0.01, 0.1, 0.1, 0.01, 0.005, 0.01, 1, 0.01, 0.08],
)
articulation_controller = ur10.get_articulation_controller()
goal_position = np.array([0.3, 0.6, 0.0515 / 2])
held = []
for i in range(3000):
    my_world.step(render=True)
    if my_world.is_playing():
        actions = my_controller.forward(
            picking_position=cube.get_world_pose()[0],
            placing_position=goal_position,
            current_joint_positions=ur10.get_joint_positions(),
            end_effector_offset=np.array([0, 0, 0.0515 / 2 + 0.004]),
        )
        held.append(gripper.is_closed())
        if my_controller.is_done():
            break
        articulation_controller.apply_action(actions)
cube_position = cube.get_world_pose()[0]
print("done:", my_controller.is_done(), "steps:", i, "held for", sum(held), "steps; cube at", np.round(cube_position, 3))
simulation_app.close()
