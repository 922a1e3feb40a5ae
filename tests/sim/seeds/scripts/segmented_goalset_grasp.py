"""A camera above the table segments a cube labelled "cube" (Isaac's semantic_segmentation
annotator, the label set with add_update_semantics), the cube's position is estimated from the
segmented depth pixels, and a cuRobo-style goal-set IK picks one of four pre-grasp poses above it
(the hand turned by 0, 90, 180 and 270 degrees about the vertical; `solve_goalset` says which
through `goalset_index`). The Franka then goes to that pre-grasp, down to the grasp, closes and
lifts the cube. Written as for Isaac Sim 4.x and cuRobo; only the imports differ, and cuRobo's
`IKSolver` is the MotionGenerator's (`motion_gen.ik_solver`)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip import MotionGenerator, Pose
from manip.sim import ArticulationAction, Camera, DynamicCuboid, Franka, World, add_update_semantics
from manip.sim import get_prim_at_path
import manip.sim as rot_utils

SIZE = 0.0515
my_world = World(stage_units_in_meters=1.0)
my_world.scene.add_default_ground_plane()
robot = my_world.scene.add(Franka("/World/Franka", name="franka"))
cube = my_world.scene.add(DynamicCuboid("/World/Cube", name="cube", position=np.array([0.45, 0.12, SIZE / 2]),
                                        size=SIZE, color=np.array([0, 0, 1.0])))
add_update_semantics(cube.prim, semantic_label="cube", type_label="class")
camera = Camera(prim_path="/World/camera", position=np.array([0.45, 0.0, 1.2]), resolution=(160, 160),
                orientation=rot_utils.euler_angles_to_quats(np.array([0, 90, 0]), degrees=True))
my_world.reset()
camera.initialize()
camera.add_semantic_segmentation_to_frame({"colorize": False})
for _ in range(20):
    my_world.step(render=True)

# --- find the cube in the image: its label's id, its pixels, their world points
frame = camera.get_current_frame()
segmentation = frame["semantic_segmentation"]
labels = segmentation["info"]["idToLabels"]
cube_id = next(int(i) for i, label in labels.items() if label.get("class") == "cube")
rows, cols = np.nonzero(segmentation["data"] == cube_id)
depth = frame["distance_to_image_plane"][rows, cols]
points = camera.get_world_points_from_image_coords(np.stack([cols, rows], axis=1), depth)
top = points[points[:, 2] > points[:, 2].max() - 0.005]     # the top face (the sides seen slanted)
estimate = np.array([top[:, 0].mean(), top[:, 1].mean(), top[:, 2].mean() - SIZE / 2])
print("cube pixels", rows.size, "estimated", estimate, "true", cube.get_world_pose()[0])

# --- cuRobo: goal-set IK over several pre-grasp poses (hand down, four yaws)
motion_gen = MotionGenerator("franka")
ik_solver = motion_gen.ik_solver
joint_idx = [robot.get_dof_index(x) for x in motion_gen.joint_names]
down = np.array([0.0, 1.0, 0.0, 0.0])                       # (w, x, y, z): panda_hand pointing down


def hand_pose(height, yaw):
    turn = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
    q = rot_utils.quats_to_rot_matrices(turn[None])[0] @ rot_utils.quats_to_rot_matrices(down[None])[0]
    return Pose(estimate + [0.0, 0.0, height], rot_utils.rot_matrices_to_quats(q[None])[0])


yaws = np.radians([0, 90, 180, 270])
pre_grasps = Pose.stack([hand_pose(0.2, yaw) for yaw in yaws])
q_now = robot.get_joint_positions()[joint_idx]
result = ik_solver.solve_goalset(pre_grasps, seed_q=q_now)
print("goal set success", result.success.item(), "goalset_index", result.goalset_index.item())
chosen = result.goalset_index.item()
q_pre = result.solution[result.success][0]
q_grasp = ik_solver.solve(hand_pose(0.105, yaws[chosen]), seed_q=q_pre).q
q_lift = ik_solver.solve(hand_pose(0.25, yaws[chosen]), seed_q=q_grasp).q
controller = robot.get_articulation_controller()


def drive(q, steps):
    for _ in range(steps):
        controller.apply_action(ArticulationAction(joint_positions=q, joint_indices=joint_idx))
        my_world.step(render=True)


robot.gripper.open()
drive(q_pre, 150)
hand_at_pre = get_prim_at_path("/World/Franka/panda_hand").get_world_pose()
drive(q_grasp, 120)
robot.gripper.close()
for _ in range(40):
    my_world.step(render=True)
drive(q_lift, 150)
cube_after = cube.get_world_pose()[0]
print("cube lifted to", cube_after)
simulation_app.close()
