"""Isaac Sim's "Lula RMPflow" tutorial (the Franka follows a target around a cube), ported to manip by its imports.

The tutorial's `scenario.py` as its section "Loading RMPflow for Supported Robots" leaves it
(with the world state of the section before): a Franka follows a target with `RmpFlow` loaded
through `load_supported_motion_policy_config`, a cube obstacle registered with `add_obstacle`,
`update_world()` and `set_robot_base_pose()` every frame, actions from an
`ArticulationMotionPolicy`. The class below is the tutorial's code except:

- imports: `isaacsim...` -> `manip.sim` (README, "Porting a tutorial");
- the lines marked `# [manip]`: the Franka's Isaac Sim 5 asset path (manip maps Isaac's
  `/Isaac/Robots/Franka/franka.usd`), and the target's `frame_prim.usd` (a USD prop manip
  cannot load: an Xform at /World/target stands for it, as the tutorial uses only its pose);
- below the class, `# [manip]` throughout: what the extension template's buttons do (LOAD adds
  the assets to the World and resets it, then `setup()`; RUN calls `update(step)` every physics
  step), headless by default (`--viewer` opens MuJoCo's viewer), bounded by `--steps`; after
  half of them the target moves to a second pose (a GUI user drags it); and an exit status:
  0 when the robot never touched the obstacle and right_gripper ended within 1 cm of each pose.

manip's RmpFlow is not RMPflow: it is manip's QP controller under RmpFlow's names
(`manip/sim/motion_generation/rmpflow.py` says what differs).

    python examples/rmpflow_follow_target.py [--steps 1200] [--viewer]
"""
import argparse  # [manip]
import sys  # [manip]

import numpy as np
from manip.sim import FixedCuboid
from manip.sim import SingleArticulation as Articulation
from manip.sim import SingleXFormPrim as XFormPrim
from manip.sim import euler_angles_to_quats
from manip.sim import add_reference_to_stage
from manip.sim import ArticulationMotionPolicy, RmpFlow
from manip.sim.motion_generation.interface_config_loader import (
    get_supported_robot_policy_pairs,
    load_supported_motion_policy_config,
)
from manip.sim import get_assets_root_path


class FrankaRmpFlowExample:
    def __init__(self):
        self._rmpflow = None
        self._articulation_rmpflow = None

        self._articulation = None
        self._target = None

    def load_example_assets(self):
        # Add the Franka and target to the stage
        # The position in which things are loaded is also the position in which they

        robot_prim_path = "/panda"
        path_to_robot_usd = get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"  # [manip] Isaac 5: .../FrankaRobotics/FrankaPanda/franka.usd

        add_reference_to_stage(path_to_robot_usd, robot_prim_path)
        self._articulation = Articulation(robot_prim_path)

        # [manip] the tutorial: add_reference_to_stage(get_assets_root_path() + "/Isaac/Props/UIElements/frame_prim.usd", "/World/target")
        self._target = XFormPrim("/World/target", scale=[0.04, 0.04, 0.04])

        self._obstacle = FixedCuboid(
            "/World/obstacle", size=0.05, position=np.array([0.4, 0.0, 0.65]), color=np.array([0.0, 0.0, 1.0])
        )

        # Return assets that were added to the stage so that they can be registered with the core.World
        return self._articulation, self._target, self._obstacle

    def setup(self):
        # Loading RMPflow can be done quickly for supported robots
        print("Supported Robots with a Provided RMPflow Config:", list(get_supported_robot_policy_pairs().keys()))
        rmp_config = load_supported_motion_policy_config("Franka", "RMPflow")

        # Initialize an RmpFlow object
        self._rmpflow = RmpFlow(**rmp_config)
        self._rmpflow.add_obstacle(self._obstacle)

        # Use the ArticulationMotionPolicy wrapper object to connect rmpflow to the Franka robot articulation.
        self._articulation_rmpflow = ArticulationMotionPolicy(self._articulation, self._rmpflow)

        self._target.set_world_pose(np.array([0.5, 0, 0.7]), euler_angles_to_quats([0, np.pi, 0]))

    def update(self, step: float):
        # Step is the time elapsed on this frame
        target_position, target_orientation = self._target.get_world_pose()

        self._rmpflow.set_end_effector_target(target_position, target_orientation)

        # Track any movements of the cube obstacle
        self._rmpflow.update_world()

        # Track any movements of the robot base
        robot_base_translation, robot_base_orientation = self._articulation.get_world_pose()
        self._rmpflow.set_robot_base_pose(robot_base_translation, robot_base_orientation)

        action = self._articulation_rmpflow.get_next_articulation_action(step)
        self._articulation.apply_action(action)

    def reset(self):
        # Rmpflow is stateless unless it is explicitly told not to be

        self._target.set_world_pose(np.array([0.5, 0, 0.7]), euler_angles_to_quats([0, np.pi, 0]))


#: [manip] The second target pose (a GUI user drags the target): right of the cube, lower.
SECOND_POSITION = np.array([0.4, -0.3, 0.5])  # [manip]
TOLERANCE = 0.01  # [manip] [m]: the drives settle ~5 mm below their command under gravity


def _contacts(world, robot, obstacle) -> int:  # [manip]
    """Simulated contacts between the robot's bodies and the obstacle's geom this step."""  # [manip]
    m, d = world.model, world.data  # [manip]
    bodies = {b for b in range(m.nbody) if m.body(b).name.startswith(robot.prim_path + "/")}  # [manip]
    return sum(1 for c in d.contact[: d.ncon]  # [manip]
               if (c.geom1 == obstacle.geom_id and m.geom_bodyid[c.geom2] in bodies)  # [manip]
               or (c.geom2 == obstacle.geom_id and m.geom_bodyid[c.geom1] in bodies))  # [manip]


def main() -> int:  # [manip] the extension template's buttons, headless
    parser = argparse.ArgumentParser(  # [manip]
        description="Isaac Sim's Lula RMPflow tutorial on manip, with only its imports changed.")  # [manip]
    parser.add_argument("--viewer", action="store_true",  # [manip]
                        help="Open MuJoCo's interactive viewer (needs a display).")  # [manip]
    parser.add_argument("--steps", type=int, default=1200,  # [manip]
                        help="Physics steps to run at 60 Hz; the target moves after half of them (default 1200).")
    args = parser.parse_args()  # [manip]
    from manip.sim import SimulationApp, World  # [manip]

    app = SimulationApp({"headless": not args.viewer})  # [manip]
    world = World(stage_units_in_meters=1.0)  # [manip]
    world.scene.add_default_ground_plane()  # [manip] the template's new stage has one
    scenario = FrankaRmpFlowExample()  # [manip]
    robot, target, obstacle = scenario.load_example_assets()  # [manip] LOAD
    for asset in (robot, target, obstacle):  # [manip]
        world.scene.add(asset)  # [manip]
    world.reset()  # [manip]
    scenario.setup()  # [manip]
    scenario.reset()  # [manip]
    world.add_physics_callback("sim_step", scenario.update)  # [manip] RUN
    contacts, errors = 0, []  # [manip]
    for k in range(args.steps):  # [manip]
        if not app.is_running():  # [manip]
            break  # [manip]
        if k == args.steps // 2:  # [manip] the end of the first half: measure, then move the target
            errors.append(_error(scenario, robot, target))  # [manip]
            target.set_world_pose(SECOND_POSITION, euler_angles_to_quats([0, np.pi, 0]))  # [manip]
        world.step(render=args.viewer)  # [manip]
        contacts += _contacts(world, robot, obstacle)  # [manip]
    errors.append(_error(scenario, robot, target))  # [manip]
    app.close()  # [manip]
    print("right_gripper to target at the end of each half: " + ", ".join(f"{e * 1000:.1f} mm" for e in errors))
    print(f"simulated contacts robot-obstacle: {contacts}")  # [manip]
    return 0 if contacts == 0 and max(errors) < TOLERANCE else 1  # [manip]


def _error(scenario, robot, target) -> float:  # [manip]
    """Distance [m] from right_gripper (the URDF frame RmpFlow controls) to the target."""  # [manip]
    rmpflow = scenario._articulation_rmpflow.get_motion_policy()  # [manip]
    position, _ = rmpflow.get_end_effector_pose(robot.get_joint_positions()[:7])  # [manip]
    return float(np.linalg.norm(position - target.get_world_pose()[0]))  # [manip]


if __name__ == "__main__":  # [manip]
    sys.exit(main())  # [manip]
