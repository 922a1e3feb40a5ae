"""Adding a manipulator (Isaac Sim tutorial port): the Franka picks a cube with Isaac's
PickPlaceController and puts it down on the other side of its base.

    python examples/pick_place_controller.py               # headless
    python examples/pick_place_controller.py --viewer      # watch it in MuJoCo's viewer
    python examples/pick_place_controller.py --video pick_place.mp4

As in the tutorial, a 5.15 cm cube is dropped from 0.3 m at (0.3, 0.3) and the goal is
(-0.3, -0.3) on the ground; a physics callback calls the controller once per step and
applies its action until `is_done()` (ten phases, about 38 s of simulated time). The
controller follows its end-effector targets with manip's inverse kinematics; the cube is
held by finger friction only, and the grasp is checked before the cube is carried (a cube
that is not between the fingers stops the controller, which says why). Exit status 0 when
the cube ends within 2 cm of the goal.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

CUBE_SIZE = 0.0515  # [m], the tutorial's cube
GOAL = np.array([-0.3, -0.3, CUBE_SIZE / 2.0])  # [m] where the cube's centre should end
TOLERANCE = 0.02  # [m]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    parser.add_argument("--video", metavar="PATH", help="Write an MP4 video (offscreen rendering, slower).")
    args = parser.parse_args(argv)

    from manip.sim import DynamicCuboid, Franka, PickPlaceController, SimulationApp, World

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka(prim_path="/World/Fancy_Franka", name="fancy_franka"))
    cube = world.scene.add(
        DynamicCuboid(
            prim_path="/World/random_cube",
            name="fancy_cube",
            position=np.array([0.3, 0.3, 0.3]),
            scale=np.array([CUBE_SIZE, CUBE_SIZE, CUBE_SIZE]),
            size=1.0,
            color=np.array([0.0, 0.0, 1.0]),
        )
    )
    world.reset()
    world.set_camera_view(eye=[1.3, -1.3, 0.9], target=[0.0, 0.0, 0.2])  # pick and goal both in view
    if args.video:
        world.start_recording(args.video)

    controller = PickPlaceController(name="pick_place_controller", gripper=franka.gripper, robot_articulation=franka)
    franka.gripper.set_joint_positions(franka.gripper.joint_opened_positions)
    phase = [-1]

    def physics_step(step_size: float) -> None:
        cube_position, _ = cube.get_world_pose()
        actions = controller.forward(
            picking_position=cube_position,
            placing_position=GOAL,
            current_joint_positions=franka.get_joint_positions(),
        )
        franka.apply_action(actions)
        if controller.get_current_event() != phase[0]:
            phase[0] = controller.get_current_event()
            print(f"[{world.current_time:6.2f} s] phase {phase[0]}, cube at {np.round(cube_position, 3)}")
        if controller.is_done():
            world.pause()

    world.add_physics_callback("sim_step", callback_fn=physics_step)
    while app.is_running() and world.is_playing():
        world.step(render=True)
    if controller.failure is not None:
        print(f"stopped: {controller.failure}")
    else:
        print("done picking and placing" if controller.is_done() else "stopped before the end")
    world.remove_physics_callback("sim_step")
    world.play()
    for _ in range(30):  # let the cube come to rest
        world.step(render=True)
    if args.video:
        print(f"video written to {world.stop_recording()}")
    app.close()

    position, _ = cube.get_world_pose()
    error = float(np.linalg.norm(position - GOAL))
    print(f"cube at {np.round(position, 4)}, {error * 100:.2f} cm from the goal")
    return 0 if controller.is_done() and controller.failure is None and error < TOLERANCE else 1


if __name__ == "__main__":
    sys.exit(main())
