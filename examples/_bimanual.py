"""What `bimanual_handover.py` and `bimanual_carry.py` share: two simulated Frankas driven by one plan.

`Bimanual` holds a `manip.sim` World with two `Franka` robots (one per arm of the
`dual_franka` robot, Isaac's multi-robot pattern) and the `MotionGenerator` of the two arms
as one robot. It plans from the measured state (a failed plan is retried with a new seed),
splits each combined trajectory into each robot's ArticulationActions
(`trajectory.to_articulation_actions(robot)`), steps both robots together (their drives
get gravity compensation from the arm's Pinocchio model, as the real Panda's controller
does), drives the grippers, and checks what the fingers hold. Not an example itself (its
name starts with "_"); a module the two examples import.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from manip import ArticulationAction, Cuboid, MotionGenerator, Pose
from manip import quaternion as quat
from manip.kinematics import Kinematics
from manip.robot_config import load_robot_config

PLAN_TRIES = 3          # per motion, each from the measured state with a new seed
SETTLE_TOLERANCE = 0.01  # [rad] tracking error accepted at the end of a motion
LIMIT_SLACK = 1e-3      # [rad] a measured joint this little beyond a limit is planned from the limit
STATIC_STEPS = 6        # consecutive resting steps that count as at rest
FLOOR_CLEARANCE = 0.01  # [m] free-space motions keep the robot and what it holds this far above the ground


def floor_guard(hole_x=(-0.3, 0.15), hole_y=(-0.55, 0.55)) -> list[Cuboid]:
    """The planner-only floor: four 10 cm thick boxes, top FLOOR_CLEARANCE above the ground,
    around a hole where the two bases stand (the ground itself is left out of the planner's
    world: the grasps and releases happen on it)."""
    (x0, x1), (y0, y1), size, t = hole_x, hole_y, 3.0, 0.1
    z = FLOOR_CLEARANCE - t / 2
    return [
        Cuboid("floor_front", [size - x1, 2 * size, t], Pose(np.array([(size + x1) / 2, 0.0, z]))),
        Cuboid("floor_back", [size + x0, 2 * size, t], Pose(np.array([(x0 - size) / 2, 0.0, z]))),
        Cuboid("floor_left", [x1 - x0, size - y1, t], Pose(np.array([(x0 + x1) / 2, (size + y1) / 2, z]))),
        Cuboid("floor_right", [x1 - x0, size + y0, t], Pose(np.array([(x0 + x1) / 2, (y0 - size) / 2, z]))),
    ]


class MotionFailed(Exception):
    """A motion could not be planned, or the object is not where it should be."""


def hand_down(yaw: float) -> np.ndarray:
    """(w, x, y, z) of a hand pointing down (hand z = world -z), turned by `yaw` [rad] about world z."""
    return quat.multiply(quat.from_axis_angle([0.0, 0.0, 1.0], yaw), np.array([0.0, 1.0, 0.0, 0.0]))


@dataclass
class Arm:
    """One simulated Franka and its arm of the combined robot."""

    robot: object        # the manip.sim Franka
    columns: slice       # its joints in the combined configuration
    tcp: str             # its TCP link in the planner ("left_panda_hand_tcp")
    hand: str            # its hand link ("left_panda_hand")
    home: np.ndarray     # (7,) its default configuration [rad]


class Bimanual:
    """Two Frankas in a World, planned as one robot (see the module docstring).

    Args:
        world: the World (the two robots added, not yet reset).
        mg: the MotionGenerator of the two arms ("dual_franka").
        left, right: the two `Franka` robots, in the order of `mg.config.arms`.
        seed: seed of the plans.
        render: render each step (a viewer is open).
        verbose: print a line per motion.
    """

    def __init__(self, world, mg: MotionGenerator, left, right, *, seed: int, render: bool, verbose: bool):
        self.world, self.mg, self.seed, self.render, self.verbose = world, mg, int(seed), render, verbose
        self.arms = []
        for robot, arm in zip((left, right), mg.config.arms):
            cols = slice(*arm.columns)
            self.arms.append(Arm(robot, cols, arm.tcp_link, arm.ee_link, mg.default_joint_positions[cols].copy()))
        self._pin = Kinematics(load_robot_config("franka")).model   # one arm, fingers locked: its gravity torques
        self._pin_data = self._pin.createData()
        self._plan_seed = self.seed * 100_003
        self._floor = False

    # ------------------------------------------------------------------ state
    def say(self, text: str) -> None:
        if self.verbose:
            print(f"  [{self.world.current_time:7.2f} s] {text}", flush=True)

    def q(self) -> np.ndarray:
        """(14,) the measured configuration of both arms [rad], limits within LIMIT_SLACK put back on them."""
        q = np.concatenate([a.robot.get_joint_positions()[:7] for a in self.arms])
        lo, hi = self.mg.lower_limits, self.mg.upper_limits
        out = np.maximum(lo - q, q - hi)
        return np.where((out > 0) & (out < LIMIT_SLACK), np.clip(q, lo, hi), q)

    def tcp(self, arm: Arm) -> Pose:
        """The arm's TCP pose in the planner's base frame (= the world: the base is at the origin)."""
        return self.mg.fk(self.q(), arm.tcp)

    #: set by each example: the held object's name ("cube"), its place position (3,) [m] and
    #: the distance from it counted as placed [m]
    thing: str
    place: np.ndarray
    success: float

    def object_position(self) -> np.ndarray:
        raise NotImplementedError

    def start_pose(self, rng: np.random.Generator) -> None:
        """Put the object at the episode's seeded start pose (before it settles)."""
        raise NotImplementedError

    def run(self) -> None:
        """The episode's motions; raises MotionFailed when one cannot be planned or held."""
        raise NotImplementedError

    def episode(self, index: int) -> tuple[bool, float, str]:
        """One episode from a seeded start pose: (placed, final error [m], why not)."""
        self.reset()
        self.start_pose(np.random.default_rng([self.seed, index]))
        self.settle()
        why = ""
        try:
            self.run()
        except MotionFailed as exc:
            why = str(exc)
            self.say(f"FAILED: {why}")
        error = float(np.linalg.norm(self.object_position() - self.place))
        placed = error < self.success
        if not placed and not why:
            why = f"the {self.thing} rests {error * 100:.1f} cm from its place position"
        return placed, error, why

    def object_in_tcp(self, arm: Arm) -> np.ndarray:
        """(3,) the held object's centre in the arm's TCP frame [m] (measured)."""
        return self.tcp(arm).inverse().transform_points(self.object_position()[None])[0]

    # ------------------------------------------------------------------ stepping
    def step(self, actions=()) -> None:
        """One physics step after applying `actions` [(robot, ArticulationAction)], both arms'
        drives helped by their gravity torques."""
        for robot, action in actions:
            robot.get_articulation_controller().apply_action(action)
        for a in self.arms:
            g = pin.computeGeneralizedGravity(self._pin, self._pin_data, a.robot.get_joint_positions()[:7])
            a.robot.set_joint_efforts(g, joint_indices=np.arange(7))
        self.world.step(render=self.render)

    def settle(self, steps: int = 240) -> None:
        """Step until both arms are at rest (at most `steps`)."""
        calm = 0
        for _ in range(steps):
            qd = max(np.max(np.abs(a.robot.get_joint_velocities()[:7])) for a in self.arms)
            calm = calm + 1 if qd < 0.02 else 0
            if calm >= STATIC_STEPS:
                return
            self.step()

    def reset(self) -> None:
        """The World reset (both arms at home, fingers open), the planner's attachments dropped."""
        self.world.reset()
        for name in list(self.mg.checker.attached_objects):
            self.mg.detach_object(self.q(), name=name)
        self._plan_seed += 1009

    # ------------------------------------------------------------------ planning
    def sync_world(self, ignore=()) -> None:
        """The planner's obstacles := the World's (both robots, the ground and `ignore` left out)."""
        ground = [o.name for o in self.world.scene.get_collision_objects() if o.shape == "plane"]
        self.mg.update_world_from_sim(self.world, [a.robot for a in self.arms], ignore=[*ignore, *ground])
        self._floor = False

    def set_floor(self, on: bool) -> None:
        """The floor guard on for free-space motions, off for the straight lines down to the ground."""
        if on != self._floor:
            for box in floor_guard():
                self.mg.add_obstacle(box) if on else self.mg.remove_obstacle(box.name)
            self._floor = on

    def _plan(self, phase: str, call) -> object:
        last = None
        for attempt in range(PLAN_TRIES):
            self._plan_seed += 1
            r = call(self.q(), self._plan_seed)
            if r.success:
                self.say(f"{phase:<15} planned in {r.timings['total'] * 1e3:6.1f} ms, motion {r.trajectory.duration:5.2f} s")
                return r
            last = r
            self.say(f"{phase}: plan failed ({r.status.name}: {r.message})")
        raise MotionFailed(f"{phase}: no plan after {PLAN_TRIES} tries ({last.status.name}: {last.message})")

    def execute(self, result) -> None:
        """Replay a combined trajectory: each robot its own arm's actions, one per physics step."""
        traj = result.trajectory.resample(self.world.get_physics_dt())
        per_robot = [(a.robot, traj.to_articulation_actions(a.robot)) for a in self.arms]
        for k in range(traj.num_samples - 1):
            self.step([(robot, actions[k]) for robot, actions in per_robot])
        goal = traj.positions[-1]
        for _ in range(60):
            if np.max(np.abs(self.q() - goal)) < SETTLE_TOLERANCE:
                break
            self.step()

    def move_link(self, arm: Arm, goal: Pose, phase: str, linear: bool = False, **options) -> None:
        """Plan `arm`'s TCP to `goal` (the other arm held) and execute it."""
        self.set_floor(not linear)
        self.execute(self._plan(phase, lambda q, seed: self.mg.plan_pose(q, goal, link=arm.tcp, linear=linear,
                                                                         seed=seed, **options)))

    def move_links(self, goals: dict, phase: str, floor: bool = True, **options) -> None:
        """Plan several TCPs to their goals in one motion (`plan_poses`; `floor`: with the floor
        guard) and execute it."""
        self.set_floor(floor)
        self.execute(self._plan(phase, lambda q, seed: self.mg.plan_poses(q, goals, seed=seed, **options)))

    def move_home(self, arm: Arm, phase: str) -> None:
        """`arm` back to its default configuration (the other arm where it is)."""
        self.set_floor(True)
        def call(q, seed):
            goal = q.copy()
            goal[arm.columns] = arm.home
            return self.mg.plan_joints(q, goal, seed=seed)
        self.execute(self._plan(phase, call))

    # ------------------------------------------------------------------ hands
    def gripper(self, arm: Arm, width_each: float, phase: str) -> None:
        """Drive `arm`'s fingers to `width_each` [m] each and step until they stop."""
        robot = arm.robot
        action = ArticulationAction(joint_positions=[width_each, width_each], joint_indices=robot.gripper.joint_dof_indices)
        prev = robot.gripper.get_joint_positions()
        still = 0
        for k in range(90):
            self.step([(robot, action)] if k == 0 else [])
            f = robot.gripper.get_joint_positions()
            still = still + 1 if np.max(np.abs(f - prev)) < 2e-5 else 0
            prev = f
            if still >= 3 and k >= 5:
                break
        self.say(f"{phase:<15} fingers at {f[0] * 1e3:.1f} / {f[1] * 1e3:.1f} mm")

    def check_held(self, arm: Arm, width: float, when: str, point: np.ndarray | None = None) -> None:
        """Raise MotionFailed unless `point` (3,) [m] (default: the object's centre) is between
        `arm`'s fingertips and they are stopped on the object (`width` [m] across its gripped faces)."""
        point = self.object_position() if point is None else point
        local = self.tcp(arm).inverse().transform_points(np.asarray(point, dtype=float)[None])[0]
        f = arm.robot.gripper.get_joint_positions()
        if np.all(np.abs(local) < [0.03, 0.02, 0.03]) and np.all(f > width / 2 - 0.012) and np.all(f < width / 2 + 0.01):
            return
        raise MotionFailed(f"{when}: the object is not held by {arm.hand} (its centre at {np.round(local, 3).tolist()} m "
                           f"in the TCP frame, fingers at {np.round(f * 1e3, 1).tolist()} mm)")

    def attach(self, arm: Arm | tuple, name: str = "cube", dims=None) -> None:
        """The held object becomes the planner's, attached to `arm`'s hand (or to both hands)
        where the simulator has it now."""
        prim = self.world.scene.get_object(name)
        p, q = prim.get_world_pose()
        dims = np.asarray(dims if dims is not None else prim.get_size() * prim.get_local_scale(), dtype=float)
        link = tuple(a.hand for a in arm) if isinstance(arm, tuple) else arm.hand
        if name in [o.name for o in self.mg.world]:
            self.mg.remove_obstacle(name)   # detached earlier: replaced by where it is now
        self.mg.attach_object(Cuboid(name, dims, Pose(np.asarray(p, float), np.asarray(q, float))), q=self.q(), link=link)

    def detach(self) -> None:
        """The planner's attached objects back into its world where the arms hold them now."""
        self.mg.detach_object(self.q())

    def grasp_yaw(self, p: np.ndarray, qc: np.ndarray, arm: Arm) -> float:
        """A top grasp's hand yaw [rad] for a cube at p (3,) with orientation qc (wxyz): the yaw of one of
        its faces (modulo 90 deg) nearest the direction from the arm's base to the cube."""
        R = quat.to_matrix(qc)
        up = int(np.argmax(np.abs(R[2, :])))
        side = R[:, (up + 1) % 3]
        face = float(np.arctan2(side[1], side[0]))
        base = self.mg.config.arms[self.arms.index(arm)].base_pose.position
        azimuth = float(np.arctan2(p[1] - base[1], p[0] - base[0]))
        return azimuth + float((face - azimuth + np.pi / 4) % (np.pi / 2) - np.pi / 4)

    def close(self) -> None:
        self.app.close()


def run_episodes(make_demo: type[Bimanual], doc: str, argv: list[str] | None, *, things: str, done: str) -> int:
    """The examples' `main()`: the flags (--episodes, --seed, --viewer, --quiet), the episode
    loop (one line per episode: placed or not, the object's distance from its place position)
    and the summary; the exit status is 0 only when every episode placed the object.

    Args:
        make_demo: the example's `Bimanual` class, `Demo(seed, viewer=, verbose=)` (its `thing`
            names the object in the lines, its `success` is the distance counted as placed [m]).
        doc: the example's module docstring (its first paragraph is the description).
        things: the object's plural in the summary ("cubes"); done: what the summary says was
            done with them ("handed over and placed").
    """
    thing, success = make_demo.thing, make_demo.success
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--episodes", type=int, default=3, help="Episodes to run (default 3).")
    parser.add_argument("--seed", type=int, default=0, help=f"Seed of the {thing} poses and of the plans.")
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's viewer (it needs a display).")
    parser.add_argument("--quiet", action="store_true", help="Print only one line per episode and the summary.")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error("--episodes must be >= 1")
    demo = make_demo(args.seed, viewer=args.viewer, verbose=not args.quiet)
    placed = 0
    try:
        for k in range(args.episodes):
            t = time.perf_counter()
            ok, error, why = demo.episode(k)
            placed += ok
            print(f"episode {k}: {'placed' if ok else 'FAILED'}, {thing} {error * 1000:.1f} mm from its place "
                  f"position, "
                  f"{time.perf_counter() - t:.1f} s{'' if ok else ': ' + why}", flush=True)
    finally:
        demo.close()
    print(f"{placed}/{args.episodes} {things} {done} within {success * 100:.0f} cm")
    return 0 if placed == args.episodes else 1
