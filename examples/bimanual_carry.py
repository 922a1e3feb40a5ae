"""Two Frankas lift and carry a long box together, its grip held by a relative-pose constraint.

Isaac's multi-robot pattern in `manip.sim` (two `Franka` prims, one controller each) with one
planner for both arms (`MotionGenerator("dual_franka")`). Both hands come down on the ends of
a 40 cm box lying between the arms and close on it; the box becomes the planner's object held
by both hands (`attach_object(..., link=("left_panda_hand", "right_panda_hand"))`); the lift,
the carry and the lowering are each one motion of both arms planned with
`manip.RelativePoseConstraint("left_panda_hand", "right_panda_hand")`: the right hand's pose in
the left hand's frame stays within 2 mm and 0.01 rad of what it was at the grasp over the whole
continuous motion (certified between samples), so the arms never pull the box apart. Then both
hands open and the arms go home.

    python examples/bimanual_carry.py                     # 3 episodes, headless
    python examples/bimanual_carry.py --episodes 10 --seed 1
    python examples/bimanual_carry.py --viewer            # MuJoCo's window (needs a display)

The box moves only by contact and friction with the fingers. The exit status is 0 only when
every episode ends with the box within 1 cm of its place position and never dropped.
"""

from __future__ import annotations

import sys

import numpy as np

from _bimanual import Bimanual, hand_down, run_episodes
from manip import MotionGenerator, Pose, RelativePoseConstraint
from manip import quaternion as quat
from manip.sim import DynamicCuboid, Franka, SimulationApp, VisualCuboid, World, create_new_stage

BOX = np.array([0.05, 0.40, 0.05])                 # [m] edges: 5 cm wide (x), 40 cm long (y)
START_X, START_Y = (0.45, 0.55), (-0.04, 0.04)     # [m] where episodes put the box's centre
START_YAW = 0.15                                   # [rad] largest turn of the box about z at the start
PLACE = np.array([0.40, 0.0, BOX[2] / 2])          # [m] where the box is carried (yaw 0)
GRIP = 0.14                                        # [m] each hand this far from the box's centre
SUCCESS = 0.01                                     # [m]
LIFT = 0.20                                        # [m]
APPROACH = 0.12                                    # [m]
GRASP_HEIGHT = 0.003                               # [m] TCP above the box's axis
RELEASE_HEIGHT = 0.004                             # [m] box bottom above the ground when lowered
SQUEEZE = 0.01                                     # [m] each finger's target inside the box's face
HOLD = dict(position_tolerance=0.002, rotation_tolerance=0.01)   # the relative pose of the hands
CARRY = dict(velocity_scale=0.5, acceleration_scale=0.5)


class Carry(Bimanual):
    """The scene and one carry episode (see the module docstring)."""

    thing, place, success = "box", PLACE, SUCCESS

    def __init__(self, seed: int, viewer: bool = False, verbose: bool = True):
        self.app = SimulationApp({"headless": not viewer})
        World.clear_instance()
        create_new_stage()
        world = World(physics_dt=1.0 / 60.0)
        world.scene.add_default_ground_plane()
        self.box = world.scene.add(DynamicCuboid("/World/box", name="box", position=[0.5, 0.0, BOX[2] / 2], size=1.0,
                                                 scale=BOX, mass=0.2, color=np.array([0.8, 0.5, 0.1])))
        world.scene.add(VisualCuboid("/World/place_marker", name="place_marker", size=1.0,
                                     position=PLACE * [1, 1, 0] + [0, 0, 0.0005], scale=BOX * [1.2, 1.05, 0] + [0, 0, 0.001],
                                     color=np.array([0.1, 0.8, 0.2])))
        mg = MotionGenerator("dual_franka", padding=0.005, time_budget=5.0, seed=seed)
        left = world.scene.add(Franka("/World/left_franka", name="left_franka", position=mg.config.arms[0].base_pose.position))
        right = world.scene.add(Franka("/World/right_franka", name="right_franka",
                                       position=mg.config.arms[1].base_pose.position))
        super().__init__(world, mg, left, right, seed=seed, render=bool(viewer), verbose=verbose)
        world.reset()

    def object_position(self) -> np.ndarray:
        return np.asarray(self.box.get_world_pose()[0], dtype=float)

    def box_pose(self) -> Pose:
        p, q = self.box.get_world_pose()
        return Pose(np.asarray(p, dtype=float), np.asarray(q, dtype=float))

    def grips(self) -> tuple[np.ndarray, np.ndarray]:
        """The two grip points (3,) [m] on the box's axis, left then right, where the box is now."""
        pts = self.box_pose().transform_points(np.array([[0.0, GRIP, 0.0], [0.0, -GRIP, 0.0]]))
        return pts[0], pts[1]

    def start_pose(self, rng: np.random.Generator) -> None:
        p0 = np.array([rng.uniform(*START_X), rng.uniform(*START_Y), BOX[2] / 2])
        self.box.set_world_pose(p0, quat.from_axis_angle([0, 0, 1], rng.uniform(-START_YAW, START_YAW)))

    def run(self) -> None:
        mg, L, R = self.mg, self.arms[0], self.arms[1]
        self.sync_world(ignore=["box"])
        yaw = float(np.arctan2(*quat.to_matrix(self.box_pose().quaternion)[[1, 0], 0]))
        down = hand_down(yaw + np.pi / 2)         # the fingers across the box (along its x)
        gl, gr = (g + [0, 0, GRASP_HEIGHT] for g in self.grips())
        self.move_links({L.tcp: Pose(gl + [0, 0, APPROACH], down), R.tcp: Pose(gr + [0, 0, APPROACH], down)}, "pre-grasp")
        self.set_floor(False)
        self.move_links({L.tcp: Pose(gl, down), R.tcp: Pose(gr, down)}, "descend", floor=False)
        for arm in (L, R):
            self.gripper(arm, BOX[0] / 2 - SQUEEZE, f"{arm.hand.split('_')[0]} close")
        self.check_grips("after the grasp")
        self.attach((L, R), name="box")
        hold = (RelativePoseConstraint(L.hand, R.hand, **HOLD),)
        # lift, carry over the place position, lower: each one motion of both arms, the grip held
        tl, tr = self.tcp(L), self.tcp(R)
        lifted = {L.tcp: Pose(tl.position + [0, 0, LIFT], tl.quaternion), R.tcp: Pose(tr.position + [0, 0, LIFT], tr.quaternion)}
        self.move_links(lifted, "lift", floor=False, constraints=hold, **CARRY)
        self.check_grips("after the lift")
        # the box's centre to PLACE (its yaw to 0): both TCPs keep their pose in the box's frame
        T_place = Pose(PLACE + [0, 0, RELEASE_HEIGHT + LIFT], [1.0, 0, 0, 0]) @ self.box_pose().inverse()
        over = {a.tcp: T_place @ self.tcp(a) for a in (L, R)}
        self.move_links(over, "carry", constraints=hold, **CARRY)
        self.check_grips("after the carry")
        lowered = {a.tcp: Pose(self.tcp(a).position - [0, 0, LIFT], self.tcp(a).quaternion) for a in (L, R)}
        self.move_links(lowered, "lower", floor=False, constraints=hold, **CARRY)
        for arm in (L, R):
            self.gripper(arm, arm.robot.gripper.joint_opened_positions[0], f"{arm.hand.split('_')[0]} open")
        self.detach()
        mg.remove_obstacle("box")
        up = {a.tcp: Pose(self.tcp(a).position + [0, 0, APPROACH], self.tcp(a).quaternion) for a in (L, R)}
        self.move_links(up, "retreat", floor=False)
        for arm in (L, R):
            self.move_home(arm, f"{arm.hand.split('_')[0]} home")
        self.settle()

    def check_grips(self, when: str) -> None:
        """Both hands still hold the box at its grip points (raise MotionFailed if not)."""
        for arm, point in zip(self.arms, self.grips()):
            self.check_held(arm, BOX[0], when, point=point)


def main(argv: list[str] | None = None) -> int:
    return run_episodes(Carry, __doc__, argv, things="boxes", done="carried and put down")


if __name__ == "__main__":
    sys.exit(main())
