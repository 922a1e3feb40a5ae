"""Isaac Sim's "Lula RMPflow" follow-target tutorial (standalone script), ported to manip by its imports.

The tutorial's standalone variations, written after Isaac Sim's documentation (2022-2023 releases):
the FollowTarget task's Franka follows its target cube with RmpFlow, loaded for a supported
robot through `interface_config_loader`, wrapped in an ArticulationMotionPolicy, with a cube
obstacle given to it (`add_obstacle`) and its world updated every frame (`update_world`).
The code below is the tutorial's except:

- imports: `omni.isaac...` -> `manip.sim` (README, "Porting a tutorial");
- the lines marked `# [manip]`: headless by default (`--viewer` opens MuJoCo's viewer), the
  main loop bounded by `--steps` (the tutorial loops until its window closes), the target
  moved through four waypoints around the obstacle (a GUI user drags it), and a report with
  an exit status: 0 when the robot never touched the obstacle and reached every waypoint.

manip's RmpFlow is not RMPflow: it is manip's QP controller under RmpFlow's names
(`manip.sim.motion_generation.rmpflow` says what differs).

    python examples/rmpflow_follow_target.py [--steps 1200] [--viewer]
"""
import argparse  # [manip]
import sys  # [manip]

_parser = argparse.ArgumentParser(  # [manip]
    description="Isaac Sim's Lula RMPflow follow-target tutorial on manip, with only its imports changed.")  # [manip]
_parser.add_argument("--viewer", action="store_true",  # [manip]
                     help="Open MuJoCo's interactive viewer (needs a display).")  # [manip]
_parser.add_argument("--steps", type=int, default=1200,  # [manip]
                     help="Physics steps to run, at 60 Hz (default 1200: 300 per waypoint).")  # [manip]
_args = _parser.parse_args()  # [manip]

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": not _args.viewer})  # [manip] the tutorial: {"headless": False}

from manip.sim import FollowTarget
from manip.sim import RmpFlow, ArticulationMotionPolicy, interface_config_loader
from manip.sim import World
from manip.sim import FixedCuboid
import numpy as np

my_world = World(stage_units_in_meters=1.0)
my_task = FollowTarget(name="follow_target_task")
my_world.add_task(my_task)
# Create a cuboid to serve as an obstacle
obstacle = my_world.scene.add(FixedCuboid("/World/obstacle", name="obstacle", size=0.08,
                                          position=np.array([0.4, 0.0, 0.37]), color=np.array([0.0, 0.0, 1.0])))
my_world.reset()
task_params = my_world.get_task("follow_target_task").get_params()
franka_name = task_params["robot_name"]["value"]
target_name = task_params["target_name"]["value"]
my_franka = my_world.scene.get_object(franka_name)

# Load RMPflow for a supported robot (the config files are in the motion_generation extension)
rmp_config = interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow")
rmpflow = RmpFlow(**rmp_config)
rmpflow.add_obstacle(obstacle)

# Use the ArticulationMotionPolicy wrapper object to connect rmpflow to the Franka robot articulation.
physics_dt = 1 / 60.0
articulation_rmpflow = ArticulationMotionPolicy(my_franka, rmpflow, physics_dt)
articulation_controller = my_franka.get_articulation_controller()

_WAYPOINTS = np.array([[0.4, 0.3, 0.45], [0.46, 0.2, 0.27], [0.46, -0.2, 0.27], [0.4, -0.3, 0.45]])  # [manip]
_per_waypoint = max(1, _args.steps // len(_WAYPOINTS))  # [manip]
_robot_bodies = {b for b in range(my_world.model.nbody)  # [manip] the Franka's bodies in MuJoCo
                 if my_world.model.body(b).name.startswith(my_franka.prim_path + "/")}  # [manip]
_contacts, _errors, _clearance = 0, [], []  # [manip]
while simulation_app.is_running() and my_world.current_time_step_index <= _args.steps:  # [manip] bounded
    _k = my_world.current_time_step_index  # [manip]
    my_task.set_params(target_position=_WAYPOINTS[min(_k // _per_waypoint, len(_WAYPOINTS) - 1)])  # [manip]
    my_world.step(render=True)
    if my_world.is_playing():
        if my_world.current_time_step_index == 0:
            my_world.reset()
        observations = my_world.get_observations()

        # Set rmpflow target to be the current position of the target cube.
        rmpflow.set_end_effector_target(
            target_position=observations[target_name]["position"],
            target_orientation=observations[target_name]["orientation"],
        )

        # Track any movements of the obstacle
        rmpflow.update_world()

        actions = articulation_rmpflow.get_next_articulation_action()
        articulation_controller.apply_action(actions)

        _d = my_world.data  # [manip] contacts between the robot and the obstacle in the simulation
        _contacts += sum(1 for c in _d.contact[: _d.ncon] if {c.geom1, c.geom2} & {obstacle.geom_id}  # [manip]
                         and my_world.model.geom_bodyid[c.geom1 if c.geom2 == obstacle.geom_id else c.geom2]  # [manip]
                         in _robot_bodies)  # [manip]
        _clearance.append(rmpflow.last_result.obstacle_clearance)  # [manip]
        if (my_world.current_time_step_index + 1) % _per_waypoint == 0:  # [manip] the end of a waypoint's time
            _p, _ = rmpflow.get_end_effector_pose(my_franka.get_joint_positions()[:7])  # [manip]
            _errors.append(float(np.linalg.norm(_p - observations[target_name]["position"])))  # [manip]

simulation_app.close()

_ok = _contacts == 0 and len(_errors) == len(_WAYPOINTS) and max(_errors) < 0.01  # [manip]
print(f"end effector to target at the end of each waypoint's {_per_waypoint} steps: "  # [manip]
      + ", ".join(f"{e * 1000:.1f} mm" for e in _errors))  # [manip]
print(f"simulated contacts robot-obstacle: {_contacts}; smallest robot-obstacle distance in the controller's model: "  # [manip]
      f"{min(_clearance) * 1000:.1f} mm")  # [manip]
sys.exit(0 if _ok else 1)  # [manip]
