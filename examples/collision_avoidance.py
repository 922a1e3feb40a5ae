"""Collision checking and avoidance: distances, attached objects and a changing world.

Shows `check_collision` / `distance`, then carries a long box through a gap: the plan with
the box attached avoids what the bare hand would not need to, and after `detach_object`
the box stays in the world where it was released.

    python examples/collision_avoidance.py [--seed 0]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from manip import MotionGenerator, Pose
from manip.collision import Cuboid, Cylinder, WorldConfig

DOWN = np.array([0.0, 1.0, 0.0, 0.0])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=0, help="Seed of the planning (default 0).")
    args = parser.parse_args(argv)

    world = WorldConfig(
        [
            Cuboid("table", [0.8, 1.2, 0.04], Pose([0.55, 0.0, -0.02])),
            Cylinder("post", radius=0.04, height=0.6, pose=Pose([0.45, 0.0, 0.3])),
        ]
    )
    mg = MotionGenerator("franka", world, seed=args.seed)
    ready = mg.default_joint_positions
    print(f"ready: in collision {mg.check_collision(ready)}, signed distance {mg.distance(ready) * 100:.1f} cm")

    pick = mg.ik(Pose([0.45, 0.3, 0.45], DOWN), seed_q=ready, collision_free=True)
    place = mg.ik(Pose([0.45, -0.3, 0.45], DOWN), seed_q=ready, collision_free=True)
    if not (pick.success and place.success):
        print("IK failed:", pick.status.name, place.status.name)
        return 1
    bare = mg.plan_joints(pick.q, place.q)
    print(f"bare hand, pick -> place: {bare.status.name}, motion {bare.motion_time:.2f} s")

    # a 30 cm bar held below the hand
    bar_pose = mg.fk(pick.q, "panda_hand_tcp") @ Pose([0.0, 0.0, 0.1])
    mg.add_obstacle(Cuboid("bar", [0.03, 0.03, 0.3], bar_pose))
    print(f"bar added to the world: hand now in collision {mg.check_collision(pick.q)}")
    mg.attach_object("bar", q=pick.q)
    print(f"bar attached: in collision {mg.check_collision(pick.q)}, distance {mg.distance(pick.q) * 100:.1f} cm")
    carried = mg.plan_joints(pick.q, place.q)
    if carried.success:
        print(f"carrying the bar: {carried.status.name}, motion {carried.motion_time:.2f} s, "
              f"path {carried.trajectory.path_length():.2f} rad (bare hand: {bare.trajectory.path_length():.2f} rad)")
    else:
        print(f"carrying the bar: {carried.status.name} ({carried.message})")
    dropped = mg.detach_object(place.q)
    print(f"bar released at {np.round(dropped[0].pose.position, 3)}; world: {mg.world.names}")
    return 0 if bare.success and carried.success else 1


if __name__ == "__main__":
    sys.exit(main())
