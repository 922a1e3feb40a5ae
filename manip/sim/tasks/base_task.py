"""Tasks (Isaac's `BaseTask`) and the Franka pick-and-place task."""

from __future__ import annotations

import logging
from typing import Any

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.objects import DynamicCuboid
from manip.sim.robots.robot import Franka
from manip.sim.scenes.scene import Scene
from manip.sim.scenes.stage import get_current_stage
from manip.validation import positive, unit_quat, vec

logger = logging.getLogger(__name__)


def find_unique_string_name(initial_name: str, is_unique_fn) -> str:
    """`initial_name`, or `initial_name_1`, `_2`, ... : the first for which is_unique_fn is True."""
    if is_unique_fn(initial_name):
        return initial_name
    i = 1
    while not is_unique_fn(f"{initial_name}_{i}"):
        i += 1
    return f"{initial_name}_{i}"


def new_franka(scene: Scene) -> Franka:
    """A Franka at a free "/World/Franka..." prim path named a free "my_franka..." (the robot of
    Isaac's Franka tasks, `set_robot`)."""
    stage = get_current_stage()
    path = find_unique_string_name("/World/Franka", lambda p: stage.get_prim(p) is None)
    name = find_unique_string_name("my_franka", lambda n: not scene.object_exists(n))
    return Franka(path, name=name)


class BaseTask:
    """A task: builds its part of the scene, observes, and is stepped by the World.

    `World.add_task(task)` registers it; the next `World.reset()` calls `set_up_scene(scene)`
    once, then `post_reset()` at every reset; `World.step()` calls
    `pre_step(time_step_index, simulation_time)` before physics.

    Args:
        name: unique task name.
        offset: (3,) translation [m] applied to the task's objects (see
            `_move_task_objects_to_their_frame`).
    """

    def __init__(self, name: str, offset=None):
        self._name = name
        self._offset = vec(offset, 3, "offset") if offset is not None else np.zeros(3)
        self._scene: Scene | None = None
        self._task_objects: dict[str, Any] = {}

    @property
    def name(self) -> str:
        return self._name

    @property
    def scene(self) -> Scene | None:
        return self._scene

    def set_up_scene(self, scene: Scene) -> None:
        """Add the task's objects to `scene` (subclasses call this first)."""
        self._scene = scene

    def _move_task_objects_to_their_frame(self) -> None:
        """Translate every task object by `offset` (their current and default poses)."""
        if not np.any(self._offset):
            return
        for obj in self._task_objects.values():
            if hasattr(obj, "get_default_state") and hasattr(obj, "set_default_state"):
                s = obj.get_default_state()
                obj.set_default_state(position=s.position + self._offset)
            if hasattr(obj, "reference"):  # articulation: move the referenced model's frame
                obj.reference.position = obj.reference.position + self._offset
            elif hasattr(obj, "set_world_pose"):
                p, q = obj.get_world_pose()
                obj.set_world_pose(p + self._offset, q)

    def get_task_objects(self) -> dict:
        return dict(self._task_objects)

    def _not_implemented(self, method: str, returns: str) -> NotImplementedError:
        return NotImplementedError(
            f"{type(self).__name__}.{method}() is not implemented: override it in your task to return {returns} "
            "(BaseTask only declares it, as Isaac's)")

    def get_observations(self) -> dict:
        """The task's observations {object name: {quantity: value}} (override it)."""
        raise self._not_implemented("get_observations", "{object name: {quantity: value}}")

    def calculate_metrics(self) -> dict:
        """The task's metrics {name: value} (override it)."""
        raise self._not_implemented("calculate_metrics", "a dict of metrics")

    def is_done(self) -> bool:
        """Whether the task is done (override it)."""
        raise self._not_implemented("is_done", "a bool")

    def pre_step(self, time_step_index: int, simulation_time: float) -> None:
        """Called before each World step."""

    def post_reset(self) -> None:
        """Called after each World reset."""

    def get_description(self) -> str:
        return ""

    def get_params(self) -> dict:
        """The task's parameters {name: {"value": ..., "modifiable": bool}} (override it)."""
        raise self._not_implemented("get_params", '{name: {"value": ..., "modifiable": bool}}')

    def set_params(self, *args, **kwargs) -> None:
        """Change the task's modifiable parameters (override it)."""
        raise self._not_implemented("set_params", "None after changing the parameters")

    def cleanup(self) -> None:
        """Called at each `World.reset()` before the stage compiles (as Isaac's: remove here the
        objects the task added during the episode) and when the World is cleared."""


class PickPlace(BaseTask):
    """Franka pick-and-place of a cube (Isaac's `PickPlace` task for the Franka).

    Scene: the default ground plane, a Franka at the origin (prim "/World/Franka", name
    "my_franka"), a blue DynamicCuboid (prim "/World/Cube", name "cube") of `size=1.0`
    scaled by `cube_size`, as Isaac builds them.

    Observations: {cube_name: {"position", "orientation", "target_position"},
    robot_name: {"joint_positions", "end_effector_position"}} (end effector: the Franka's
    TCP between the fingertips).

    Metrics (Isaac leaves them unimplemented): `calculate_metrics()` gives the cube's distance
    to the target [m]; `is_done()` is True when that distance is below `success_tolerance`.

    Args:
        name: task name.
        cube_initial_position: (3,) [m] (Isaac's default [0.3, 0.3, 0.3]: the cube drops
            onto the ground at the first steps).
        cube_initial_orientation: (4,) (w, x, y, z).
        target_position: (3,) where the cube's centre should end [m] (Isaac's default
            [-0.3, -0.3, cube_size_z / 2]).
        cube_size: (3,) edge lengths [m], or one edge length (Isaac's default 0.0515 each).
        offset: (3,) translation of the whole task [m].
        cube_mass: [kg] (default 0.03).
        success_tolerance: [m] for `is_done`.
    """

    def __init__(self, name: str = "franka_pick_place", cube_initial_position=None, cube_initial_orientation=None,
                 target_position=None, cube_size=None, offset=None, *, cube_mass: float = 0.03,
                 success_tolerance: float = 0.01):
        super().__init__(name, offset)
        if cube_size is None:
            self._cube_size = np.full(3, 0.0515)
        elif np.ndim(cube_size) == 0:
            self._cube_size = np.full(3, positive(cube_size, "cube_size", "m"))
        else:
            self._cube_size = vec(cube_size, 3, "cube_size")
            if not np.all(self._cube_size > 0):
                raise InvalidInputError(f"cube_size must be positive edge lengths [m]; got {self._cube_size}")
        half = self._cube_size[2] / 2
        self._cube_position = (vec(cube_initial_position, 3, "cube_initial_position")
                               if cube_initial_position is not None else np.array([0.3, 0.3, 0.3]))
        self._cube_orientation = (unit_quat(cube_initial_orientation) if cube_initial_orientation is not None
                                  else np.array([1.0, 0.0, 0.0, 0.0]))
        self._target_position = (vec(target_position, 3, "target_position") if target_position is not None
                                 else np.array([-0.3, -0.3, half]))
        self._cube_mass = positive(cube_mass, "cube_mass", "kg")
        self._tolerance = positive(success_tolerance, "success_tolerance", "m")
        self._cube: DynamicCuboid | None = None
        self._robot: Franka | None = None

    def set_up_scene(self, scene: Scene) -> None:
        super().set_up_scene(scene)
        scene.add_default_ground_plane()
        stage = get_current_stage()
        cube_path = find_unique_string_name("/World/Cube", lambda p: stage.get_prim(p) is None)
        cube_name = find_unique_string_name("cube", lambda n: not scene.object_exists(n))
        self._cube = scene.add(DynamicCuboid(cube_path, name=cube_name, position=self._cube_position,
                                             orientation=self._cube_orientation, size=1.0, scale=self._cube_size,
                                             mass=self._cube_mass, color=[0.0, 0.0, 1.0]))
        self._task_objects[self._cube.name] = self._cube
        self._robot = scene.add(self.set_robot())
        self._task_objects[self._robot.name] = self._robot
        self._move_task_objects_to_their_frame()
        self._target_position = self._target_position + self._offset

    def set_robot(self) -> Franka:
        """The robot of the task (override to change it)."""
        return new_franka(self._scene)

    @property
    def cube(self) -> DynamicCuboid | None:
        return self._cube

    @property
    def robot(self) -> Franka | None:
        return self._robot

    def get_observations(self) -> dict:
        p, q = self._cube.get_world_pose()
        return {
            self._cube.name: {"position": p, "orientation": q, "target_position": self._target_position.copy()},
            self._robot.name: {
                "joint_positions": self._robot.get_joint_positions(),
                "end_effector_position": self._robot.end_effector.get_world_pose()[0],
            },
        }

    def get_params(self) -> dict:
        p, q = self._cube.get_world_pose()
        return {
            "cube_name": {"value": self._cube.name, "modifiable": False},
            "robot_name": {"value": self._robot.name, "modifiable": False},
            "cube_position": {"value": p, "modifiable": True},
            "cube_orientation": {"value": q, "modifiable": True},
            "target_position": {"value": self._target_position.copy(), "modifiable": True},
            "cube_size": {"value": self._cube_size.copy(), "modifiable": False},
        }

    def set_params(self, cube_position=None, cube_orientation=None, target_position=None) -> None:
        """Move the cube now and/or change the target (not the defaults restored by reset)."""
        if target_position is not None:
            self._target_position = vec(target_position, 3, "target_position")
        if cube_position is not None or cube_orientation is not None:
            self._cube.set_world_pose(cube_position, cube_orientation)

    def calculate_metrics(self) -> dict:
        d = float(np.linalg.norm(self._cube.get_world_pose()[0] - self._target_position))
        return {"cube_to_target_distance": d}

    def is_done(self) -> bool:
        return self.calculate_metrics()["cube_to_target_distance"] < self._tolerance

    def post_reset(self) -> None:
        self._robot.gripper.set_joint_positions(self._robot.gripper.joint_opened_positions)
