"""Isaac's `omni.isaac.core.utils.viewports.set_camera_view` (`isaacsim.core.utils.viewports`):
standalone scripts point the viewport at the scene with it after creating the World."""

from __future__ import annotations

import logging

from manip.errors import InvalidInputError
from manip.sim.core.world import World

logger = logging.getLogger(__name__)

#: The viewport camera Isaac's function moves by default (the only one here: the World's view).
VIEWPORT_CAMERA = "/OmniverseKit_Persp"


def set_camera_view(eye, target, camera_prim_path: str = VIEWPORT_CAMERA, viewport_api=None) -> None:
    """Point the World's view (MuJoCo's viewer and `World.start_recording`'s default camera)
    from `eye` (3,) at `target` (3,) [m] (`World.set_camera_view`).

    Args:
        eye: camera position (3,) [m].
        target: the point looked at (3,) [m].
        camera_prim_path: Isaac's viewport camera, "/OmniverseKit_Persp" (the only view
            here; for a `Camera` prim, set its pose).
        viewport_api: accepted for Isaac's signature (there is one view).

    Raises:
        InvalidInputError: another camera prim path (move a `Camera` with set_world_pose), or
            a bad eye / target.
    """
    if camera_prim_path != VIEWPORT_CAMERA:
        raise InvalidInputError(f"set_camera_view moves the viewport camera {VIEWPORT_CAMERA!r} only; got "
                                f"{camera_prim_path!r} (a Camera prim is moved with camera.set_world_pose)")
    world = World.instance()
    if world is None:  # Isaac logs and returns when no viewport exists
        logger.warning("set_camera_view: no World yet, nothing to point; create the World first")
        return
    world.set_camera_view(eye, target)
