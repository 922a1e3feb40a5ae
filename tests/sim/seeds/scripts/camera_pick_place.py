"""A camera above the table captures RGB and depth while a Franka picks Isaac's default cube
and places it (the PickPlace task and its controller, as in Isaac's examples, with an
isaacsim.sensors.camera.Camera added as its tutorial makes one): the cube is found in the
images before and after, where the camera's projection of its simulated position says.
Written as for Isaac Sim 4.x; only the imports differ (omni.isaac... -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import PickPlace
from manip.sim import PickPlaceController
from manip.sim import Camera
import manip.sim as rot_utils
from manip.sim import get_translation_from_target
from manip.sim import ArticulationAction

my_world = World(stage_units_in_meters=1.0)
my_task = PickPlace()
my_world.add_task(my_task)
camera = Camera(
    prim_path="/World/camera",
    position=np.array([0.0, 0.0, 2.0]),
    frequency=20,
    resolution=(256, 256),
    orientation=rot_utils.euler_angles_to_quats(np.array([0, 90, 0]), degrees=True),
)
my_world.reset()
camera.initialize()
camera.add_motion_vectors_to_frame()
camera.add_distance_to_image_plane_to_frame()

task_params = my_task.get_params()
cube_name = task_params["cube_name"]["value"]
my_franka = my_world.scene.get_object(task_params["robot_name"]["value"])
my_cube = my_world.scene.get_object(cube_name)
my_controller = PickPlaceController(name="pick_place_controller", gripper=my_franka.gripper,
                                    robot_articulation=my_franka)
articulation_controller = my_franka.get_articulation_controller()


def cube_in_image():
    """(pixel (u, v) of the cube's centre, the depth there [m], its top's distance from the camera
    along its axis [m], the centre (u, v) of the pixels that see blue, the PickPlace cube's colour)."""
    position, _ = my_cube.get_world_pose()
    u, v = camera.get_image_coords_from_world_points(np.array([position]))[0]
    depth = camera.get_depth()
    rgb = camera.get_rgba()[:, :, :3].astype(float)
    blue = (rgb[:, :, 2] > 60) & (rgb[:, :, 0] < 0.5 * rgb[:, :, 2]) & (rgb[:, :, 1] < 0.5 * rgb[:, :, 2])
    rows, cols = np.nonzero(blue)
    top = position + [0.0, 0.0, 0.0515 / 2]
    along_axis = -get_translation_from_target(top, "/World/defaultGroundPlane", camera)[2]
    return (u, v), float(depth[round(v), round(u)]), float(along_axis), (cols.mean(), rows.mean())


frames = []
before = cube_in_image()
for i in range(3000):
    my_world.step(render=True)
    observations = my_world.get_observations()
    actions = my_controller.forward(
        picking_position=observations[cube_name]["position"],
        placing_position=observations[cube_name]["target_position"],
        current_joint_positions=observations[task_params["robot_name"]["value"]]["joint_positions"],
        end_effector_offset=np.array([0, 0.005, 0]),
    )
    articulation_controller.apply_action(actions)
    if i % 100 == 0:
        frame = camera.get_current_frame()
        frames.append({"rgba": frame["rgba"].shape, "depth": frame["distance_to_image_plane"].shape,
                       "motion": float(np.abs(frame["motion_vectors"]).max())})
    if my_controller.is_done():
        break
home = my_franka.get_joints_default_state().positions
for _ in range(120):  # the arm back up out of the camera's view of the cube
    articulation_controller.apply_action(ArticulationAction(joint_positions=home))
    my_world.step(render=True)
after = cube_in_image()
target = observations[cube_name]["target_position"]
intrinsics = camera.get_intrinsics_matrix()
simulation_app.close()
