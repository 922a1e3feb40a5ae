"""Follow a moving target with the reactive controller: a figure-eight through an obstacle.

    python examples/follow_target.py [--duration 20] [--speed 0.2] [--no-obstacle]
                                     [--solver daqp] [--viewer [web]] [--video follow.mp4]

The Franka's tool centre point follows a target that moves at constant speed along a
figure-eight in the plane x = 0.5 m in front of it, hand pointing down. A fixed box stands
on the right lobe of the figure-eight: while the target is inside or behind it, the arm
stops `safety_margin` (1 cm) from the box and waits; when the target comes out it follows
again. The controller is `manip.sim.RMPFlowController` (Isaac's name; a QP controller,
`manip.control.ReactiveController`, not RMPflow), stepped once per physics step (60 Hz).

Printed at the end: tracking error (end effector to target, measured in the simulation)
overall and where the target is at least 15 cm from the box; the minimum clearance
between the simulated arm and the box; the number of simulated contacts between them;
joint position / velocity limit violations; the control rate. Exit status 0 when there
was no contact and no limit violation.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

#: The figure-eight: centre [m], half width (y) and half height (z) [m].
CENTRE = np.array([0.5, 0.0, 0.45])
HALF_WIDTH = 0.22
HALF_HEIGHT = 0.12
#: The obstacle: a box on the right lobe of the figure-eight.
BOX_CENTRE = np.array([0.5, 0.2, 0.45])
BOX_SIZE = np.array([0.06, 0.06, 0.3])
HAND_DOWN = np.array([0.0, 1.0, 0.0, 0.0])  # (w, x, y, z)
FREE_DISTANCE = 0.15  # [m] target this far from the box counts as "free space"
VELOCITY_TOLERANCE = 1.05  # measured joint speed may exceed the limit by 5 % (drive overshoot)


class FigureEight:
    """Points of a figure-eight (Lissajous 1:2 curve) at a constant speed along it."""

    def __init__(self, centre=CENTRE, half_width=HALF_WIDTH, half_height=HALF_HEIGHT, samples: int = 4000):
        self.centre = np.asarray(centre, dtype=float)
        theta = np.linspace(0.0, 2 * np.pi, samples + 1)
        self._theta = theta
        self._points = self.centre + np.stack([np.zeros_like(theta), half_width * np.sin(theta),
                                               half_height * np.sin(2 * theta)], axis=1)
        seg = np.linalg.norm(np.diff(self._points, axis=0), axis=1)
        self._s = np.concatenate([[0.0], np.cumsum(seg)])
        self.length = float(self._s[-1])

    def at(self, distance: float) -> np.ndarray:
        """The point `distance` [m] along the curve from its start (periodic)."""
        s = distance % self.length
        return np.array([np.interp(s, self._s, self._points[:, k]) for k in range(3)])


def box_distance(point: np.ndarray, centre: np.ndarray = BOX_CENTRE, size: np.ndarray = BOX_SIZE) -> float:
    """Distance [m] from `point` to the axis-aligned box (0 inside)."""
    gap = np.maximum(np.abs(point - centre) - size / 2, 0.0)
    return float(np.linalg.norm(gap))


def run(duration: float = 20.0, speed: float = 0.2, obstacle: bool = True, solver: str = "daqp",
        viewer: bool | str = False, video: str | None = None, verbose: bool = False) -> dict:
    """Run the scenario; returns its figures (see `report`)."""
    from manip.sim import FixedCuboid, Franka, RMPFlowController, SimulationApp, World, VisualSphere

    app = SimulationApp({"headless": not viewer, "viewer": "web" if viewer == "web" else "native"})
    World.clear_instance()
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    path = FigureEight()
    target = world.scene.add(VisualSphere("/World/Target", name="target", position=path.at(0.0), radius=0.015,
                                          color=[1.0, 0.0, 0.0]))
    box = None
    if obstacle:
        box = world.scene.add(FixedCuboid("/World/Box", name="box", position=BOX_CENTRE, size=1.0, scale=BOX_SIZE,
                                          color=[0.2, 0.4, 0.9]))
    world.reset()
    world.set_camera_view(eye=[1.5, 1.3, 1.0], target=[0.4, 0.0, 0.4])
    if video:
        world.start_recording(video)
    controller = RMPFlowController("follow", franka, physics_dt=world.get_physics_dt(), solver=solver)
    if box is not None:
        controller.add_obstacle(box)
    ctrl = controller.controller
    dt = world.get_physics_dt()
    arm = np.array([franka.get_dof_index(j) for j in ctrl.joint_names])
    lower, upper, vmax = ctrl.lower_limits, ctrl.upper_limits, ctrl.velocity_limits
    robot_bodies = {b for b in range(world.model.nbody) if world.model.body(b).name.startswith("/World/Franka/")}
    box_geom = box.geom_id if box is not None else -1

    # Start on the curve: let the arm settle on the first target point.
    for _ in range(90):
        franka.apply_action(controller.forward(path.at(0.0), HAND_DOWN))
        world.step(render=viewer)

    n = int(round(duration / dt))
    errors, free, clearance, times = [], [], [], []
    contacts = position_violations = velocity_violations = held = 0
    wall = time.perf_counter()
    for k in range(n):
        if not app.is_running():
            break
        p = path.at(speed * k * dt)
        target.set_world_pose(position=p)
        action = controller.forward(p, HAND_DOWN)
        r = controller.last_result
        times.append(r.solve_time)
        held += not r.solved
        franka.apply_action(action)
        world.step(render=viewer or bool(video))
        ee = franka.end_effector.get_world_pose()[0]
        p_next = path.at(speed * (k + 1) * dt)  # where the target is now, after the step
        target.set_world_pose(position=p_next)
        e = float(np.linalg.norm(ee - p_next))
        errors.append(e)
        free.append(box is None or box_distance(p_next) >= FREE_DISTANCE)
        q = franka.get_joint_positions()[arm]
        qd = franka.get_joint_velocities()[arm]
        position_violations += int(np.any(q < lower - 1e-6) or np.any(q > upper + 1e-6))
        velocity_violations += int(np.any(np.abs(qd) > vmax * VELOCITY_TOLERANCE))
        if box is not None:
            clearance.append(ctrl.clearance(q)[0])
            d = world.data
            for c in d.contact[: d.ncon]:
                b1, b2 = world.model.geom_bodyid[c.geom1], world.model.geom_bodyid[c.geom2]
                if (c.geom1 == box_geom and b2 in robot_bodies) or (c.geom2 == box_geom and b1 in robot_bodies):
                    contacts += 1
        if verbose and k % 120 == 0:
            print(f"t={k * dt:5.1f} s  error {e * 100:5.2f} cm  {r}")
    wall = time.perf_counter() - wall
    video_path = world.stop_recording() if video else None
    app.close()
    errors_a, free_a = np.array(errors), np.array(free, dtype=bool)
    times_a = np.array(times)
    return {
        "steps": len(errors),
        "error_median": float(np.median(errors_a)),
        "error_p95": float(np.percentile(errors_a, 95)),
        "free_error_median": float(np.median(errors_a[free_a])) if free_a.any() else float("nan"),
        "free_error_p95": float(np.percentile(errors_a[free_a], 95)) if free_a.any() else float("nan"),
        "min_clearance": float(min(clearance)) if clearance else float("inf"),
        "contacts": contacts,
        "position_violations": position_violations,
        "velocity_violations": velocity_violations,
        "held_steps": held,
        "step_median_ms": float(np.median(times_a) * 1e3),
        "step_p99_ms": float(np.percentile(times_a, 99) * 1e3),
        "control_rate_hz": float(1.0 / np.median(times_a)),
        "loop_rate_hz": len(errors) / wall,
        "video": str(video_path) if video_path else None,
    }


def report(r: dict) -> str:
    lines = [
        f"steps: {r['steps']}",
        f"tracking error: median {r['error_median'] * 100:.2f} cm, p95 {r['error_p95'] * 100:.2f} cm "
        f"(target >= {FREE_DISTANCE * 100:.0f} cm from the box: median {r['free_error_median'] * 100:.2f} cm, "
        f"p95 {r['free_error_p95'] * 100:.2f} cm)",
        f"minimum clearance arm-box: {r['min_clearance'] * 100:.2f} cm; simulated contacts arm-box: {r['contacts']}",
        f"limit violations: position {r['position_violations']} steps, velocity {r['velocity_violations']} steps; "
        f"QP held {r['held_steps']} steps",
        f"control rate: {r['control_rate_hz']:.0f} Hz (step median {r['step_median_ms']:.3f} ms, p99 "
        f"{r['step_p99_ms']:.3f} ms); simulation loop {r['loop_rate_hz']:.0f} steps/s",
    ]
    if r.get("video"):
        lines.append(f"video written to {r['video']}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=20.0, help="Seconds of target motion (default 20).")
    parser.add_argument("--speed", type=float, default=0.2, help="Target speed [m/s] (default 0.2).")
    parser.add_argument("--no-obstacle", action="store_true", help="Put no box on the target's path.")
    parser.add_argument("--solver", default="daqp", help="The qpsolvers backend of the controller's QP (default daqp).")
    parser.add_argument("--viewer", nargs="?", const="native", choices=("native", "web"), default=None,
                        help="--viewer: MuJoCo's window (needs a display). --viewer web: the browser (no display "
                             "needed; pip install \"manip-robotics[viz]\").")
    parser.add_argument("--video", metavar="PATH", help="Write an MP4 video (offscreen rendering, slower).")
    parser.add_argument("--verbose", action="store_true", help="Print a line every 2 s of simulated time.")
    args = parser.parse_args(argv)
    r = run(args.duration, args.speed, not args.no_obstacle, args.solver, args.viewer, args.video, args.verbose)
    print(report(r))
    ok = r["contacts"] == 0 and r["position_violations"] == 0 and r["velocity_violations"] == 0
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
