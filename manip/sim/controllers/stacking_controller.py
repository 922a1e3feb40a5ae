"""Isaac's Franka `StackingController`: one `PickPlaceController` run per cube, in order.

    controller = StackingController("stacking_controller", gripper=franka.gripper, robot_articulation=franka,
                                    picking_order_cube_names=task.get_cube_names(), robot_observation_name="my_franka")
    action = controller.forward(observations=world.get_observations())

As Isaac's: each `forward` picks the current cube at its observed "position" and places it
at its "target_position"; when the pick-and-place controller is done, the next cube
follows; after the last one, every call returns an action that holds all joints (None
entries). If the pick-and-place controller ends a cube with a failed grasp
(`PickPlaceController.failure`), the sequence goes on with the next cube, as Isaac's
(which cannot tell); `failures` lists them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.controllers.base_controller import BaseController
from manip.sim.controllers.pick_place_controller import PickPlaceController


class StackingController(BaseController):
    """Pick and place cubes one after the other (Isaac's Franka `StackingController`).

    Args:
        name: controller name.
        gripper: the robot's `ParallelGripper`.
        robot_articulation: the robot (a `Franka`).
        picking_order_cube_names: the cubes' observation names, in stacking order.
        robot_observation_name: the robot's observation name.

    Raises:
        InvalidInputError: an empty or non-string cube list.
    """

    def __init__(self, name: str, gripper: Any, robot_articulation: Any, picking_order_cube_names: list[str],
                 robot_observation_name: str):
        super().__init__(name)
        self._pick_place = PickPlaceController(name=name + "_pick_place_controller", gripper=gripper,
                                               robot_articulation=robot_articulation)
        self._order = self._names(picking_order_cube_names)
        self._robot_name = robot_observation_name
        self._current = 0
        self.failures: list[tuple[str, str]] = []

    @staticmethod
    def _names(names: Any) -> list[str]:
        if isinstance(names, str) or not all(isinstance(n, str) for n in names) or len(names) == 0:
            raise InvalidInputError(f"picking_order_cube_names must be a non-empty list of cube names; got {names!r}")
        return list(names)

    @property
    def pick_place_controller(self) -> PickPlaceController:
        return self._pick_place

    def forward(self, observations: dict, end_effector_orientation=None, end_effector_offset=None
                ) -> ArticulationAction:
        """The next action: the current cube's pick-and-place step, or a hold when all are done.

        Raises:
            InvalidInputError: the observations lack the robot or the current cube (the message
                lists the names they have).
        """
        if self._robot_name not in observations:
            raise InvalidInputError(f"observations have no robot {self._robot_name!r}; names: {sorted(observations)}")
        q = np.asarray(observations[self._robot_name]["joint_positions"], dtype=float)
        if self.is_done():
            return ArticulationAction(joint_positions=[None] * q.shape[0])
        cube = self._order[self._current]
        if cube not in observations:
            raise InvalidInputError(f"observations have no cube {cube!r}; names: {sorted(observations)}")
        actions = self._pick_place.forward(
            picking_position=observations[cube]["position"],
            placing_position=observations[cube]["target_position"],
            current_joint_positions=q,
            end_effector_orientation=end_effector_orientation,
            end_effector_offset=end_effector_offset,
        )
        if self._pick_place.is_done():
            if self._pick_place.failure is not None:
                self.failures.append((cube, str(self._pick_place.failure)))
            self._current += 1
            self._pick_place.reset()
        return actions

    def reset(self, picking_order_cube_names: list[str] | None = None) -> None:
        """Start again from the first cube (of a new order, if given)."""
        self._current = 0
        self.failures = []
        self._pick_place.reset()
        if picking_order_cube_names is not None:
            self._order = self._names(picking_order_cube_names)

    def is_done(self) -> bool:
        """True once every cube has been placed."""
        return self._current >= len(self._order)


__all__ = ["StackingController"]
