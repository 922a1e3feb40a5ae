"""Carry an open cup full of marbles from one shelf to another, upright, around a post.

    python examples/carry_upright.py                  # headless; prints the measured tilt
    python examples/carry_upright.py --tolerance 0.1 --marbles 6 --viewer

A Franka in MuJoCo (`manip.sim`) picks an open cup (a thin-walled cylinder, 6.8 cm across,
7.8 cm tall, a free body) standing on shelf A with a side grasp, carries it around a post to
shelf B and puts it down. The cup holds small spheres (1 cm radius, free bodies). Every
motion is planned by the MotionGenerator with an `OrientationConstraint` held over the whole
continuous motion (`plan_grasp` for the grasp and the lift, `plan_place(constraints=...)` for
the carry): before the grasp on the hand's axis that will hold the cup's axis; once the cup
is held, on the cup's own axis as measured in the hand (so an offset of the grasp counts).
The simulation measures the cup's tilt (its axis against the vertical) at every physics step
and counts the spheres still in the cup at the end.

The physics is honest: the cup is held by the fingers' friction only, the spheres roll in
it. What the planner guarantees is the planned motion's tilt; the cup's measured tilt adds
the arm's tracking error and the cup's slip in the grasp. So the plan holds the cup's axis
within `tolerance - GRIP_BUDGET` and the grip is modelled stiffly enough to stay inside the
budget: friction cones stiffened (`impratio` 10: MuJoCo's friction is a soft constraint, under
the cup's steady off-axis load the default one lets it creep about 0.03 rad/s) and the finger
pads' contacts stiffer (time constant 2 ms, MuJoCo substeps of 0.5 ms). Measured over seeds
0-9 (BENCHMARKS.md, "Carrying a cup upright"): the cup's tilt 0.067-0.080 rad, at most 0.008
rad above the planned tilt of its axis (the arm's tracking and the cup's slip in the grasp
together; 0.08 above with MuJoCo's default grip). Exit status 0 when the cup stands on shelf
B, every sphere is in it, and the cup's measured tilt never exceeded `tolerance`.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile

import mujoco
import numpy as np
import pinocchio as pin

from manip import ArticulationAction, Cylinder, MotionGenerator, OrientationConstraint, Pose
from manip import quaternion as quat
from manip.sim import DynamicSphere, FixedCuboid, Franka, SimulationApp, World, add_reference_to_stage, create_new_stage

TCP = "panda_hand_tcp"
CUP_RADIUS = 0.031  # [m] centre of the wall
CUP_WALL = 0.003  # [m] half thickness of the wall
CUP_HEIGHT = 0.078  # [m]
CUP_SEGMENTS = 12  # flat wall pieces (the fingers close on two opposite ones)
MARBLE_RADIUS = 0.01  # [m]
SHELF_A = np.array([0.42, 0.38, 0.20])  # [m] centre of the top face
SHELF_B = np.array([0.45, -0.38, 0.26])
SHELF_SIZE = np.array([0.22, 0.22])
POST = (np.array([0.50, 0.0]), np.array([0.10, 0.10, 0.75]))  # centre (x, y), size [m]
CUP_START = SHELF_A + [0.0, 0.0, 0.0]  # [m] near shelf A's front edge: the hand reaches below its top
CUP_GOAL = SHELF_B + [0.0, 0.0, 0.0]
GRASP_HEIGHT = 0.066  # [m] TCP above the cup's bottom (the hand clear of the shelf)
GRASP_BACK = 0.012  # [m] TCP this far short of the cup's axis (the palm clear of the rim)
SQUEEZE = 0.006  # [m] each finger's target inside the cup's outer face (about 9 N of grip each)
CARRY_SCALE = 0.3  # velocity and acceleration scale while the cup is held
PADDING = 0.01  # [m]
#: [rad] of the tolerance kept for the grip's slip and the arm's tracking error: the planner
#: holds the cup's axis within tolerance - GRIP_BUDGET (measured: the cup's tilt <= 0.008 above the plan's)
GRIP_BUDGET = 0.02
#: The grip: MuJoCo substep [s], the finger pads' contact time constant [s] (>= 2 substeps)
#: and the friction cones' impedance ratio (MuJoCo's `impratio`: friction stiffer than the normal force)
SUBSTEP = 0.0005
PAD_TIMECONST = 0.002
IMPRATIO = 10.0


#: The cup's friction (sliding 1.2, torsional 0.02 m, rolling 0.1 mm); against the fingers the
#: finger pads' own parameters apply (their `priority` is higher: robots/franka/robot.yaml).
SLEEVE = 'friction="1.2 0.02 0.0001"'


def cup_mjcf() -> str:
    """The cup as an MJCF body with a free joint: a disc and CUP_SEGMENTS flat wall pieces."""
    half = math.pi * CUP_RADIUS / CUP_SEGMENTS + 0.0015
    walls = "\n".join(
        f'<geom type="box" size="{CUP_WALL} {half:.4f} {CUP_HEIGHT / 2 - 0.003:.4f}" '
        f'pos="{CUP_RADIUS * math.cos(a):.5f} {CUP_RADIUS * math.sin(a):.5f} {CUP_HEIGHT / 2 + 0.003:.4f}" '
        f'euler="0 0 {a:.5f}" mass="0.008" {SLEEVE}/>'
        for a in 2 * np.pi * np.arange(CUP_SEGMENTS) / CUP_SEGMENTS)
    return (f'<mujoco model="cup"><worldbody><body name="cup"><freejoint name="free"/>'
            f'<geom name="bottom" type="cylinder" size="{CUP_RADIUS + CUP_WALL} 0.003" pos="0 0 0.003" mass="0.02" '
            f'friction="1.2 0.02 0.0001"/>\n{walls}\n</body></worldbody></mujoco>')


def side_grasp(centre: np.ndarray, azimuth: float) -> Pose:
    """The TCP pose of a side grasp of the cup whose axis passes through `centre` (3,), from
    `azimuth` [rad]: the hand's z horizontal towards the axis (the TCP GRASP_BACK short of
    it), its y (the fingers' closing direction) horizontal, so its x points down."""
    z = -np.array([np.cos(azimuth), np.sin(azimuth), 0.0])
    y = np.array([-z[1], z[0], 0.0])
    return Pose(centre - GRASP_BACK * z, quat.from_matrix(np.stack([np.cross(y, z), y, z], axis=1)))


class CarryUpright:
    """The scene, the planner, and the carry."""

    def __init__(self, tolerance: float, marbles: int, viewer: bool = False, seed: int = 0, verbose: bool = True):
        self.tolerance, self.verbose = tolerance, verbose
        self.app = SimulationApp({"headless": not viewer})
        World.clear_instance()
        create_new_stage()
        self.world = World(physics_dt=1.0 / 60.0, substep_dt=SUBSTEP)
        scene = self.world.scene
        scene.add_default_ground_plane()
        for name, top in (("shelf_a", SHELF_A), ("shelf_b", SHELF_B)):
            scene.add(FixedCuboid(f"/World/{name}", name=name, position=top - [0, 0, top[2] / 2], size=1.0,
                                  scale=[*SHELF_SIZE, top[2]], color=[0.6, 0.45, 0.3]))
        (pxy, psize) = POST
        scene.add(FixedCuboid("/World/post", name="post", position=[*pxy, psize[2] / 2], size=1.0, scale=psize,
                              color=[0.8, 0.45, 0.1]))
        path = os.path.join(tempfile.mkdtemp(prefix="manip_cup_"), "cup.xml")
        with open(path, "w") as f:
            f.write(cup_mjcf())
        self.cup_prim = add_reference_to_stage(path, "/World/cup")
        self.cup_prim.position = CUP_START.copy()
        rng = np.random.default_rng(seed)
        self.marbles = []
        for i in range(marbles):  # stacked two by two inside the cup
            jitter = rng.uniform(-0.002, 0.002, 2)
            p = CUP_START + [0.011 * (1 if i % 2 else -1) + jitter[0], jitter[1], 0.016 + 0.021 * (i // 2)]
            self.marbles.append(scene.add(DynamicSphere(f"/World/marble{i}", name=f"marble{i}", position=p,
                                                        radius=MARBLE_RADIUS, mass=0.005, color=[0.2, 0.3, 0.9])))
        self.robot = scene.add(Franka("/World/Franka", name="franka"))
        self.world.reset()
        self.stiffen_grip()
        self.cup_body = mujoco.mj_name2id(self.world.model, mujoco.mjtObj.mjOBJ_BODY, "/World/cup/cup")
        self.controller = self.robot.get_articulation_controller()
        self.mg = MotionGenerator("franka", seed=seed, padding=PADDING)
        self._pin_model = self.mg.kinematics.model
        self._pin_data = self._pin_model.createData()
        self.max_tilt = 0.0  # the cup's, measured from the first motion on
        self.max_hand_tilt = 0.0  # the hand's cup axis, measured from the lift to the release
        self.stage_tilt: dict[str, float] = {}  # the largest measured tilt in each stage
        self.stage = "start"
        self._measuring = False
        # the hand's axis that holds the cup's axis: -x of the TCP in a side grasp (`side_grasp`);
        # once the cup is held, the cup's axis as measured in the hand (`hold`)
        self.upright = self.constraint((-1.0, 0.0, 0.0))

    def constraint(self, axis) -> OrientationConstraint:
        """`axis` (3,) of the TCP frame within tolerance - GRIP_BUDGET of the vertical."""
        return OrientationConstraint(axis=axis, direction=(0.0, 0.0, 1.0), tolerance=self.tolerance - GRIP_BUDGET,
                                     link=TCP)

    def stiffen_grip(self) -> None:
        """The finger pads' contacts stiffer (PAD_TIMECONST) and the friction cones (IMPRATIO):
        the cup held by friction then slips within GRIP_BUDGET (module docstring)."""
        m = self.world.model
        fingers = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"{self.robot.prim_path}/{name}")
                   for name in ("panda_leftfinger", "panda_rightfinger")]
        assert min(fingers) >= 0, "the Franka's finger bodies"
        m.geom_solref[np.isin(m.geom_bodyid, fingers), 0] = PAD_TIMECONST
        m.opt.impratio = IMPRATIO

    # ------------------------------------------------------------------ simulation
    def say(self, text: str) -> None:
        if self.verbose:
            print(f"  [{self.world.current_time:6.2f} s] {text}", flush=True)

    def q(self) -> np.ndarray:
        return self.robot.get_joint_positions()[:7].copy()

    def cup_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """(position of the cup's bottom centre (3,) [m], its rotation (3, 3)), measured."""
        d = self.world.data
        return d.xpos[self.cup_body].copy(), d.xmat[self.cup_body].reshape(3, 3).copy()

    def cup_tilt(self) -> float:
        """Angle [rad] between the cup's axis and the vertical, measured."""
        return float(np.arccos(np.clip(self.cup_pose()[1][2, 2], -1.0, 1.0)))

    def hand_tilt(self) -> float:
        """Angle [rad] between the constrained axis of the hand (`self.upright.axis`) and the vertical, measured."""
        _, q = self.robot.end_effector.get_world_pose()
        up = quat.to_matrix(np.asarray(q, dtype=float)) @ np.asarray(self.upright.axis)
        return float(np.arccos(np.clip(up[2], -1.0, 1.0)))

    def step(self, action: ArticulationAction | None = None) -> None:
        """One physics step with gravity compensation of the arm (as the flagship example)."""
        if action is not None:
            self.controller.apply_action(action)
        g = pin.computeGeneralizedGravity(self._pin_model, self._pin_data, self.q())
        self.robot.set_joint_efforts(g, joint_indices=np.arange(7))
        self.world.step(render=False)
        if self._measuring:
            if self.stage not in ("to cup", "approach", "close", "retreat"):  # the hand holds the cup upright
                self.max_hand_tilt = max(self.max_hand_tilt, self.hand_tilt())
            tilt = self.cup_tilt()
            self.max_tilt = max(self.max_tilt, tilt)
            self.stage_tilt[self.stage] = max(self.stage_tilt.get(self.stage, 0.0), tilt)

    def execute(self, stage: str, result) -> None:
        """Replay a planned trajectory (one action per physics step), then let the arm settle."""
        traj = result.trajectory
        self.stage = stage
        self.say(f"{stage:<10} motion {traj.duration:5.2f} s, planned tilt of the hand <= "
                 f"{self.upright.tilt(self.mg.kinematics, traj.positions).max():.3f} rad")
        for action in traj.to_articulation_actions(self.robot, physics_dt=self.world.get_physics_dt()):
            self.step(action)
        for _ in range(30):
            self.step()

    def gripper(self, width_each: float, stage: str) -> None:
        self.stage = stage
        idx = self.robot.gripper.joint_dof_indices
        self.controller.apply_action(ArticulationAction(joint_positions=[width_each, width_each], joint_indices=idx))
        for _ in range(60):
            self.step()

    def marbles_in_cup(self) -> int:
        """Spheres whose centre is inside the cup (measured)."""
        p, R = self.cup_pose()
        local = (np.array([m.get_world_pose()[0] for m in self.marbles]) - p) @ R
        radial = np.linalg.norm(local[:, :2], axis=1)
        return int(np.sum((radial < CUP_RADIUS) & (local[:, 2] > 0.0) & (local[:, 2] < CUP_HEIGHT)))

    # ------------------------------------------------------------------ the task
    def sync_world(self) -> None:
        """The planner's world: the shelves and the post (and the ground) from the simulator,
        the cup as a cylinder where it stands."""
        self.mg.update_world_from_sim(self.world, self.robot, ignore=["/World/cup", "/World/marble"])
        p, R = self.cup_pose()
        axis = R[:, 2]
        self.mg.add_obstacle(Cylinder("cup", CUP_RADIUS + CUP_WALL, CUP_HEIGHT,
                                      Pose(p + axis * CUP_HEIGHT / 2, quat.from_matrix(R))))

    def hold(self) -> None:
        """Constrain the cup's own axis from now on: its direction in the TCP frame, measured."""
        _, R = self.cup_pose()
        hand = self.mg.kinematics.fk(self.q(), TCP).rotation
        self.upright = self.constraint(hand.T @ R[:, 2])

    def run(self) -> bool:
        mg = self.mg
        for _ in range(180):  # the marbles settle
            self.step()
        self.sync_world()
        bottom, _ = self.cup_pose()
        centre = bottom + [0.0, 0.0, GRASP_HEIGHT]
        grasps = Pose.stack([side_grasp(centre, a) for a in 2 * np.pi * np.arange(CUP_SEGMENTS) / CUP_SEGMENTS])
        self._measuring = True
        grasp = mg.plan_grasp(self.q(), grasps, "cup", approach=0.10, lift=0.06, link=TCP,
                              constraints=(self.upright,))
        if not grasp.success:
            self.say(f"no grasp: {grasp.status.name}: {grasp.message}")
            return False
        self.say(f"grasp planned in {grasp.timings['total'] * 1e3:.0f} ms (candidate {grasp.grasp_index})")
        self.execute("to cup", grasp.segment("free"))
        self.execute("approach", grasp.segment("approach"))
        self.gripper(CUP_RADIUS + CUP_WALL - SQUEEZE, "close")
        mg.remove_obstacle("cup")
        p, R = self.cup_pose()
        mg.attach_object(Cylinder("cup", CUP_RADIUS + CUP_WALL, CUP_HEIGHT,
                                  Pose(p + R[:, 2] * CUP_HEIGHT / 2, quat.from_matrix(R))), q=self.q(), link=TCP)
        self.execute("lift", grasp.segment("lift"))
        self.hold()
        carry = {"velocity_scale": CARRY_SCALE, "acceleration_scale": CARRY_SCALE}
        goals = Pose.stack([Pose(CUP_GOAL + [0.0, 0.0, CUP_HEIGHT / 2 + 0.002], quat.from_axis_angle([0, 0, 1], a))
                            for a in np.arange(-2, 3) * np.pi / 6])
        place = mg.plan_place(self.q(), goals, retreat=0.08, approach=0.06, link=TCP, constraints=(self.upright,),
                              **carry)
        if not place.success:
            self.say(f"no placement: {place.status.name}: {place.message}")
            return False
        self.say(f"carry planned in {place.timings['total'] * 1e3:.0f} ms (placement {place.grasp_index})")
        self.execute("carry", place.segment("free"))
        self.execute("put down", place.segment("descend"))
        self.gripper(self.robot.gripper.joint_opened_positions[0], "open")
        mg.detach_object(self.q())
        self.execute("retreat", place.segment("retreat"))
        self._measuring = False
        for _ in range(60):
            self.step()
        return True

    def close(self) -> None:
        self.app.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tolerance", type=float, default=0.1,
                        help=f"Largest tilt of the cup [rad], measured (the plan keeps {GRIP_BUDGET} rad of it for the grip).")
    parser.add_argument("--marbles", type=int, default=6, help="Spheres in the cup (0-8).")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the marbles' placement and of the planning.")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's window (needs a display).")
    parser.add_argument("--quiet", action="store_true", help="Print no progress lines.")
    args = parser.parse_args(argv)
    if not 0 <= args.marbles <= 8:
        parser.error("--marbles must be in 0..8")
    if not GRIP_BUDGET < args.tolerance < 1.0:
        parser.error(f"--tolerance must be in ({GRIP_BUDGET}, 1) rad (GRIP_BUDGET of it is kept for the grip)")
    demo = CarryUpright(args.tolerance, args.marbles, viewer=args.viewer, seed=args.seed, verbose=not args.quiet)
    try:
        done = demo.run()
        bottom, _ = demo.cup_pose()
        on_b = bool(np.linalg.norm(bottom[:2] - CUP_GOAL[:2]) < 0.03 and abs(bottom[2] - CUP_GOAL[2]) < 0.01)
        kept = demo.marbles_in_cup()
        print(f"cup on shelf B: {'yes' if on_b else 'no'} ({bottom[0]:.3f}, {bottom[1]:.3f}, {bottom[2]:.3f}) m; "
              f"marbles in the cup: {kept}/{args.marbles}")
        print(f"measured tilt of the cup: max {demo.max_tilt:.4f} rad (tolerance {args.tolerance} rad; by stage: "
              + ", ".join(f"{k} {v:.4f}" for k, v in demo.stage_tilt.items()) + ")")
        print(f"measured tilt of the hand's constrained axis while it held the cup: max {demo.max_hand_tilt:.4f} rad "
              f"(planned within {demo.upright.tolerance:.3f} rad)")
    finally:
        demo.close()
    ok = done and on_b and kept == args.marbles and demo.max_tilt <= args.tolerance
    print("carried upright" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
