"""A/B timings of two manip.sim features, each in one process (BENCHMARKS.md "Simulation:
robot-overlap check at reset, SurfaceGripper per step"):

- `world.reset()` of two Frankas 1 m apart with and without the robot-overlap check
  (`manip.sim.scenes.robot_overlaps`, patched out for B);
- `world.step(render=False)` of a UR10 holding a cube by a closed `SurfaceGripper` against the
  same scene with the gripper open; and `SurfaceGripper.update()` alone;
- `set_world_pose` of a Franka beside another after the reset, with and without the moved-robot
  overlap check (`SimHandle.robot_cores` emptied for B); `SurfaceGripper.close()` alone (the ray,
  the pull-in distance against the robot's geoms, the weld) against `close()` + `open()` of
  round four's weld without the pull (`_pull` patched to return the gap).

Run: `python benchmarks/sim_grip_and_overlap.py [--rounds 3]` (under the machine's benchmark lock).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import manip.sim.core.simulation_context as sc
from manip import Kinematics, load_robot_config
from manip.sim import (
    DynamicCuboid,
    FixedCuboid,
    Franka,
    SingleManipulator,
    SurfaceGripper,
    World,
    create_new_stage,
    get_assets_root_path,
)


def fresh() -> World:
    World.clear_instance()
    create_new_stage()
    return World()


def resets(n: int, check: bool) -> float:
    """Mean seconds per `world.reset()` of two Frankas 1 m apart."""
    original = sc.check_robot_overlaps
    if not check:
        sc.check_robot_overlaps = lambda *args: None
    try:
        world = fresh()
        world.scene.add_default_ground_plane()
        world.scene.add(Franka("/World/F1", name="f1", position=[0, 0, 0]))
        world.scene.add(Franka("/World/F2", name="f2", position=[0, 1.0, 0]))
        world.reset()
        t = time.perf_counter()
        for _ in range(n):
            world.reset()
        return (time.perf_counter() - t) / n
    finally:
        sc.check_robot_overlaps = original


def ur10_holding(closed: bool):
    """A UR10 at home over a cube on a pedestal, its SurfaceGripper closed on it (or open)."""
    kin = Kinematics(load_robot_config("ur10"))
    q0 = np.array(kin.config.default_joint_positions)
    x, y, z = kin.fk(q0, "tool0").position
    world = fresh()
    world.scene.add_default_ground_plane()
    top = z - 0.004
    world.scene.add(FixedCuboid("/World/p", name="p", position=[x, y, (top - 0.05) / 2], scale=[0.1, 0.1, top - 0.05],
                                size=1.0))
    world.scene.add(DynamicCuboid("/World/c", name="c", position=[x, y, top - 0.025], size=0.05))
    gripper = SurfaceGripper("/World/UR10/ee_link", direction="x")
    ur10 = world.scene.add(SingleManipulator("/World/UR10", name="ur", end_effector_prim_name="ee_link",
                                             gripper=gripper, usd_path=get_assets_root_path() + "/ur10/ur10.xml"))
    ur10.set_joints_default_state(positions=q0)
    world.reset()
    if closed:
        gripper.close()
        assert gripper.is_closed()
    return world, gripper


def steps(n: int, closed: bool) -> float:
    world, _ = ur10_holding(closed)
    t = time.perf_counter()
    for _ in range(n):
        world.step(render=False)
    return (time.perf_counter() - t) / n


def update_cost(n: int = 2000) -> float:
    world, gripper = ur10_holding(True)
    world.step(render=False)
    t = time.perf_counter()
    for _ in range(n):
        gripper.update()
    return (time.perf_counter() - t) / n


def moves(n: int, check: bool) -> float:
    """Mean seconds per `set_world_pose` of a Franka 1 m from another, after the reset."""
    world = fresh()
    world.scene.add(Franka("/World/F1", name="f1", position=[0, 0, 0]))
    f2 = world.scene.add(Franka("/World/F2", name="f2", position=[0, 1.0, 0]))
    world.reset()
    sim = f2._core.sim
    cores = sim.robot_cores
    sim.robot_cores = cores if check else ()
    t = time.perf_counter()
    for i in range(n):
        f2.set_world_pose(position=[0.0, 1.0 + 0.001 * (i % 2), 0.0])
    dt = (time.perf_counter() - t) / n
    sim.robot_cores = cores
    return dt


def closes(n: int, pull: bool) -> float:
    """Mean seconds per `SurfaceGripper.close()` + `open()` on the cube 4 mm below the flange."""
    _, gripper = ur10_holding(False)
    original = SurfaceGripper._pull
    if not pull:
        SurfaceGripper._pull = lambda self, body, axis, gap: gap
    try:
        t = time.perf_counter()
        for _ in range(n):
            gripper.close()
            gripper.open()
        return (time.perf_counter() - t) / n
    finally:
        SurfaceGripper._pull = original


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    for _ in range(args.rounds):
        a, b = resets(20, True), resets(20, False)
        c, d = steps(300, True), steps(300, False)
        print(f"reset with check {a * 1e3:.2f} ms, without {b * 1e3:.2f} ms, ratio {a / b:.3f}; "
              f"step gripper closed {c * 1e3:.3f} ms, open {d * 1e3:.3f} ms, ratio {c / d:.3f}")
    print(f"SurfaceGripper.update() alone (closed): {update_cost() * 1e6:.1f} us per call")
    for _ in range(args.rounds):
        a, b = moves(2000, True), moves(2000, False)
        c, d = closes(500, True), closes(500, False)
        print(f"set_world_pose with check {a * 1e6:.1f} us, without {b * 1e6:.1f} us, ratio {a / b:.2f}; "
              f"close+open with pull-in {c * 1e6:.1f} us, without {d * 1e6:.1f} us, ratio {c / d:.2f}")


if __name__ == "__main__":
    main()
