"""Isaac's "Adding a New Manipulator" pattern on the Franka: an RMPflow controller of one's own
(`MotionPolicyController` + `RmpFlow` + `ArticulationMotionPolicy`) and a pick-and-place
controller subclassing the manipulators extension's generic `PickPlaceController`, given it as
`cspace_controller`. Written as for Isaac Sim 4.5; only the imports differ
(isaacsim.robot.manipulators.controllers / isaacsim.robot_motion.motion_generation -> manip.sim)."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np

import manip.sim as manipulators_controllers
import manip.sim as mg
from manip.sim import PickPlace, World
from manip.sim.motion_generation import interface_config_loader


class RMPFlowController(mg.MotionPolicyController):
    def __init__(self, name, robot_articulation, physics_dt=1.0 / 60.0):
        rmp_config = interface_config_loader.load_supported_motion_policy_config("Franka", "RMPflow")
        self.rmpflow = mg.RmpFlow(**rmp_config)
        self.articulation_rmp = mg.ArticulationMotionPolicy(robot_articulation, self.rmpflow, physics_dt)
        mg.MotionPolicyController.__init__(self, name=name, articulation_motion_policy=self.articulation_rmp)
        self._default_position, self._default_orientation = (
            self._articulation_motion_policy._robot_articulation.get_world_pose()
        )
        self._motion_policy.set_robot_base_pose(
            robot_position=self._default_position, robot_orientation=self._default_orientation
        )

    def reset(self):
        mg.MotionPolicyController.reset(self)
        self._motion_policy.set_robot_base_pose(
            robot_position=self._default_position, robot_orientation=self._default_orientation
        )


class PickPlaceController(manipulators_controllers.PickPlaceController):
    def __init__(self, name, gripper, robot_articulation, events_dt=None):
        if events_dt is None:
            events_dt = [0.008, 0.005, 0.1, 0.1, 0.0025, 0.001, 0.0025, 1, 0.008, 0.08]
        manipulators_controllers.PickPlaceController.__init__(
            self,
            name=name,
            cspace_controller=RMPFlowController(name=name + "_cspace_controller", robot_articulation=robot_articulation),
            gripper=gripper,
            events_dt=events_dt,
            end_effector_initial_height=0.3,
        )


my_world = World(stage_units_in_meters=1.0)
my_task = PickPlace(name="franka_pick_place")
my_world.add_task(my_task)
my_world.reset()
task_params = my_world.get_task("franka_pick_place").get_params()
robot_name = task_params["robot_name"]["value"]
cube_name = task_params["cube_name"]["value"]
my_franka = my_world.scene.get_object(robot_name)
my_controller = PickPlaceController(
    name="controller", gripper=my_franka.gripper, robot_articulation=my_franka
)
articulation_controller = my_franka.get_articulation_controller()

done = False
events = []
for i in range(4000):
    my_world.step(render=False)
    if my_world.is_playing():
        if my_world.current_time_step_index == 0:
            my_world.reset()
            my_controller.reset()
        observations = my_world.get_observations()
        actions = my_controller.forward(
            picking_position=observations[cube_name]["position"],
            placing_position=observations[cube_name]["target_position"],
            current_joint_positions=observations[robot_name]["joint_positions"],
            end_effector_offset=np.array([0, 0, 0.0]),
            end_effector_orientation=np.array([0.0, 1.0, 0.0, 0.0]),
        )
        events.append(my_controller.get_current_event())
        if my_controller.is_done():
            done = True
            break
        articulation_controller.apply_action(actions)

observations = my_world.get_observations()
cube_position = observations[cube_name]["position"]
target_position = observations[cube_name]["target_position"]
print("done:", done, "steps:", len(events), "cube at", np.round(cube_position, 4), "target", target_position)
simulation_app.close()
