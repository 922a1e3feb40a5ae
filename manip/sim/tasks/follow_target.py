"""Isaac Sim's `FollowTarget` task for the Franka: a robot, a target cube to move, obstacles.

Isaac's follow-target example runs with its imports changed::

    from manip.sim import FollowTarget, RMPFlowController, SimulationApp, World

The task builds the default ground plane, a red 3 cm `VisualCuboid` target (prim
"/World/TargetCube", name "target") and a Franka (prim "/World/Franka", name
"my_franka"). Observations are Isaac's: {robot name: {"joint_positions",
"joint_velocities"}, target name: {"position", "orientation"}}. Move the target with
`set_params(target_position=..., target_orientation=...)` (or the target's
`set_world_pose`); `add_obstacle()` / `remove_obstacle()` manage obstacle cubes, which a
`RMPFlowController` avoids once given them with its `add_obstacle`.

Differences from Isaac, each for a reason:

- the default target orientation is the hand pointing down as at the Franka's home pose,
  (w, x, y, z) = (0, 1, 0, 0), for the end effector `panda_hand_tcp`; Isaac's default
  (Euler -pi, 0, pi) = (0, 0, 1, 0) is that turned 180 deg about z for its own
  end-effector frame, which this wrist reaches only at its joint limit;
- obstacles from `add_obstacle` are `FixedCuboid`s: they stay where they are put (Isaac
  adds a `DynamicCuboid` that falls under gravity, onto the robot from the default
  position); like every object added to a running manip.sim World, they collide in the
  simulation after the next `world.reset()`.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.objects import FixedCuboid, VisualCuboid, XFormPrim
from manip.sim.robots.robot import Franka
from manip.sim.scenes.scene import Scene
from manip.sim.scenes.stage import get_current_stage
from manip.sim.tasks.base_task import BaseTask, find_unique_string_name
from manip.validation import unit_quat, vec

#: Default target position [m] (Isaac's) and orientation (hand down, see the module docstring).
DEFAULT_TARGET_POSITION = np.array([0.0, 0.1, 0.7])
DEFAULT_TARGET_ORIENTATION = np.array([0.0, 1.0, 0.0, 0.0])
#: Isaac's default obstacle position [m] and edge [m].
DEFAULT_OBSTACLE_POSITION = np.array([0.1, 0.1, 1.0])
OBSTACLE_SIZE = 0.1
#: `target_reached`: mean absolute coordinate difference [m] (Isaac's 0.035).
REACHED_TOLERANCE = 0.035


class FollowTarget(BaseTask):
    """The Franka follow-target task (Isaac's `omni.isaac.franka.tasks.FollowTarget`).

    Args:
        name: task name.
        target_prim_path: prim of the target (default "/World/TargetCube", made unique).
            If a prim already exists there, it is used as the target (an XFormPrim).
        target_name: scene name of the target (default "target", made unique).
        target_position: (3,) [m] (default [0, 0.1, 0.7]).
        target_orientation: (4,) (w, x, y, z) (default hand down, (0, 1, 0, 0)).
        offset: (3,) translation of the task's objects [m].
        franka_prim_path: default "/World/Franka" (made unique).
        franka_robot_name: default "my_franka" (made unique).
    """

    def __init__(self, name: str = "franka_follow_target", target_prim_path: str | None = None,
                 target_name: str | None = None, target_position=None, target_orientation=None, offset=None,
                 franka_prim_path: str | None = None, franka_robot_name: str | None = None):
        super().__init__(name, offset)
        self._target_prim_path = target_prim_path
        self._target_name = target_name
        self._target_position = (vec(target_position, 3, "target_position") if target_position is not None
                                 else DEFAULT_TARGET_POSITION.copy())
        self._target_orientation = (unit_quat(target_orientation, "target_orientation")
                                    if target_orientation is not None else DEFAULT_TARGET_ORIENTATION.copy())
        self._franka_prim_path = franka_prim_path
        self._franka_robot_name = franka_robot_name
        self._robot: Franka | None = None
        self._target = None
        self._obstacle_cubes: OrderedDict[str, FixedCuboid] = OrderedDict()

    # ------------------------------------------------------------------ scene
    def set_up_scene(self, scene: Scene) -> None:
        super().set_up_scene(scene)
        scene.add_default_ground_plane()
        stage = get_current_stage()
        if self._target_prim_path is None:
            self._target_prim_path = find_unique_string_name("/World/TargetCube", lambda p: stage.get_prim(p) is None)
        if self._target_name is None:
            self._target_name = find_unique_string_name("target", lambda n: not scene.object_exists(n))
        self.set_params(target_prim_path=self._target_prim_path, target_name=self._target_name,
                        target_position=self._target_position, target_orientation=self._target_orientation)
        self._robot = scene.add(self.set_robot())
        self._task_objects[self._robot.name] = self._robot
        self._move_task_objects_to_their_frame()

    def set_robot(self) -> Franka:
        """The task's robot (override to change it)."""
        stage = get_current_stage()
        if self._franka_prim_path is None:
            self._franka_prim_path = find_unique_string_name("/World/Franka", lambda p: stage.get_prim(p) is None)
        if self._franka_robot_name is None:
            self._franka_robot_name = find_unique_string_name("my_franka", lambda n: not self._scene.object_exists(n))
        return Franka(prim_path=self._franka_prim_path, name=self._franka_robot_name)

    @property
    def robot(self) -> Franka | None:
        return self._robot

    @property
    def target(self):
        """The target prim (a VisualCuboid unless an existing prim was given)."""
        return self._target

    # ------------------------------------------------------------------ parameters
    def set_params(self, target_prim_path: str | None = None, target_name: str | None = None,
                   target_position=None, target_orientation=None) -> None:
        """With `target_prim_path`: (re)create the target there (wrapping an existing prim);
        otherwise move the target to `target_position` / `target_orientation` (None keeps
        that part)."""
        if self._scene is None:
            raise InvalidInputError("set_params: the task's scene is not set up yet; call world.reset() first")
        if target_prim_path is not None:
            if self._target is not None:
                self._task_objects.pop(self._target.name, None)
            name = target_name if target_name is not None else self._target_name
            if get_current_stage().get_prim(target_prim_path) is not None:
                self._target = self._scene.add(XFormPrim(target_prim_path, name=name, position=target_position,
                                                         orientation=target_orientation))
            else:
                self._target = self._scene.add(VisualCuboid(target_prim_path, name=name, position=target_position,
                                                            orientation=target_orientation, color=np.array([1.0, 0, 0]),
                                                            size=1.0, scale=np.array([0.03, 0.03, 0.03])))
            self._target_prim_path, self._target_name = target_prim_path, self._target.name
            self._task_objects[self._target.name] = self._target
        elif target_position is not None or target_orientation is not None:
            self._target.set_local_pose(translation=target_position, orientation=target_orientation)

    def get_params(self) -> dict:
        position, orientation = self._target.get_local_pose()
        return {
            "target_prim_path": {"value": self._target.prim_path, "modifiable": True},
            "target_name": {"value": self._target.name, "modifiable": True},
            "target_position": {"value": position, "modifiable": True},
            "target_orientation": {"value": orientation, "modifiable": True},
            "robot_name": {"value": self._robot.name, "modifiable": False},
        }

    # ------------------------------------------------------------------ observations
    def get_observations(self) -> dict:
        state = self._robot.get_joints_state()
        position, orientation = self._target.get_local_pose()
        return {
            self._robot.name: {"joint_positions": np.array(state.positions), "joint_velocities": np.array(state.velocities)},
            self._target.name: {"position": np.array(position), "orientation": np.array(orientation)},
        }

    def target_reached(self) -> bool:
        """Isaac's test: mean absolute coordinate difference between the end effector and
        the target below 3.5 cm."""
        ee = self._robot.end_effector.get_world_pose()[0]
        target = self._target.get_world_pose()[0]
        return bool(np.mean(np.abs(np.asarray(ee) - np.asarray(target))) < REACHED_TOLERANCE)

    def calculate_metrics(self) -> dict:
        """{"end_effector_to_target_distance": [m]} (Isaac leaves it unimplemented)."""
        ee = self._robot.end_effector.get_world_pose()[0]
        target = self._target.get_world_pose()[0]
        return {"end_effector_to_target_distance": float(np.linalg.norm(np.asarray(ee) - np.asarray(target)))}

    def is_done(self) -> bool:
        """Never: the target can always move again."""
        return False

    def pre_step(self, time_step_index: int, simulation_time: float) -> None:
        """Colour the target green when reached, red otherwise (as Isaac)."""
        if hasattr(self._target, "set_color") and self._robot is not None and self._robot.num_dof is not None:
            self._target.set_color(np.array([0.0, 1.0, 0.0]) if self.target_reached() else np.array([1.0, 0.0, 0.0]))

    # ------------------------------------------------------------------ obstacles
    def add_obstacle(self, position=None) -> FixedCuboid:
        """Add a blue 10 cm obstacle cube at `position` [m] (default [0.1, 0.1, 1.0]) plus the
        task offset, and return it (give it to the controller's `add_obstacle`)."""
        stage = get_current_stage()
        path = find_unique_string_name("/World/ObstacleCube", lambda p: stage.get_prim(p) is None)
        name = find_unique_string_name("cube", lambda n: not self._scene.object_exists(n))
        p = vec(position, 3, "position") if position is not None else DEFAULT_OBSTACLE_POSITION.copy()
        cube = self._scene.add(FixedCuboid(path, name=name, position=p + self._offset, size=OBSTACLE_SIZE,
                                           color=np.array([0.0, 0.0, 1.0])))
        self._obstacle_cubes[cube.name] = cube
        return cube

    def remove_obstacle(self, name: str | None = None) -> None:
        """Remove obstacle `name` (default the last added) from the scene.

        Raises:
            InvalidInputError: no such obstacle, or none left.
        """
        if not self._obstacle_cubes:
            raise InvalidInputError("remove_obstacle: the task has no obstacles")
        if name is None:
            name = next(reversed(self._obstacle_cubes))
        if name not in self._obstacle_cubes:
            raise InvalidInputError(f"no obstacle named {name!r}; obstacles: {list(self._obstacle_cubes)}")
        self._scene.remove_object(name)
        del self._obstacle_cubes[name]

    def get_obstacle_to_delete(self) -> FixedCuboid:
        """The obstacle `remove_obstacle()` would remove (the last added)."""
        if not self._obstacle_cubes:
            raise InvalidInputError("get_obstacle_to_delete: the task has no obstacles")
        return self._obstacle_cubes[next(reversed(self._obstacle_cubes))]

    def obstacles_exist(self) -> bool:
        return len(self._obstacle_cubes) > 0

    def cleanup(self) -> None:
        """Remove every obstacle (called by `World.reset()` and when the World is cleared, as Isaac)."""
        for name in list(self._obstacle_cubes):
            if self._scene is not None and self._scene.object_exists(name):
                self._scene.remove_object(name)
            del self._obstacle_cubes[name]


__all__ = ["FollowTarget"]
