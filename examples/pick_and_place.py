"""Franka pick-and-place in MuJoCo, every motion planned by the MotionGenerator.

The Isaac Sim pick-and-place tutorial on a laptop: a Franka at the origin, a 5 cm cube on
the ground and a place position. The robot waits until the robot and the cube are at
rest, refreshes the planner's obstacles from the World, picks the cube (pre-grasp 15 cm
above it, gripper pointing down and turned to the cube's yaw, straight-line descent,
close, straight-line lift) and places it (pre-place, straight-line descent, open,
straight-line retreat, back to the wait pose). Whenever the cube lies more than 3 cm from
the place position and has come to rest, it is picked up and placed again.

    python examples/pick_and_place.py                       # 3 episodes, headless
    python examples/pick_and_place.py --episodes 10 --obstacles --seed 1
    python examples/pick_and_place.py --perturb --video pick.mp4 --plot joints.png
    python examples/pick_and_place.py --viewer              # interactive MuJoCo window
    python examples/pick_and_place.py --viewer web          # in the browser, served until Ctrl-C
    python examples/pick_and_place.py --perceive --obstacles  # obstacles only from two depth cameras
    python examples/pick_and_place.py --cube-size 0.07        # cubes of 3 to 7.8 cm

The physics is honest: the cube moves only by contact and friction with the fingers (no
welding, no teleporting; the script moves the cube itself only to start an episode and,
with --perturb, to play the person who moves it away). Every motion is a MotionGenerator
trajectory replayed as one ArticulationAction per 1/60 s step; the arm's PD drives also get
gravity compensation from the robot model, as on the real Panda. The planner sees the
World's objects except the robot, the ground and the cube, keeps 1 cm from obstacles, and a
floor guard 1 cm above the ground keeps free-space motions off the floor (with --perceive, the
planner sees only what two depth cameras see: examples/perception_rig.py). A failed plan is
retried from the measured state with a new seed; the grasp is checked before the cube is
attached to the planner's hand (the cube must be between the closed fingers: a cube that
was pushed or moved away is reported as a failed grasp, with where it is, and picked up
again); a cube that is not between the fingers after the lift is picked up again; an
episode fails after a bounded number of tries, with the reason printed. The exit status is
0 only when every episode ends with the cube within 1 cm of the place position.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from manip import ArticulationAction, Cuboid, MotionGenerator, PlanStatus, Pose
from manip import quaternion as quat
from manip.sim import (
    FixedCuboid,
    OffscreenRenderingError,
    PickPlace,
    SimulationApp,
    SimulationError,
    VisualCuboid,
    World,
    create_new_stage,
)

# ---------------------------------------------------------------------------- the task
CUBE_SIZE = 0.05  # [m]
MIN_CUBE_SIZE, MAX_CUBE_SIZE = 0.03, 0.078  # [m] cubes the gripper grasps (it opens to 0.08 m; 1 mm a side)
PLACE_POSITION = np.array([0.40, -0.35, CUBE_SIZE / 2])  # the PickPlace task's default target [m]
PICK_AREA_X = (0.35, 0.65)  # [m] where episodes put the cube
PICK_AREA_Y = (-0.35, 0.35)
MIN_DISTANCE_TO_PLACE = 0.15  # [m] random cubes start at least this far from the place position
REPICK_DISTANCE = 0.03  # [m] a resting cube farther than this from the place position is picked again
SUCCESS_TOLERANCE = 0.01  # [m] placed = final cube centre within this of the place position
#: --video's measured cost (`--episodes 1`, 4.9 s simulated: 61.3 s of wall time with
#: `--video`, 0.70 s without; EGL on Mesa's software renderer, 2-core VM, 2026-11-28).
VIDEO_COST = ("12 s of wall time per simulated second (0.08x real time, against 7x without a video; measured with "
              "software OpenGL on a 2-core VM)")

APPROACH_HEIGHT = 0.15  # [m] pre-grasp / pre-place / lift height of the TCP above the grasp
GRASP_HEIGHT = 0.003  # [m] TCP this far above the cube centre at the grasp (raised by `grasp_height`)
#: The hand's geometry the grasp height keeps clear (measured with plan_grasp at PADDING = 1 cm:
#: the palm's lowest point 36 mm above the TCP, the fingertips 10 mm below it).
PALM_ABOVE_TCP = 0.036  # [m]
FINGERTIP_BELOW_TCP = 0.010  # [m]
GRASP_MARGIN = 0.002  # [m] kept beyond PADDING by the palm (cube top) and the fingertips (ground)
RELEASE_HEIGHT = 0.003  # [m] cube bottom this far above the ground when the fingers open
RETREAT_HEIGHT = 0.10  # [m] straight up after releasing
PADDING = 0.01  # [m] clearance the planner keeps from obstacles
FLOOR_CLEARANCE = 0.01  # [m] free-space motions keep the robot and the held cube this far above the ground
SQUEEZE = 0.01  # [m] each finger's target is this far inside the cube face (~15 N grip per finger)
CARRY_SCALE = 0.5  # velocity and acceleration scale of the motions that carry the cube
TCP = "panda_hand_tcp"
LINEAR_STEP = 0.02  # [m] spacing of the IK points of straight-line motions (the result is checked densely)

# Tries before an episode is declared failed.
PLAN_TRIES = 3  # per motion, each from the current state with a new seed
PICK_TRIES = 3  # pick-and-place cycles per episode (a dropped cube is picked again)

# Waiting for rest.
STATIC_LINEAR = 0.005  # [m/s] cube speed below which it counts as resting
STATIC_ANGULAR = 0.05  # [rad/s]
STATIC_JOINT = 0.02  # [rad/s] arm joint speed
STATIC_STEPS = 6  # consecutive resting steps
MAX_WAIT = 4.0  # [s] of simulated time
SETTLE_TOLERANCE = 0.01  # [rad] tracking error accepted at the end of a motion
LIMIT_SLACK = 1e-3  # [rad] a measured joint this little beyond a limit is planned from the limit


def hand_down(yaw: float) -> np.ndarray:
    """Quaternion (w, x, y, z) of the hand pointing down (hand z = world -z), turned by `yaw`
    [rad] about world z: R = Rz(yaw) Rx(pi)."""
    return quat.multiply(quat.from_axis_angle([0.0, 0.0, 1.0], yaw), np.array([0.0, 1.0, 0.0, 0.0]))


def cube_yaw(q_cube: np.ndarray) -> float:
    """Yaw [rad] of a resting cube: the heading of whichever of its axes lies closest to
    horizontal-and-first, folded into [-pi/4, pi/4] (a cube is symmetric modulo 90 deg)."""
    R = quat.to_matrix(q_cube)
    up = int(np.argmax(np.abs(R[2, :])))  # the axis that points (most) vertically
    side = R[:, (up + 1) % 3]
    return fold_quarter(float(np.arctan2(side[1], side[0])))


def fold_quarter(angle: float) -> float:
    """`angle` [rad] modulo pi/2, in [-pi/4, pi/4)."""
    return float((angle + np.pi / 4) % (np.pi / 2) - np.pi / 4)


def grasp_height(size: float) -> float:
    """TCP height [m] above the centre of a resting cube of edge `size` [m] at the grasp:
    GRASP_HEIGHT, raised so the palm keeps PADDING + GRASP_MARGIN above a tall cube's top and
    the fingertips as much above the ground beside a small cube (a 3 cm cube: 7 mm, 7 cm: 11 mm)."""
    return max(GRASP_HEIGHT, size / 2 + PADDING + GRASP_MARGIN - PALM_ABOVE_TCP,
               FINGERTIP_BELOW_TCP + PADDING + GRASP_MARGIN - size / 2)


def grasp_yaw(cube_position: np.ndarray, cube_orientation: np.ndarray) -> float:
    """Hand yaw [rad] for a top grasp: the cube's yaw modulo 90 deg, taken nearest to the
    direction from the robot base to the cube (the least wrist twist for the arm)."""
    azimuth = float(np.arctan2(cube_position[1], cube_position[0]))
    return azimuth + fold_quarter(cube_yaw(cube_orientation) - azimuth)


# ---------------------------------------------------------------------------- scene
def _perception_rig():
    """examples/perception_rig.py (the --perceive cameras), loaded beside this file."""
    import importlib.util

    path = Path(__file__).resolve().with_name("perception_rig.py")
    spec = importlib.util.spec_from_file_location("perception_rig", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def obstacle_boxes(seed: int) -> list[tuple[str, np.ndarray, np.ndarray, float]]:
    """A few fixed boxes between and around the pick area and the place position.

    Returns:
        [(name, centre (3,) [m], full edge lengths (3,) [m], yaw [rad])], jittered by `seed`.
    """
    rng = np.random.default_rng([seed, 7919])
    layout = [  # name, centre x, y, size x, y, z
        ("wall", 0.60, -0.27, 0.12, 0.05, 0.22),  # between the pick area and the place position
        ("post", 0.36, -0.57, 0.08, 0.08, 0.35),  # behind the place position
        ("block", 0.80, 0.05, 0.08, 0.25, 0.26),  # beyond the pick area
    ]
    out = []
    for name, x, y, sx, sy, sz in layout:
        c = np.array([x, y, 0.0]) + np.append(rng.uniform(-0.02, 0.02, 2), 0.0)
        c[2] = sz / 2
        out.append((name, c, np.array([sx, sy, sz]), float(rng.uniform(-0.25, 0.25))))
    return out


def floor_guard() -> list[Cuboid]:
    """The planner-only floor (robot base frame): four 10 cm thick boxes, top FLOOR_CLEARANCE
    above the ground, around a hole x in [-0.3, 0.15] m, |y| <= 0.15 m where the base stands."""
    x0, x1, hy, size, t = -0.3, 0.15, 0.15, 2.0, 0.1
    z = FLOOR_CLEARANCE - t / 2
    return [
        Cuboid("floor_guard_front", [size - x1, 2 * size, t], Pose(np.array([(size + x1) / 2, 0.0, z]))),
        Cuboid("floor_guard_back", [size + x0, 2 * size, t], Pose(np.array([(x0 - size) / 2, 0.0, z]))),
        Cuboid("floor_guard_left", [x1 - x0, size - hy, t], Pose(np.array([(x0 + x1) / 2, (size + hy) / 2, z]))),
        Cuboid("floor_guard_right", [x1 - x0, size - hy, t], Pose(np.array([(x0 + x1) / 2, -(size + hy) / 2, z]))),
    ]


def _box_clearance(p: np.ndarray, boxes) -> float:
    """Smallest horizontal distance [m] from point p (xy) to the footprints of `boxes`."""
    best = np.inf
    for _, c, dims, yaw in boxes:
        d = p[:2] - c[:2]
        cy, sy = np.cos(-yaw), np.sin(-yaw)
        local = np.array([cy * d[0] - sy * d[1], sy * d[0] + cy * d[1]])
        outside = np.maximum(np.abs(local) - dims[:2] / 2, 0.0)
        best = min(best, float(np.linalg.norm(outside)))
    return best


def random_cube_pose(rng: np.random.Generator, boxes=(), size: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A random resting cube pose in the pick area: (position (3,) [m], quaternion (4,) wxyz)
    of a cube of edge `size` [m] (default CUBE_SIZE).

    At least MIN_DISTANCE_TO_PLACE from the place position and 10 cm (horizontally) from
    the obstacles, so that the open gripper fits around the cube.
    """
    for _ in range(1000):
        p = np.array([rng.uniform(*PICK_AREA_X), rng.uniform(*PICK_AREA_Y), (size or CUBE_SIZE) / 2])
        yaw = rng.uniform(-np.pi, np.pi)
        if np.linalg.norm(p[:2] - PLACE_POSITION[:2]) < MIN_DISTANCE_TO_PLACE:
            continue
        if boxes and _box_clearance(p, boxes) < 0.10:
            continue
        return p, quat.from_axis_angle([0.0, 0.0, 1.0], yaw)
    raise RuntimeError("no free cube position in the pick area")  # unreachable with the built-in layout


# ---------------------------------------------------------------------------- results
@dataclass
class EpisodeResult:
    """What one episode did (all times in seconds)."""

    index: int
    placed: bool
    error: float  # final distance of the cube centre to the place position [m] (from the simulator)
    plan_time: float = 0.0  # wall time inside the MotionGenerator
    motion_time: float = 0.0  # duration of the executed trajectories (simulated)
    sim_time: float = 0.0  # simulated time of the whole episode
    wall_time: float = 0.0  # wall time of the whole episode
    picks: int = 0  # pick-and-place cycles started
    plans: int = 0  # successful plans
    failed_plans: int = 0
    obstacle_contact_steps: int = 0  # physics steps in which anything touched an obstacle box
    slip: float = 0.0  # largest shift of the cube in the hand between the lift and the release [m]
    reason: str = ""  # why it failed (empty when placed)
    log: list[str] = field(default_factory=list)


class PlanningFailed(Exception):
    """A motion could not be planned within PLAN_TRIES (carries the last status)."""


class CubeDropped(Exception):
    """The cube is no longer between the fingers."""


class GraspFailed(CubeDropped):
    """The fingers closed without the cube between them (it moved, or was never there)."""


# ---------------------------------------------------------------------------- the demo
class PickAndPlace:
    """The scene, the planner and the pick-and-place loop.

    Args:
        seed: seed of cube poses, obstacle jitter and planning.
        obstacles: add fixed boxes the motions must avoid.
        cube_mass: [kg].
        viewer: "native" (or True): open MuJoCo's interactive viewer (needs a display);
            "web": show the World in the browser ("manip-robotics[viz]"); False/None: headless.
        video: path of an MP4 to record (offscreen), or None.
        verbose: print a progress line per phase.
        record_joints: keep the trajectories executed in the current episode (for --plot).
        cube_size: the cube's edge [m], MIN_CUBE_SIZE to MAX_CUBE_SIZE (the open gripper's
            width less its clearance); default CUBE_SIZE.

    Raises:
        ValueError: a cube size the gripper cannot grasp (says the valid range).
    """

    def __init__(self, seed: int = 0, obstacles: bool = False, cube_mass: float = 0.05, viewer: bool | str = False,
                 video: str | None = None, verbose: bool = True, record_joints: bool = False, perceive: bool = False,
                 cube_size: float = CUBE_SIZE):
        if not MIN_CUBE_SIZE <= cube_size <= MAX_CUBE_SIZE:
            raise ValueError(f"cube_size {cube_size} m: the Franka's gripper grasps cubes of {MIN_CUBE_SIZE} to "
                             f"{MAX_CUBE_SIZE} m (it opens to 0.08 m: 1 mm of clearance a side)")
        self.cube_size = float(cube_size)
        self.seed = int(seed)
        self.verbose = verbose
        self.record_joints = record_joints
        self.render = viewer or video is not None
        self.app = SimulationApp({"headless": not viewer, "viewer": "web" if viewer == "web" else "native"})
        World.clear_instance()  # a fresh World and stage (also when called again in one process)
        create_new_stage()
        self.world = World(physics_dt=1.0 / 60.0)
        self.task = PickPlace(target_position=self.place_position, cube_size=self.cube_size, cube_mass=cube_mass,
                              success_tolerance=SUCCESS_TOLERANCE)
        self.world.add_task(self.task)
        self.boxes = obstacle_boxes(seed) if obstacles else []
        box_prims = []
        for name, c, dims, yaw in self.boxes:
            box_prims.append(FixedCuboid(f"/World/Obstacles/{name}", name=name, position=c, size=1.0, scale=dims,
                                         orientation=quat.from_axis_angle([0, 0, 1], yaw), color=[0.8, 0.45, 0.1]))
            self.world.scene.add(box_prims[-1])
        # A flat green square on the ground marks the place position (drawn only, no collision).
        self.world.scene.add(VisualCuboid("/World/PlaceMarker", name="place_marker", size=1.0,
                                          position=self.place_position * [1, 1, 0] + [0, 0, 0.0005],
                                          scale=[self.cube_size + 0.01, self.cube_size + 0.01, 0.001], color=[0.1, 0.8, 0.2]))
        # --perceive: two depth cameras, the planner's only source of obstacles (examples/perception_rig.py)
        self.rig = _perception_rig().CameraRig() if perceive else None
        self.world.reset()
        self._box_mask = None  # geoms of the obstacle boxes (to count contacts with them)
        if box_prims:
            self._box_mask = np.zeros(self.world.model.ngeom, dtype=bool)
            self._box_mask[[b.geom_id for b in box_prims]] = True
        self.world.set_camera_view(eye=[1.5, -1.25, 1.1], target=[0.3, -0.1, 0.2])
        self.robot = self.task.robot
        self.cube = self.task.cube
        self.controller = self.robot.get_articulation_controller()
        self.arm = np.arange(7)
        # 1 cm of clearance from the obstacles: the arm tracks its trajectories within a few
        # mm, and MuJoCo collides with the convex hulls of the link meshes.
        self.mg = MotionGenerator("franka", seed=seed, time_budget=2.0, padding=PADDING)
        self.wait_q = self.mg.default_joint_positions
        self._pin_model = self.mg.kinematics.model
        self._pin_data = self._pin_model.createData()
        self.ground = [o.name for o in self.world.scene.get_collision_objects() if o.shape == "plane"]
        self._plan_seed = self.seed * 100_003
        if video is not None:
            self.world.start_recording(video)
        self._ep: EpisodeResult | None = None
        self._floor_on = False
        self.trajectory_log: list = []  # Trajectories executed in the current episode (record_joints)

    # ------------------------------------------------------------------ helpers
    @property
    def place_position(self) -> np.ndarray:
        """(3,) [m] where the cube's centre is put: PLACE_POSITION's x, y, the cube resting on the ground."""
        return np.array([PLACE_POSITION[0], PLACE_POSITION[1], self.cube_size / 2])

    def say(self, text: str) -> None:
        if self._ep is not None:
            self._ep.log.append(text)
        if self.verbose:
            print(f"  [{self.world.current_time:7.2f} s] {text}", flush=True)

    def step(self, action: ArticulationAction | None = None) -> None:
        """One physics step (1/60 s), after applying `action` (arm joint targets) if given.

        Like the real Panda's controller, the arm's drives also get a gravity-compensation
        torque computed from the robot model (Pinocchio) at the measured configuration, so
        the PD drives track without sagging under gravity.
        """
        if action is not None:
            self.controller.apply_action(action)
        g = pin.computeGeneralizedGravity(self._pin_model, self._pin_data, self.q())
        self.robot.set_joint_efforts(g, joint_indices=self.arm)
        self.world.step(render=self.render)
        if self._box_mask is not None and self._ep is not None:
            d = self.world.data
            if d.ncon and self._box_mask[d.contact.geom[: d.ncon]].any():
                self._ep.obstacle_contact_steps += 1

    def q(self) -> np.ndarray:
        """Measured arm joint positions (7,) [rad]."""
        return self.robot.get_joint_positions()[:7].copy()

    def planning_start(self) -> np.ndarray:
        """The measured arm configuration (7,) as a planning start [rad].

        A joint that a plan drove to its limit may rest a few microradians beyond it (the
        drive's overshoot), which the planner rejects as a start outside the limits: such
        tiny excursions (< LIMIT_SLACK) are put back on the limit.
        """
        q = self.q()
        lo, hi = self.mg.lower_limits, self.mg.upper_limits
        out = np.maximum(lo - q, q - hi)
        if np.any((out > 0) & (out < LIMIT_SLACK)):
            q = np.where(out < LIMIT_SLACK, np.clip(q, lo, hi), q)
        return q

    def cube_pose(self) -> tuple[np.ndarray, np.ndarray]:
        p, q = self.cube.get_world_pose()
        return np.asarray(p, dtype=float), np.asarray(q, dtype=float)

    def tcp_pose(self) -> Pose:
        p, q = self.robot.end_effector.get_world_pose()
        return Pose(np.asarray(p, dtype=float), np.asarray(q, dtype=float))

    def fingers(self) -> np.ndarray:
        return self.robot.gripper.get_joint_positions()

    def is_static(self) -> bool:
        v = np.linalg.norm(self.cube.get_linear_velocity())
        w = np.linalg.norm(self.cube.get_angular_velocity())
        qd = np.max(np.abs(self.robot.get_joint_velocities()[:7]))
        return v < STATIC_LINEAR and w < STATIC_ANGULAR and qd < STATIC_JOINT

    def wait_static(self) -> bool:
        """Step until the robot and the cube are at rest (True), at most MAX_WAIT."""
        calm = 0
        for _ in range(int(MAX_WAIT * 60)):
            calm = calm + 1 if self.is_static() else 0
            if calm >= STATIC_STEPS:
                return True
            self.step()
        return False

    def sync_obstacles(self, ground: bool = False) -> None:
        """The planner's world := the World's collision objects (robot and cube ignored; the
        ground too unless `ground`: the grasp and place sequences keep the robot off it, and
        may let the cube touch it where it lies or is put down); with --perceive, what the
        cameras see instead (`refresh_map`)."""
        if self.rig is not None:
            self.set_floor_guard(False)   # as the rebuilt world below: no guard (the grasp goes down to the floor)
            self.refresh_map()
            return
        ignore = [self.cube.prim_path, self.cube.name, *([] if ground else self.ground)]
        self.mg.update_world_from_sim(self.world, self.robot, ignore=ignore)
        self._floor_on = False

    def refresh_map(self) -> None:
        """--perceive: both depth cameras into the planner's occupancy map, the cube left out."""
        state = np.concatenate([self.planning_start(), self.fingers()])   # the fingers where they are
        self.rig.refresh(self.mg, state, Pose(*self.robot.get_world_pose()), Pose(*self.cube_pose()), self.cube_size)

    def set_floor_guard(self, on: bool) -> None:
        """Add (or remove) the planner's floor guard: boxes whose top is FLOOR_CLEARANCE above
        the ground, everywhere but around the robot's base.

        The ground itself is ignored (the grasp and the release happen at it, and the base
        stands on it), but without a floor a free-space motion may sweep the hand or the
        carried cube along the ground. The guard is on for free-space motions and off for
        the vertical straight-line ones that go down to the cube or the place position.
        """
        if on == self._floor_on:
            return
        for box in floor_guard():
            if on:
                self.mg.add_obstacle(box)
            else:
                self.mg.remove_obstacle(box.name)
        self._floor_on = on

    # ------------------------------------------------------------------ motions
    def plan(self, phase: str, goal: Pose | np.ndarray, linear: bool = False, **options):
        """Plan from the measured state (retried with new seeds); raises PlanningFailed."""
        last = None
        for attempt in range(PLAN_TRIES):
            self._plan_seed += 1
            if self.rig is not None:
                self.refresh_map()   # the map as the cameras see the World now
            start = self.planning_start()
            self.set_floor_guard(not linear)
            if isinstance(goal, Pose) and linear:
                # Coarse IK points first (faster); the planner's finer default where the arm
                # turns quickly along the line.
                r = self.mg.plan_pose(start, goal, link=TCP, linear=True, seed=self._plan_seed,
                                      linear_step=LINEAR_STEP, **options)
                if r.status is PlanStatus.LINEAR_PATH_FAIL:
                    self._ep.plan_time += r.timings.get("total", 0.0)
                    r = self.mg.plan_pose(start, goal, link=TCP, linear=True, seed=self._plan_seed, **options)
            elif isinstance(goal, Pose):
                r = self.mg.plan_pose(start, goal, link=TCP, seed=self._plan_seed, **options)
            else:
                r = self.mg.plan_joints(start, goal, seed=self._plan_seed, **options)
            self._ep.plan_time += r.timings.get("total", 0.0)
            if r.success:
                self._ep.plans += 1
                return r
            self._ep.failed_plans += 1
            last = r
            self.say(f"{phase}: plan failed ({r.status.name}: {r.message}); retry {attempt + 1}/{PLAN_TRIES - 1}"
                     if attempt + 1 < PLAN_TRIES else f"{phase}: plan failed ({r.status.name}: {r.message})")
        raise PlanningFailed(f"{phase}: no plan after {PLAN_TRIES} tries ({last.status.name}: {last.message})")

    def execute(self, result) -> None:
        """Replay a planned trajectory, one ArticulationAction per physics step, then let the
        arm settle on the final target."""
        traj = result.trajectory
        if self.record_joints:
            self.trajectory_log.append(traj)
        for action in traj.to_articulation_actions(self.robot, physics_dt=self.world.get_physics_dt()):
            self.step(action)
        self._ep.motion_time += traj.duration
        goal = traj.positions[-1]
        for _ in range(60):
            qd = self.robot.get_joint_velocities()[:7]
            if np.max(np.abs(self.q() - goal)) < SETTLE_TOLERANCE and np.max(np.abs(qd)) < 0.05:
                break
            self.step()

    def move(self, phase: str, goal: Pose | np.ndarray, linear: bool = False, **options) -> None:
        r = self.plan(phase, goal, linear=linear, **options)
        self.say(f"{phase:<12} planned in {r.timings['total'] * 1e3:6.1f} ms, motion {r.trajectory.duration:5.2f} s")
        self.execute(r)

    def gripper(self, width_each: float, phase: str) -> None:
        """Drive both fingers to `width_each` [m] and step until they stop (stall or arrive)."""
        idx = self.robot.gripper.joint_dof_indices
        self.controller.apply_action(ArticulationAction(joint_positions=[width_each, width_each], joint_indices=idx))
        prev = self.fingers()
        still = 0
        for k in range(90):
            self.step()
            f = self.fingers()
            still = still + 1 if np.max(np.abs(f - prev)) < 2e-5 else 0
            prev = f
            if still >= 3 and k >= 5:
                break
        self.say(f"{phase:<12} fingers at {f[0] * 1e3:.1f} / {f[1] * 1e3:.1f} mm")

    def holding(self) -> bool:
        """The cube is between the fingertips (measured in the simulator)."""
        return self.grasp_problem() is None

    def grasp_problem(self, planned: np.ndarray | None = None) -> str | None:
        """Why the cube is not held between the fingertips (measured in the simulator), or None.

        Held: the cube's centre within 3 cm (along the fingers' width and the hand's axis)
        and 2 cm (between the fingers) of the TCP, and each finger stopped by the cube
        (open between its target, SQUEEZE inside the face, and 1 cm outside the face: 15-35 mm
        for a 5 cm cube). `planned`: where the cube was (3,) [m] when the
        grasp was planned, to say how far it moved since.
        """
        p, _ = self.cube_pose()
        tcp = self.tcp_pose()
        local = tcp.inverse().transform_points(p[None])[0]
        f = self.fingers()
        between = bool(np.all(np.abs(local) < [0.03, 0.02, 0.03]))
        gripped = bool(np.all(f > self.cube_size / 2 - SQUEEZE) and np.all(f < self.cube_size / 2 + 0.01))
        if between and gripped:
            return None
        where = (f"its centre is {np.linalg.norm(local) * 100:.1f} cm from the TCP (at "
                 f"({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m)")
        if planned is not None and np.linalg.norm(p - planned) > 0.01:
            where += f", {np.linalg.norm(p - planned) * 100:.1f} cm from where the grasp was planned"
        fingers = f"the fingers are at {f[0] * 1e3:.1f} / {f[1] * 1e3:.1f} mm"
        if not between:
            return f"the cube is not between the fingers: {where}; {fingers}"
        if np.any(f <= self.cube_size / 2 - SQUEEZE):
            return f"the fingers closed past the cube's faces ({fingers}): it is not gripped"
        return f"the fingers did not close on the cube ({fingers})"

    def cube_in_tcp(self) -> np.ndarray:
        """(3,) the cube's centre in the TCP frame [m] (measured)."""
        return self.tcp_pose().inverse().transform_points(self.cube_pose()[0][None])[0]

    def release_position(self, hand_q: np.ndarray) -> np.ndarray:
        """TCP position (3,) [m] that puts the held cube's centre RELEASE_HEIGHT above the
        place position with the hand at orientation `hand_q` (wxyz). Uses where the cube
        sits in the hand now (measured; it may have shifted while closing or moving)."""
        in_tcp = self.cube_in_tcp()
        return self.place_position + [0.0, 0.0, RELEASE_HEIGHT] - quat.to_matrix(hand_q) @ in_tcp

    def grasp_candidates(self, p: np.ndarray, qc: np.ndarray) -> tuple[Pose, np.ndarray]:
        """The top grasps of a resting cube at p (3,) [m], orientation qc (wxyz): the hand
        pointing down at the cube's four symmetric yaws (`grasp_yaw`, the least wrist turn,
        first). `plan_grasp` takes the one with the fastest feasible sequence: a wrist that
        turns less moves faster, so the least turn wins unless the hand would hit something.

        Returns:
            (a batched Pose of the TCP (4 poses), their yaws (4,) [rad]).
        """
        yaws = grasp_yaw(p, qc) + np.array([0.0, 1.0, -1.0, 2.0]) * np.pi / 2
        return Pose.stack([Pose(p + [0.0, 0.0, grasp_height(self.cube_size)], hand_down(y)) for y in yaws]), yaws

    def place_candidates(self) -> Pose:
        """Goal poses of the held cube (a batched Pose): its centre RELEASE_HEIGHT above the
        place position, its measured orientation turned about the vertical by multiples of
        45 deg (a cube's faces repeat every 90 deg: these let `plan_place` pick the smallest
        wrist turn)."""
        _, qc = self.cube_pose()
        centre = self.place_position + [0.0, 0.0, RELEASE_HEIGHT]
        return Pose.stack([Pose(centre, quat.multiply(quat.from_axis_angle([0, 0, 1], a), qc))
                           for a in np.arange(-3, 5) * np.pi / 4])

    def plan_task(self, phase: str, plan_fn, **options):
        """`plan_fn(start, seed=..., **options)` (a plan_grasp / plan_place call) from the measured
        state, retried with new seeds like `plan` (the straight-line stages with IK points every
        LINEAR_STEP, the last try at the planner's finer default); raises PlanningFailed."""
        last = None
        for attempt in range(PLAN_TRIES):
            self._plan_seed += 1
            step = {"linear_step": LINEAR_STEP} if attempt + 1 < PLAN_TRIES else {}
            r = plan_fn(self.planning_start(), seed=self._plan_seed, **step, **options)
            self._ep.plan_time += r.timings.get("total", 0.0)
            if r.success:
                self._ep.plans += 1
                self.say(f"{phase:<12} {len(r.stages)} stages planned in {r.timings['total'] * 1e3:6.1f} ms, "
                         f"candidate {r.grasp_index}")
                return r
            self._ep.failed_plans += 1
            last = r
            self.say(f"{phase}: plan failed ({r.status.name}: {r.message})")
        raise PlanningFailed(f"{phase}: no plan after {PLAN_TRIES} tries ({last.status.name}: {last.message})")

    def run_stage(self, phase: str, result) -> None:
        """Execute one stage of a GraspPlan (re-planned from the measured state by `move` when
        the arm is not where the stage starts)."""
        if np.max(np.abs(self.q() - result.trajectory.positions[0])) > SETTLE_TOLERANCE:
            goal = self.mg.fk(result.goal_q, TCP)
            self.move(phase, goal if result.source == "linear" else result.goal_q, linear=result.source == "linear")
            return
        self.say(f"{phase:<12} motion {result.trajectory.duration:5.2f} s")
        self.execute(result)

    # ------------------------------------------------------------------ one pick and place
    def pick_and_place(self) -> None:
        """Pick the cube where it lies and put it at the place position (raises on failure).

        The grasp (`MotionGenerator.plan_grasp`: free motion to the pre-grasp, straight down
        with only the fingers allowed to touch the cube, lift) and the place (`plan_place`:
        free motion to above the place position, straight down, release, straight up) are
        each planned as one sequence, with the ground and the cube in the planner's world.
        The lift is planned again from the measured state once the grasp is checked.
        """
        mg = self.mg
        self.sync_obstacles()
        p, qc = self.cube_pose()
        T_base_world = Pose(*self.robot.get_world_pose()).inverse()
        grasps, yaws = self.grasp_candidates(p, qc)
        self.sync_obstacles(ground=True)
        mg.add_obstacle(Cuboid("cube", [self.cube_size] * 3, T_base_world @ Pose(p, qc)))
        try:
            grasp = self.plan_task("grasp", lambda q, **o: mg.plan_grasp(q, grasps, "cube", approach=APPROACH_HEIGHT,
                                                                         lift=APPROACH_HEIGHT, link=TCP, **o))
        except Exception:
            mg.remove_obstacle("cube")  # (a --perceive sync keeps the planner's other obstacles)
            raise
        yaw = float(yaws[grasp.grasp_index])
        down = hand_down(yaw)
        self.say(f"cube at ({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m, yaw {np.degrees(cube_yaw(qc)):.0f} deg, "
                 f"hand yaw {np.degrees(yaw):.0f} deg; {len(mg.world)} obstacles")
        if grasp.grasp_index:
            turn = int(round(np.degrees(yaw - yaws[0])))
            self.say(f"grasp turned by {turn} deg: {grasp.message or 'a faster motion than at the preferred yaw'}")
        self.run_stage("pre-grasp", grasp.segment("free"))
        self.run_stage("descend", grasp.segment("approach"))
        mg.remove_obstacle("cube")
        self.sync_obstacles()
        self.gripper(self.cube_size / 2 - SQUEEZE, "close")
        # Check the grasp before the cube becomes the planner's attached object: a cube that
        # moved away (pushed, or moved by someone) would be attached where it is, far from
        # the hand, and every later plan would fail for a reason that is not the real one.
        problem = self.grasp_problem(planned=p)
        if problem is not None:
            raise GraspFailed(f"grasp failed after closing: {problem}")
        # The cube as the planner's attached object, where the simulator has it now.
        p, qc = self.cube_pose()
        cube = Cuboid("cube", [self.cube_size] * 3, T_base_world @ Pose(p, qc))
        mg.attach_object(cube, q=self.planning_start(), link="panda_hand")
        try:
            carry = {"velocity_scale": CARRY_SCALE, "acceleration_scale": CARRY_SCALE}
            self.move("lift", Pose(self.tcp_pose().position + [0.0, 0.0, APPROACH_HEIGHT], down), linear=True, **carry)
            problem = self.grasp_problem()
            if problem is not None:
                raise CubeDropped(f"after the lift, {problem}")
            in_hand = self.cube_in_tcp()
            self.sync_obstacles(ground=True)
            placements = self.place_candidates()
            place = self.plan_task("pre-place", lambda q, **o: mg.plan_place(
                q, placements, retreat=RETREAT_HEIGHT, approach=APPROACH_HEIGHT, link=TCP, **o), **carry)
            self.run_stage("pre-place", place.segment("free"))
            problem = self.grasp_problem()
            if problem is not None:
                raise CubeDropped(f"on the way to the place position, {problem}")
            self.run_stage("descend", place.segment("descend"))
            self._ep.slip = max(self._ep.slip, float(np.linalg.norm(self.cube_in_tcp() - in_hand)))
        except Exception:
            mg.detach_object(self.planning_start())
            mg.remove_obstacle("cube")
            raise
        self.gripper(self.robot.gripper.joint_opened_positions[0], "open")
        mg.detach_object(self.planning_start())
        mg.remove_obstacle("cube")  # the target cube is never an obstacle
        self.run_stage("retreat", place.segment("retreat"))
        self.sync_obstacles()
        self.move("wait pose", self.wait_q)

    def recover(self) -> None:
        """After a failure: open the gripper, back off upwards if possible, go to the wait pose."""
        self.gripper(self.robot.gripper.joint_opened_positions[0], "open")
        self.sync_obstacles()
        tcp = self.tcp_pose()
        if tcp.position[2] < 0.15:
            try:
                self.move("back off", Pose(tcp.position + [0.0, 0.0, 0.10], tcp.quaternion), linear=True)
            except PlanningFailed:
                pass
        self.move("wait pose", self.wait_q)

    # ------------------------------------------------------------------ episodes
    def error(self) -> float:
        """Distance [m] of the cube centre to the place position, from the simulator."""
        return float(np.linalg.norm(self.cube_pose()[0] - self.place_position))

    def run_episode(self, index: int, perturb: bool = False, cube_pose: tuple | None = None) -> EpisodeResult:
        """Reset, put the cube at the episode's random pose, pick and place until it rests at
        the place position (and once more after a perturbation with `perturb`).

        Args:
            index: episode number (with the seed, it fixes the random cube poses).
            perturb: after the place, move the cube to a new random pose (picked again).
            cube_pose: (position (3,) [m], quaternion (4,) wxyz) to start from instead of
                the random pose.
        """
        rng = np.random.default_rng([self.seed, index])
        ep = self._ep = EpisodeResult(index=index, placed=False, error=float("nan"))
        self.trajectory_log = []
        t_wall = time.perf_counter()
        self.world.reset()  # the robot at its default (= wait) configuration, the fingers open
        t_sim = self.world.current_time
        self._plan_seed = self.seed * 100_003 + index * 1009
        p, qc = random_cube_pose(rng, self.boxes, self.cube_size)
        if cube_pose is not None:
            p, qc = cube_pose
        self.task.set_params(cube_position=p, cube_orientation=qc)
        perturbations = 1 if perturb else 0
        try:
            while True:
                if not self.wait_static():
                    self.say("the scene did not come to rest; going on")
                err = self.error()
                if err <= REPICK_DISTANCE:
                    if perturbations > 0:
                        perturbations -= 1
                        p, qc = random_cube_pose(rng, self.boxes, self.cube_size)
                        self.say(f"perturb: the cube is moved to ({p[0]:.3f}, {p[1]:.3f}) m")
                        self.task.set_params(cube_position=p, cube_orientation=qc)
                        continue
                    break
                if ep.picks >= PICK_TRIES:
                    ep.reason = ep.reason or f"cube still {err * 100:.1f} cm away after {PICK_TRIES} picks"
                    break
                ep.picks += 1
                if ep.picks > 1:
                    self.say(f"the cube is {err * 100:.1f} cm from the place position: pick #{ep.picks}")
                try:
                    self.pick_and_place()
                except (PlanningFailed, CubeDropped) as exc:
                    ep.reason = str(exc)
                    self.say(f"FAILED: {exc}")
                    try:
                        self.recover()
                    except PlanningFailed as exc2:
                        ep.reason = f"{exc}; recovery failed: {exc2}"
                        self.say(f"FAILED: {exc2}")
                        break
        finally:
            self._ep = None
        ep.error = self.error()
        ep.placed = ep.error < SUCCESS_TOLERANCE
        if ep.placed:
            ep.reason = ""
        elif not ep.reason:
            ep.reason = f"the cube rests {ep.error * 100:.1f} cm from the place position"
        ep.sim_time = self.world.current_time - t_sim
        ep.wall_time = time.perf_counter() - t_wall
        return ep

    def close(self) -> Path | None:
        path = self.world.stop_recording()
        self.app.close()
        return path


# ---------------------------------------------------------------------------- output
def summary_table(results: list[EpisodeResult]) -> str:
    head = f"{'episode':>7}  {'placed':>6}  {'error mm':>8}  {'picks':>5}  {'plan s':>6}  {'motion s':>8}  " \
           f"{'sim s':>6}  {'wall s':>6}  {'x RT':>5}  reason"
    lines = [head, "-" * len(head)]
    for r in results:
        rt = r.sim_time / r.wall_time if r.wall_time > 0 else float("nan")
        lines.append(f"{r.index:>7}  {'yes' if r.placed else 'NO':>6}  {r.error * 1e3:8.2f}  {r.picks:>5}  "
                     f"{r.plan_time:6.2f}  {r.motion_time:8.2f}  {r.sim_time:6.2f}  {r.wall_time:6.2f}  {rt:5.1f}  "
                     f"{r.reason}")
    return "\n".join(lines)


def serve_until_interrupted(url: str | None) -> None:
    """Keep the web viewer's page up (the World as the last episode left it) until Ctrl-C."""
    print(f"episodes done: the page {url} stays up; press Ctrl-C to stop", flush=True)
    try:
        while True:
            time.sleep(0.5)
    except KeyboardInterrupt:
        print("stopped")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=3, help="Number of episodes, each with a random cube pose.")
    parser.add_argument("--seed", type=int, default=0, help="Seed of the cube poses, the obstacles and the planning.")
    parser.add_argument("--obstacles", action="store_true", help="Add fixed boxes the motions must avoid.")
    parser.add_argument("--perturb", action="store_true",
                        help="After each place, move the cube to a new random pose (it is picked again).")
    parser.add_argument("--cube-size", type=float, default=CUBE_SIZE,
                        help=f"Edge of the cube [m], {MIN_CUBE_SIZE} to {MAX_CUBE_SIZE} (the gripper opens to 0.08 m).")
    parser.add_argument("--cube-mass", type=float, default=0.05,
                        help="Mass of the cube [kg] (0.01-0.05 in the tutorial).")
    parser.add_argument("--viewer", nargs="?", const="native", choices=("native", "web"), default=None,
                        help="--viewer: MuJoCo's window (needs a display). --viewer web: the browser (no display "
                             "needed; pip install \"manip-robotics[viz]\"), served until Ctrl-C.")
    parser.add_argument("--video", metavar="PATH",
                        help=f"Record an MP4 (offscreen). Rendering costs about {VIDEO_COST}, so a run with "
                             "a video takes about 90 times as long.")
    parser.add_argument("--plot", metavar="PATH", help="Write a PNG of the joint position, velocity, acceleration "
                        "and jerk of the last episode's motions, limits drawn.")
    parser.add_argument("--perceive", action="store_true",
                        help="The planner gets no obstacles from the simulator, only what two simulated depth cameras "
                             "see (an occupancy map refreshed before each motion).")
    parser.add_argument("--quiet", action="store_true", help="Print no per-phase progress lines.")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error("--episodes must be >= 1")
    if not MIN_CUBE_SIZE <= args.cube_size <= MAX_CUBE_SIZE:
        parser.error(f"--cube-size must be in [{MIN_CUBE_SIZE}, {MAX_CUBE_SIZE}] m")
    if not 0.0 < args.cube_mass <= 0.5:
        parser.error("--cube-mass must be in (0, 0.5] kg")

    print(f"Franka pick-and-place: {args.episodes} episode(s), seed {args.seed}"
          f"{', obstacles' if args.obstacles else ''}{', perturbations' if args.perturb else ''}")
    if args.video:
        print(f"recording a video to {args.video}")
    else:
        print("  (add --video out.mp4 to record a video, --viewer to watch in MuJoCo's window, --plot joints.png)")

    try:
        demo = PickAndPlace(seed=args.seed, obstacles=args.obstacles, cube_mass=args.cube_mass, viewer=args.viewer,
                            video=args.video, verbose=not args.quiet, record_joints=args.plot is not None,
                            perceive=args.perceive, cube_size=args.cube_size)
    except (SimulationError, OffscreenRenderingError) as exc:  # no display for --viewer, no GL/ffmpeg for --video
        hint = ("\n  (no display? --viewer web shows it in the browser instead)"
                if args.viewer == "native" and isinstance(exc, SimulationError) else "")
        print(f"error: {exc}{hint}", file=sys.stderr)
        return 2
    if args.viewer == "web":
        print(f"  watch it at {demo.app.viewer_url} (served until Ctrl-C, also after the episodes)", flush=True)
    results = []
    try:
        for i in range(args.episodes):
            print(f"episode {i}:")
            r = demo.run_episode(i, perturb=args.perturb)
            results.append(r)
            verdict = "placed" if r.placed else f"NOT placed: {r.reason}"
            print(f"  -> {verdict}; error {r.error * 1e3:.1f} mm, planning {r.plan_time:.2f} s, "
                  f"motion {r.motion_time:.2f} s, {r.sim_time / max(r.wall_time, 1e-9):.1f}x real time")
            if args.viewer and not demo.app.is_running():
                print("viewer closed: stopping")
                break
        if args.viewer == "web":
            serve_until_interrupted(demo.app.viewer_url)
    finally:
        video = demo.close()
    print()
    print(summary_table(results))
    if video is not None:
        print(f"video written to {video}")
    if args.plot and demo.trajectory_log:
        from manip.viz.plots import plot_joint_trajectory, robot_limits

        plot_joint_trajectory(demo.trajectory_log, args.plot, limits=robot_limits(demo.mg),
                              title=f"episode {results[-1].index}: planned arm motions (dashed: limits)")
        print(f"plot written to {args.plot}")
    k = sum(r.placed for r in results)
    print(f"placed {k}/{args.episodes} episodes")
    return 0 if k == args.episodes else 1


if __name__ == "__main__":
    sys.exit(main())
