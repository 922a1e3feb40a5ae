"""IK targets as draggable gizmos: drag the target, release, and the robot plans to it.

`TargetGizmo` puts a transform-controls gizmo `/target` in the scene at a pose of the
end-effector. When the user releases it (viser's drag phase "end"), `on_release` is
called with the gizmo's pose (a `Pose` in the base frame); the `Viewer` plans to it
(`MotionGenerator.plan_pose`) and shows the result and its status in the GUI.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import numpy as np

from manip.pose import Pose

logger = logging.getLogger(__name__)


class TargetGizmo:
    """A draggable pose target.

    Args:
        scene: a viser `SceneApi`.
        pose: where the gizmo starts (base frame).
        on_release: called with the gizmo's `Pose` when a drag ends.
        name: scene-tree name of the gizmo.
        scale: gizmo size [m].
    """

    def __init__(self, scene: Any, pose: Pose, on_release: Callable[[Pose], None], *, name: str = "/target",
                 scale: float = 0.15):
        self.name = name
        self._on_release = on_release
        self.handle = scene.add_transform_controls(
            name, scale=scale, position=np.asarray(pose.position), wxyz=np.asarray(pose.quaternion))
        self.handle.on_update(self._on_update)

    @property
    def pose(self) -> Pose:
        """The gizmo's current pose (base frame)."""
        return Pose(np.array(self.handle.position, dtype=float), np.array(self.handle.wxyz, dtype=float))

    def move_to(self, pose: Pose) -> None:
        """Place the gizmo at `pose` (without planning)."""
        self.handle.position = np.asarray(pose.position)
        self.handle.wxyz = np.asarray(pose.quaternion)

    def _on_update(self, event: Any) -> None:
        if getattr(event, "phase", "end") != "end":
            return
        try:
            self._on_release(self.pose)
        except Exception:  # a callback thread: log, the viewer keeps running
            logger.exception("planning to the gizmo's target failed")

    def remove(self) -> None:
        """Remove the gizmo from the scene."""
        self.handle.remove()
