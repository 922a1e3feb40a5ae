"""A task of one's own, as Isaac's "Adding a New Task" tutorial writes one: a BaseTask that sets
up a Franka and a goal marker, reports observations, turns the marker green in `pre_step` once
the gripper reaches it, and gives `calculate_metrics` / `is_done`; a BaseController of one's own
that drives the arm with the Franka's KinematicsSolver (Lula IK); a physics callback logging the
distance; the loop stops when the task is done, and a reset starts it over. Only the imports
differ from Isaac Sim 4.x."""

from manip.sim import SimulationApp

simulation_app = SimulationApp({"headless": True})

import numpy as np
from manip.sim import World
from manip.sim import BaseTask
from manip.sim import BaseController
from manip.sim import Franka
from manip.sim import KinematicsSolver
from manip.sim import VisualCuboid
from manip.sim import euler_angles_to_quat
from manip.sim import carb


class ReachTask(BaseTask):
    def __init__(self, name, goal_position, offset=None):
        super().__init__(name=name, offset=offset)
        self._goal_position = np.array(goal_position)
        self._task_achieved = False

    def set_up_scene(self, scene):
        super().set_up_scene(scene)
        scene.add_default_ground_plane()
        self._franka = scene.add(Franka(prim_path="/World/Fancy_Franka", name="fancy_franka"))
        self._goal = scene.add(VisualCuboid(prim_path="/World/goal", name="goal", position=self._goal_position,
                                            size=0.03, color=np.array([1.0, 0.0, 0.0])))

    def get_observations(self):
        return {
            self._franka.name: {"joint_positions": self._franka.get_joint_positions()},
            self._goal.name: {"position": self._goal.get_world_pose()[0]},
        }

    def gripper_position(self):
        position, _ = ik_solver.compute_end_effector_pose()
        return position

    def pre_step(self, control_index, simulation_time):
        if not self._task_achieved and np.linalg.norm(self.gripper_position() - self._goal_position) < 0.01:
            self._goal.get_applied_visual_material().set_color(color=np.array([0.0, 1.0, 0.0]))
            self._task_achieved = True

    def calculate_metrics(self):
        return {"distance": float(np.linalg.norm(self.gripper_position() - self._goal_position))}

    def is_done(self):
        return self._task_achieved

    def post_reset(self):
        self._goal.get_applied_visual_material().set_color(color=np.array([1.0, 0.0, 0.0]))
        self._task_achieved = False


class ReachController(BaseController):
    def __init__(self, solver):
        super().__init__(name="reach_controller")
        self._solver = solver

    def forward(self, goal_position, goal_orientation):
        action, success = self._solver.compute_inverse_kinematics(goal_position, goal_orientation)
        if not success:
            carb.log_warn("IK did not converge to a solution: no action is being taken")
            return None
        return action


world = World(stage_units_in_meters=1.0)
task = ReachTask(name="reach", goal_position=[0.45, 0.2, 0.3])
world.add_task(task)
world.reset()
franka = world.scene.get_object("fancy_franka")
ik_solver = KinematicsSolver(franka)
controller = ReachController(ik_solver)
articulation_controller = franka.get_articulation_controller()
down = euler_angles_to_quat(np.array([0.0, np.pi, 0.0]))

distances = []
world.add_physics_callback("log_distance", lambda step_size: distances.append(task.calculate_metrics()["distance"]))
episodes = []
for episode in range(2):
    steps = 0
    while simulation_app.is_running() and steps < 600:
        world.step(render=False)
        steps += 1
        if world.is_done():
            break
        observations = world.get_observations()
        action = controller.forward(observations["goal"]["position"], down)
        if action is not None:
            articulation_controller.apply_action(action)
    episodes.append((steps, task.is_done(), task.calculate_metrics()["distance"],
                     task._goal.get_applied_visual_material().get_color().copy()))
    world.reset()
    controller.reset()
reset_color = task._goal.get_applied_visual_material().get_color().copy()
simulation_app.close()
