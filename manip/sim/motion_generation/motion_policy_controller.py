"""`MotionPolicyController`: Isaac's controller stepping a motion policy towards an end-effector target.

    controller = MotionPolicyController("follow", ArticulationMotionPolicy(franka, rmpflow))
    action = controller.forward(target_end_effector_position, target_end_effector_orientation)
    franka.apply_action(action)

Each `forward` sets the policy's end-effector target, updates its world (`update_world()`:
the obstacles' poses are re-read) and returns the policy's next ArticulationAction, as
Isaac's. `reset()` resets the policy, which (as Isaac's RmpFlow) forgets its obstacles and
its base pose.
"""

from __future__ import annotations

from typing import Any

from manip.articulation_action import ArticulationAction
from manip.errors import InvalidInputError
from manip.sim.controllers.base_controller import BaseController
from manip.sim.motion_generation.articulation_motion_policy import ArticulationMotionPolicy


class MotionPolicyController(BaseController):
    """A controller that steps an `ArticulationMotionPolicy`.

    Args:
        name: controller name.
        articulation_motion_policy: the policy on its robot.

    Raises:
        InvalidInputError: not an ArticulationMotionPolicy.
    """

    def __init__(self, name: str, articulation_motion_policy: ArticulationMotionPolicy):
        super().__init__(name)
        if not isinstance(articulation_motion_policy, ArticulationMotionPolicy):
            raise InvalidInputError(f"articulation_motion_policy must be an ArticulationMotionPolicy; "
                                    f"got {type(articulation_motion_policy).__name__}")
        self._articulation_motion_policy = articulation_motion_policy
        self._motion_policy = articulation_motion_policy.get_motion_policy()

    def forward(self, target_end_effector_position, target_end_effector_orientation=None) -> ArticulationAction:
        """The action for the next frame towards a world target: position (3,) [m], orientation
        (4,) (w, x, y, z) or None (any orientation)."""
        self._motion_policy.set_end_effector_target(target_end_effector_position, target_end_effector_orientation)
        self._motion_policy.update_world()
        return self._articulation_motion_policy.get_next_articulation_action()

    def add_obstacle(self, obstacle: Any, static: bool = False) -> None:
        """Give the policy an obstacle (a manip.sim shape object)."""
        self._motion_policy.add_obstacle(obstacle, static=static)

    def remove_obstacle(self, obstacle: Any) -> None:
        """Take an added obstacle away from the policy."""
        self._motion_policy.remove_obstacle(obstacle)

    def reset(self) -> None:
        """Reset the policy (see the module docstring)."""
        self._motion_policy.reset()

    def get_articulation_motion_policy(self) -> ArticulationMotionPolicy:
        return self._articulation_motion_policy

    def get_motion_policy(self) -> Any:
        return self._motion_policy


__all__ = ["MotionPolicyController"]
