"""Two Frankas hand a cube over in mid-air, every motion planned for both arms as one robot.

Isaac's multi-robot pattern in `manip.sim`: two `Franka` prims 0.7 m apart facing the same
side, each with its own controller; the planner is `MotionGenerator("dual_franka")` (the
two arms as one robot, `robots/dual_franka/`), whose combined trajectories are split per
robot by `trajectory.to_articulation_actions(robot)`. An episode:

1. the left arm picks the cube from the ground (top grasp; the right arm held still);
2. both arms move at once, in one planned motion: the left hand brings the cube to the
   handover point, turned so that the fingers hold its top and bottom faces, while the right
   hand comes to face it from the other side;
3. the right hand approaches in a straight line and closes on the cube's two free faces;
   the left hand opens and backs away;
4. the right arm puts the cube down at the place position and both arms go home.

    python examples/bimanual_handover.py                  # 3 episodes, headless
    python examples/bimanual_handover.py --episodes 10 --seed 1
    python examples/bimanual_handover.py --viewer         # MuJoCo's window (needs a display)

The cube moves only by contact and friction with the fingers. The exit status is 0 only
when every episode ends with the cube within 1 cm of the place position.
"""

from __future__ import annotations

import sys

import numpy as np

from manip import MotionGenerator, Pose
from manip import quaternion as quat
from manip.sim import DynamicCuboid, Franka, SimulationApp, VisualCuboid, World, create_new_stage
from _bimanual import Bimanual, hand_down, run_episodes

CUBE = 0.05                                        # [m] edge
PICK_X, PICK_Y = (0.42, 0.55), (0.22, 0.38)        # [m] where episodes put the cube (in front of the left arm)
PLACE = np.array([0.45, -0.30, CUBE / 2])          # [m] where the right arm puts it
HANDOVER = np.array([0.50, 0.0, 0.35])             # [m] the cube's centre at the handover
SUCCESS = 0.01                                     # [m]
APPROACH = 0.12                                    # [m] straight-line approaches and retreats
GRASP_HEIGHT = 0.003                               # [m] TCP above the cube centre at the pick
RELEASE_HEIGHT = 0.004                             # [m] cube bottom above the ground when released
SQUEEZE = 0.01                                     # [m] each finger's target inside the cube face
#: Hand orientations (w, x, y, z) at the handover: the left hand points towards the right
#: (its z = world -y) with its fingers closing vertically (y = world z); the right hand points
#: back at it (z = world y), its fingers closing along world x: the cube's two free faces.
LEFT_HANDOVER = quat.from_matrix(np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]))
RIGHT_HANDOVER = quat.from_matrix(np.array([[0.0, 1, 0], [0, 0, 1], [1, 0, 0]]))
#: The right hand pointing down with its fingers still along world x (the place).
RIGHT_PLACE = quat.from_matrix(np.array([[0.0, 1, 0], [1, 0, 0], [0, 0, -1]]))


class Handover(Bimanual):
    """The scene and one handover episode (see the module docstring)."""

    thing, place, success = "cube", PLACE, SUCCESS

    def __init__(self, seed: int, viewer: bool = False, verbose: bool = True):
        self.app = SimulationApp({"headless": not viewer})
        World.clear_instance()
        create_new_stage()
        world = World(physics_dt=1.0 / 60.0)
        world.scene.add_default_ground_plane()
        self.cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.3, CUBE / 2],
                                                  size=CUBE, mass=0.05, color=np.array([0.1, 0.3, 0.9])))
        world.scene.add(VisualCuboid("/World/place_marker", name="place_marker", size=1.0,
                                     position=PLACE * [1, 1, 0] + [0, 0, 0.0005], scale=[CUBE + 0.01, CUBE + 0.01, 0.001],
                                     color=np.array([0.1, 0.8, 0.2])))
        mg = MotionGenerator("dual_franka", padding=0.005, time_budget=3.0, seed=seed)
        left = world.scene.add(Franka("/World/left_franka", name="left_franka", position=mg.config.arms[0].base_pose.position))
        right = world.scene.add(Franka("/World/right_franka", name="right_franka",
                                       position=mg.config.arms[1].base_pose.position))
        super().__init__(world, mg, left, right, seed=seed, render=bool(viewer), verbose=verbose)
        world.reset()

    def start_pose(self, rng: np.random.Generator) -> None:
        p0 = np.array([rng.uniform(*PICK_X), rng.uniform(*PICK_Y), CUBE / 2])
        self.cube.set_world_pose(p0, quat.from_axis_angle([0, 0, 1], rng.uniform(-np.pi, np.pi)))

    def object_position(self) -> np.ndarray:
        return np.asarray(self.cube.get_world_pose()[0], dtype=float)

    def run(self) -> None:
        mg, L, R = self.mg, self.arms[0], self.arms[1]
        self.sync_world(ignore=["cube"])
        # 1. the left arm picks the cube (top grasp, the yaw of one of its faces nearest the arm's heading)
        p, qc = self.cube.get_world_pose()
        yaw = self.grasp_yaw(np.asarray(p), np.asarray(qc), L)
        grasp = Pose(np.asarray(p) + [0, 0, GRASP_HEIGHT], hand_down(yaw))
        self.move_link(L, Pose(grasp.position + [0, 0, APPROACH], grasp.quaternion), "pre-grasp")
        self.move_link(L, grasp, "descend", linear=True)
        self.gripper(L, CUBE / 2 - SQUEEZE, "left close")
        self.check_held(L, CUBE, "after the left grasp")
        self.attach(L)
        self.move_link(L, Pose(self.tcp(L).position + [0, 0, APPROACH], grasp.quaternion), "lift", linear=True)
        # 2. both arms at once: the cube to the handover point, the right hand facing it
        left_goal = Pose(HANDOVER - quat.to_matrix(LEFT_HANDOVER) @ self.object_in_tcp(L), LEFT_HANDOVER)
        right_pre = Pose(HANDOVER - [0, APPROACH, 0], RIGHT_HANDOVER)
        self.move_links({L.tcp: left_goal, R.tcp: right_pre}, "to handover")
        # 3. the right hand takes it: straight in, close, the left hand lets go and backs away
        centre = self.object_position()
        self.move_link(R, Pose(centre, RIGHT_HANDOVER), "right approach", linear=True)
        self.gripper(R, CUBE / 2 - SQUEEZE, "right close")
        self.check_held(R, CUBE, "after the right grasp")
        self.detach()
        self.attach(R)
        self.gripper(L, L.robot.gripper.joint_opened_positions[0], "left open")
        back = self.tcp(L)
        self.move_link(L, Pose(back.position + [0, APPROACH, 0], back.quaternion), "left retreat", linear=True)
        self.move_home(L, "left home")
        # 4. the right arm places the cube
        self.check_held(R, CUBE, "before the place")
        release = PLACE + [0, 0, RELEASE_HEIGHT] - quat.to_matrix(RIGHT_PLACE) @ self.object_in_tcp(R)
        self.move_link(R, Pose(release + [0, 0, APPROACH], RIGHT_PLACE), "pre-place")
        self.move_link(R, Pose(release, RIGHT_PLACE), "descend", linear=True)
        self.gripper(R, R.robot.gripper.joint_opened_positions[0], "right open")
        self.detach()
        mg.remove_obstacle("cube")
        up = self.tcp(R)
        self.move_link(R, Pose(up.position + [0, 0, APPROACH], up.quaternion), "right retreat", linear=True)
        self.move_home(R, "right home")
        self.settle()


def main(argv: list[str] | None = None) -> int:
    return run_episodes(Handover, __doc__, argv, things="cubes", done="handed over and placed")


if __name__ == "__main__":
    sys.exit(main())
