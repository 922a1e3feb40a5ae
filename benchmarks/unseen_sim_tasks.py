"""Unseen problems, round three: Isaac's pick-and-place controllers in manip.sim on random cubes.

    python benchmarks/unseen_sim_tasks.py franka --n 20 --seed 4200
    python benchmarks/unseen_sim_tasks.py ur10 --n 20 --seed 4300

`franka`: the Isaac tutorial's Franka `PickPlaceController` (examples/pick_place_controller.py)
on a cube of edge 3-7 cm at a random reachable spot (0.3-0.6 m from the base, azimuth within
+-100 deg), yaw 0 on even episodes and random on odd ones (the controller's gripper yaw is
fixed, as in Isaac), and a random goal on the ground at least 25 cm from the cube.
`ur10`: Isaac's UR10 suction pattern (tests/sim/seeds/scripts/ur10_suction_pick_place.py:
`SurfaceGripper`, the generic `PickPlaceController` over an `RMPFlowController`) on a cube of
4-7 cm, 0.45-0.8 m from the base, random yaw, a random goal. Each episode runs until the
controller is done or stops (or 60 s of simulated time); placed = the cube's centre within 2 cm
(horizontally) of the goal and resting on the ground. Prints one line per episode and a summary.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

AZIMUTH = np.radians(100)  # [rad] cubes and goals within this of the x axis


def _spot(rng, r_lo, r_hi, az=AZIMUTH):
    r, a = rng.uniform(r_lo, r_hi), rng.uniform(-az, az)
    return np.array([r * np.cos(a), r * np.sin(a)])


def _cube_and_goal(rng, r_lo, r_hi, yaw_random: bool, size):
    from manip import quaternion as quat
    p = _spot(rng, r_lo, r_hi)
    while True:
        g = _spot(rng, r_lo, r_hi)
        if np.linalg.norm(g - p) >= 0.25:
            break
    yaw = rng.uniform(-np.pi, np.pi) if yaw_random else 0.0
    return (np.array([p[0], p[1], size / 2]), quat.from_axis_angle([0, 0, 1], yaw), np.array([g[0], g[1], size / 2]))


def franka_episode(seed: int, i: int) -> dict:
    from manip.sim import DynamicCuboid, Franka, PickPlaceController, World, create_new_stage
    rng = np.random.default_rng([seed, i])
    size = float(rng.uniform(0.03, 0.07))
    p, q, goal = _cube_and_goal(rng, 0.3, 0.6, i % 2 == 1, size)
    World.clear_instance()
    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka(prim_path="/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=p, orientation=q, size=size))
    world.reset()
    ctl = PickPlaceController(name="pp", gripper=franka.gripper, robot_articulation=franka)
    franka.gripper.set_joint_positions(franka.gripper.joint_opened_positions)
    return _run(world, ctl, cube, goal, lambda: ctl.forward(
        picking_position=cube.get_world_pose()[0], placing_position=goal,
        current_joint_positions=franka.get_joint_positions()), franka.apply_action, size, i, "failure")


def ur10_episode(seed: int, i: int) -> dict:
    from manip.sim import (
        DynamicCuboid,
        PickPlaceController,
        RMPFlowController,
        SingleManipulator,
        SurfaceGripper,
        World,
        create_new_stage,
        get_assets_root_path,
    )
    rng = np.random.default_rng([seed, i])
    size = float(rng.uniform(0.04, 0.07))
    p, q, goal = _cube_and_goal(rng, 0.45, 0.8, True, size)
    World.clear_instance()
    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane()
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=p, orientation=q, size=size))
    gripper = SurfaceGripper(end_effector_prim_path="/World/UR10/ee_link", translate=0.0, direction="x")
    ur10 = world.scene.add(SingleManipulator(prim_path="/World/UR10", name="ur10", end_effector_prim_name="ee_link",
                                             gripper=gripper, usd_path=get_assets_root_path() + "/ur10/ur10.xml"))
    ur10.set_joints_default_state(positions=np.array([0.0, -2.2, 1.9, -1.383, -1.57, 0.0]))
    world.reset()
    ctl = PickPlaceController(name="pp", cspace_controller=RMPFlowController(name="c", robot_articulation=ur10,
                                                                              robot="ur10"),
                              gripper=gripper, end_effector_initial_height=0.4,
                              events_dt=[0.01, 0.01, 0.1, 0.1, 0.01, 0.005, 0.01, 1, 0.01, 0.08])
    art = ur10.get_articulation_controller()
    return _run(world, ctl, cube, goal, lambda: ctl.forward(
        picking_position=cube.get_world_pose()[0], placing_position=goal,
        current_joint_positions=ur10.get_joint_positions(), end_effector_offset=np.array([0, 0, size / 2 + 0.004])),
        art.apply_action, size, i, "failure")


def _run(world, ctl, cube, goal, forward, apply, size, i, failure_attr) -> dict:
    t0 = time.perf_counter()
    error = None
    steps = 0
    for steps in range(3600):
        world.step(render=False)
        try:
            action = forward()
        except Exception as exc:  # noqa: BLE001 - a finding, recorded
            error = f"{type(exc).__name__}: {exc}"[:300]
            break
        if ctl.is_done() or getattr(ctl, failure_attr, None) is not None:
            break
        apply(action)
    for _ in range(60):
        world.step(render=False)
    c = cube.get_world_pose()[0]
    d = float(np.linalg.norm(c[:2] - goal[:2]))
    placed = d < 0.02 and abs(c[2] - size / 2) < 0.01
    why = error or (getattr(ctl, failure_attr, None) and str(getattr(ctl, failure_attr))) or (
        "" if placed else f"controller {'done' if ctl.is_done() else 'not done'}, cube {d * 100:.1f} cm from the goal, "
        f"at z {c[2] * 100:.1f} cm")
    return {"i": i, "size": size, "placed": placed, "error_cm": d * 100, "done": bool(ctl.is_done()),
            "sim_s": world.current_time, "steps": steps, "wall": time.perf_counter() - t0, "why": why}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("robot", choices=("franka", "ur10"))
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--seed", type=int, default=4200)
    a = ap.parse_args(argv)
    run = franka_episode if a.robot == "franka" else ur10_episode
    rows = []
    for i in range(a.n):
        r = run(a.seed, i)
        rows.append(r)
        print(f"{a.robot} {i:3d} size {r['size'] * 100:4.1f} cm: {'placed' if r['placed'] else 'FAILED'} "
              f"{r['error_cm']:5.1f} cm from the goal, done {r['done']}, sim {r['sim_s']:5.1f} s, wall {r['wall']:5.1f} s"
              + (f"\n    {r['why']}" if r["why"] else ""), flush=True)
    k = sum(r["placed"] for r in rows)
    print(f"\n{a.robot}: placed {k}/{len(rows)}")
    return 0 if k == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())
