"""Several robots and several tasks in one World (the pattern of Isaac's "Adding Multiple
Robots" and "Multiple Tasks" tutorials): each task adds a Jetbot and a Franka, moves the
Franka beside the Jetbot in set_up_scene, and offsets everything by the task's offset.
Only the imports differ from Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import BaseTask
from manip.sim import WheeledRobot
from manip.sim import Franka
from manip.sim import DifferentialController
from manip.sim import get_assets_root_path
from manip.sim import find_unique_string_name
from manip.sim import is_prim_path_valid


class RobotsPlaying(BaseTask):
    def __init__(self, name, offset=None):
        super().__init__(name=name, offset=offset)

    def set_up_scene(self, scene):
        super().set_up_scene(scene)
        scene.add_default_ground_plane()
        assets_root_path = get_assets_root_path()
        jetbot_prim_path = find_unique_string_name(
            initial_name="/World/Fancy_Jetbot", is_unique_fn=lambda x: not is_prim_path_valid(x)
        )
        jetbot_name = find_unique_string_name(initial_name="fancy_jetbot", is_unique_fn=lambda x: not scene.object_exists(x))
        self._jetbot = scene.add(
            WheeledRobot(
                prim_path=jetbot_prim_path,
                name=jetbot_name,
                wheel_dof_names=["left_wheel_joint", "right_wheel_joint"],
                create_robot=True,
                usd_path=assets_root_path + "/Isaac/Robots/Jetbot/jetbot.usd",
                position=np.array([0, 0.3, 0]),
            )
        )
        self._task_objects[self._jetbot.name] = self._jetbot
        franka_prim_path = find_unique_string_name(
            initial_name="/World/Fancy_Franka", is_unique_fn=lambda x: not is_prim_path_valid(x)
        )
        franka_name = find_unique_string_name(initial_name="fancy_franka", is_unique_fn=lambda x: not scene.object_exists(x))
        self._franka = scene.add(Franka(prim_path=franka_prim_path, name=franka_name))
        self._task_objects[self._franka.name] = self._franka
        # the Franka beside the Jetbot, before the first reset
        current_position, _ = self._franka.get_world_pose()
        self._franka.set_world_pose(position=current_position + np.array([1.0, 0, 0]))
        self._franka.set_default_state(position=current_position + np.array([1.0, 0, 0]))
        self._move_task_objects_to_their_frame()

    def get_observations(self):
        return {
            self._jetbot.name: {"position": self._jetbot.get_world_pose()[0]},
            self._franka.name: {"position": self._franka.get_world_pose()[0],
                                "joint_positions": self._franka.get_joint_positions()},
        }

    def get_params(self):
        return {"jetbot_name": {"value": self._jetbot.name, "modifiable": False},
                "franka_name": {"value": self._franka.name, "modifiable": False}}


world = World(stage_units_in_meters=1.0)
for i in range(2):
    world.add_task(RobotsPlaying(name=f"my_awesome_task_{i}", offset=np.array([0, (i * 2) - 3, 0])))
world.reset()

jetbots, frankas, start = [], [], []
for i in range(2):
    params = world.get_task(f"my_awesome_task_{i}").get_params()
    jetbots.append(world.scene.get_object(params["jetbot_name"]["value"]))
    frankas.append(world.scene.get_object(params["franka_name"]["value"]))
    start.append(jetbots[-1].get_world_pose()[0])
controller = DifferentialController(name="simple_control", wheel_radius=0.03, wheel_base=0.1125)

for step in range(120):
    world.step(render=True)
    for jetbot in jetbots:
        jetbot.apply_wheel_actions(controller.forward(command=[0.2, 0.0]))
    if step == 30:
        for franka in frankas:
            franka.gripper.close()

observations = world.get_observations()
travelled = [float(np.linalg.norm(j.get_world_pose()[0][:2] - s[:2])) for j, s in zip(jetbots, start)]
franka_positions = [f.get_world_pose()[0] for f in frankas]
fingers = [f.gripper.get_joint_positions() for f in frankas]
print("jetbots travelled", travelled, "frankas at", franka_positions)
simulation_app.close()
