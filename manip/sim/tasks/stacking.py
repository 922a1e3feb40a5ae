"""Isaac's Franka `Stacking` task: cubes to pick and stack at one target, in order.

    task = Stacking()
    world.add_task(task)
    world.reset()
    controller = StackingController("stacking_controller", gripper=franka.gripper, robot_articulation=franka,
                                    picking_order_cube_names=task.get_cube_names(), robot_observation_name="my_franka")
    franka.get_articulation_controller().apply_action(controller.forward(observations=world.get_observations()))

As Isaac's (`omni.isaac.franka.tasks.Stacking` on `omni.isaac.core.tasks.Stacking`): the
default ground plane, one blue-ish DynamicCuboid per initial position (prims "/World/Cube",
"/World/Cube_1", ..., names "cube", "cube_1", ...; `size=1.0` scaled by `cube_size`), a
Franka ("/World/Franka", name "my_franka"); the i-th cube's target is the stack position
raised by i cube heights plus half of one. Differences: the cubes' colours are fixed (Isaac
draws them at random), and `calculate_metrics` / `is_done` are implemented (Isaac leaves
them unimplemented): each cube's distance to its target, done when all are within
`success_tolerance`.
"""

from __future__ import annotations

import numpy as np

from manip.errors import InvalidInputError
from manip.sim.objects import DynamicCuboid
from manip.sim.robots.robot import Franka
from manip.sim.scenes.scene import Scene
from manip.sim.scenes.stage import get_current_stage
from manip.sim.tasks.base_task import BaseTask, find_unique_string_name, new_franka
from manip.validation import as_real_array, positive, unit_quat, vec

#: The cubes' colours, in turn (RGB in [0, 1]).
COLORS = np.array([[0.1, 0.3, 0.9], [0.9, 0.4, 0.1], [0.2, 0.7, 0.3], [0.7, 0.2, 0.7]])


class Stacking(BaseTask):
    """Stack cubes at a target with a Franka (Isaac's Franka `Stacking` task).

    Args:
        name: task name.
        target_position: (3,) where the stack stands [m]: its x and y are used (Isaac's default
            [0.5, 0.5, 0]).
        cube_size: (3,) edge lengths [m] (Isaac's default 0.0515 each).
        offset: (3,) translation of the whole task [m].
        cube_initial_positions: (N, 3) the cubes' centres [m] (Isaac's [[0.3, 0.3, 0.3],
            [0.3, -0.3, 0.3]]: they drop onto the ground at the first steps).
        cube_initial_orientations: (N, 4) (w, x, y, z), or None (identity).
        success_tolerance: [m] for `is_done`.

    Raises:
        InvalidInputError: bad arguments (named in the message).
    """

    def __init__(self, name: str = "franka_stacking", target_position=None, cube_size=None, offset=None, *,
                 cube_initial_positions=None, cube_initial_orientations=None, success_tolerance: float = 0.02):
        super().__init__(name, offset)
        positions = (np.array([[0.3, 0.3, 0.3], [0.3, -0.3, 0.3]]) if cube_initial_positions is None
                     else as_real_array(cube_initial_positions, "cube_initial_positions"))
        if positions.ndim != 2 or positions.shape[1] != 3 or len(positions) == 0:
            raise InvalidInputError(f"cube_initial_positions must have shape (N, 3); got {positions.shape}")
        self._positions = positions
        if cube_initial_orientations is None:
            self._orientations = np.tile([1.0, 0.0, 0.0, 0.0], (len(positions), 1))
        else:
            given = as_real_array(cube_initial_orientations, "cube_initial_orientations")
            if given.shape != (len(positions), 4):
                raise InvalidInputError(f"cube_initial_orientations must have shape ({len(positions)}, 4); "
                                        f"got {given.shape}")
            self._orientations = np.array([unit_quat(q, "cube_initial_orientations") for q in given])
        self._cube_size = np.full(3, 0.0515) if cube_size is None else vec(cube_size, 3, "cube_size")
        if not np.all(self._cube_size > 0):
            raise InvalidInputError(f"cube_size must be positive edge lengths [m]; got {self._cube_size}")
        target = np.array([0.5, 0.5, 0.0]) if target_position is None else vec(target_position, 3, "target_position")
        self._stack_target_position = target + self._offset
        self._tolerance = positive(success_tolerance, "success_tolerance", "m")
        self._cubes: list[DynamicCuboid] = []
        self._robot: Franka | None = None

    def set_up_scene(self, scene: Scene) -> None:
        super().set_up_scene(scene)
        scene.add_default_ground_plane()
        stage = get_current_stage()
        for i, (p, q) in enumerate(zip(self._positions, self._orientations)):
            path = find_unique_string_name("/World/Cube", lambda s: stage.get_prim(s) is None)
            name = find_unique_string_name("cube", lambda n: not scene.object_exists(n))
            cube = scene.add(DynamicCuboid(path, name=name, position=p, orientation=q, size=1.0, scale=self._cube_size,
                                           color=COLORS[i % len(COLORS)]))
            self._cubes.append(cube)
            self._task_objects[cube.name] = cube
        self._robot = scene.add(self.set_robot())
        self._task_objects[self._robot.name] = self._robot
        self._move_task_objects_to_their_frame()

    def set_robot(self) -> Franka:
        """The robot of the task (override to change it)."""
        return new_franka(self._scene)

    @property
    def robot(self) -> Franka | None:
        return self._robot

    def get_cube_names(self) -> list[str]:
        """The cubes' names, in the order they are stacked."""
        return [c.name for c in self._cubes]

    def _target(self, i: int) -> np.ndarray:
        h = self._cube_size[2]
        return np.array([self._stack_target_position[0], self._stack_target_position[1], h * i + h / 2.0])

    def get_observations(self) -> dict:
        obs = {self._robot.name: {"joint_positions": self._robot.get_joint_positions(),
                                  "end_effector_position": self._robot.end_effector.get_world_pose()[0]}}
        for i, cube in enumerate(self._cubes):
            p, q = cube.get_world_pose()
            obs[cube.name] = {"position": p, "orientation": q, "target_position": self._target(i)}
        return obs

    def get_params(self) -> dict:
        return {"stack_target_position": {"value": self._stack_target_position.copy(), "modifiable": True},
                "robot_name": {"value": self._robot.name, "modifiable": False}}

    def set_params(self, cube_name: str | None = None, cube_position=None, cube_orientation=None,
                   stack_target_position=None) -> None:
        """Move the stack's target, and/or move one cube now (not its default pose).

        Raises:
            InvalidInputError: an unknown cube (the message lists them), a bad vector.
        """
        if stack_target_position is not None:
            self._stack_target_position = vec(stack_target_position, 3, "stack_target_position")
        if cube_name is not None:
            if cube_name not in self.get_cube_names():
                raise InvalidInputError(f"set_params: no cube named {cube_name!r}; cubes: {self.get_cube_names()}")
            self._task_objects[cube_name].set_world_pose(cube_position, cube_orientation)

    def calculate_metrics(self) -> dict:
        """{cube name: distance [m] of its centre to its place in the stack}."""
        return {c.name: float(np.linalg.norm(c.get_world_pose()[0] - self._target(i)))
                for i, c in enumerate(self._cubes)}

    def is_done(self) -> bool:
        return all(d < self._tolerance for d in self.calculate_metrics().values())

    def post_reset(self) -> None:
        self._robot.gripper.set_joint_positions(self._robot.gripper.joint_opened_positions)


__all__ = ["COLORS", "Stacking"]
