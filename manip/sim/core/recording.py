"""Offscreen rendering and MP4 recording of a camera view.

MuJoCo renders offscreen through EGL (GPU or Mesa; Debian/Ubuntu package `libegl1`) or
OSMesa (pure software; package `libosmesa6`). The backend is chosen once, at the first
render, by `manip.sim.core.gl_backend.ensure_offscreen_gl` (EGL or OSMesa when `MUJOCO_GL` is
unset and there is no display). Writing MP4 needs the `video` extra
(`pip install "manip-robotics[video]"`: imageio + imageio-ffmpeg).
"""

from __future__ import annotations

import logging
from pathlib import Path

import mujoco
import numpy as np

from manip.errors import InvalidInputError, ManipError, UnknownNameError
from manip.sim.core.gl_backend import choose_gl_backend, ensure_offscreen_gl, gl_help  # noqa: F401 (re-exported)
from manip.sim.scenes.stage import SimHandle
from manip.validation import positive, vec

logger = logging.getLogger(__name__)


class OffscreenRenderingError(ManipError):
    """No offscreen OpenGL backend (EGL or OSMesa) is available, or MP4 writing is not installed."""


class CameraView:
    """A free camera of the World's viewer and recordings: look-at point (3,) [m], distance [m],
    azimuth and elevation [deg]. (Not Isaac's `omni.isaac.sensor.CameraView`, a batched view of
    camera prims: that one raises NotImplementedError here, saying so.)"""

    def __init__(self, lookat=(0.2, 0.0, 0.2), *, distance: float = 2.0, azimuth: float = 135.0,
                 elevation: float = -25.0, **isaac_arguments):
        if isinstance(lookat, str) or isaac_arguments:
            raise NotImplementedError(
                "Isaac's omni.isaac.sensor.CameraView (a batched view of camera prims) is not implemented in manip: "
                "use one manip.sim.Camera per camera prim. manip.sim.CameraView is the viewer's and recordings' "
                "free camera: CameraView(lookat=(x, y, z), distance=..., azimuth=..., elevation=...)")
        self.lookat = vec(lookat, 3, "CameraView lookat")
        self.distance = positive(distance, "CameraView distance", "m")
        self.azimuth = float(vec(azimuth, 1, "CameraView azimuth")[0])       # [deg], finite
        self.elevation = float(vec(elevation, 1, "CameraView elevation")[0])

    @classmethod
    def from_eye_target(cls, eye, target) -> CameraView:
        """The view from `eye` (3,) looking at `target` (3,) (Isaac's `set_camera_view`)."""
        eye = vec(eye, 3, "eye")
        target = vec(target, 3, "target")
        v = target - eye
        dist = float(np.linalg.norm(v))
        if dist <= 0 or not np.isfinite(dist):
            raise InvalidInputError("camera eye and target must be distinct finite points")
        az = float(np.degrees(np.arctan2(v[1], v[0])))
        el = float(np.degrees(np.arcsin(v[2] / dist)))
        return cls(target, distance=dist, azimuth=az, elevation=el)

    def apply(self, cam: mujoco.MjvCamera) -> None:
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = self.lookat
        cam.distance = self.distance
        cam.azimuth = self.azimuth
        cam.elevation = self.elevation


class Recorder:
    """Writes frames of a camera view to an MP4 file while the World steps.

    Args:
        model: the compiled model (the renderer is bound to it).
        path: output .mp4 path.
        camera: a named camera of the model, a `CameraView`, or None (the World's view).
        width, height: frame size [px] (at most the model's offscreen buffer, 1920 x 1080).
        fps: frames per second of simulated time.
    """

    def __init__(self, model: mujoco.MjModel, path: str | Path, camera: str | CameraView | None = None, *,
                 width: int = 640, height: int = 480, fps: float = 30.0):
        try:
            import imageio.v2 as imageio
        except ImportError as exc:
            raise OffscreenRenderingError("writing MP4 needs the video extra: pip install 'manip-robotics[video]'") from exc
        if width <= 0 or height <= 0 or width > model.vis.global_.offwidth or height > model.vis.global_.offheight:
            raise InvalidInputError(
                f"frame size {width}x{height} must be positive and at most "
                f"{model.vis.global_.offwidth}x{model.vis.global_.offheight}"
            )
        self.fps = positive(fps, "fps", "1/s")
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.camera = camera
        self.frames = 0
        self._next_time = 0.0
        self.renderer = make_renderer(model, width, height)
        self._writer = imageio.get_writer(str(self.path), fps=self.fps, codec="libx264", quality=7,
                                          macro_block_size=1, ffmpeg_log_level="error")

    def maybe_capture(self, data: mujoco.MjData, time: float, view: CameraView) -> None:
        """Capture a frame if at least 1/fps of simulated time passed since the last one."""
        if time + 1e-9 < self._next_time:
            return
        self._next_time = time + 1.0 / self.fps
        self.capture(data, view)

    def capture(self, data: mujoco.MjData, view: CameraView) -> None:
        """Write one frame (of `view` when the recorder has no camera of its own)."""
        _update_scene(self.renderer, data, self.camera, view)
        self._writer.append_data(self.renderer.render())
        self.frames += 1

    def close(self) -> None:
        self._writer.close()
        self.renderer.close()
        logger.info("wrote %d frames to %s", self.frames, self.path)


def check_camera(model: mujoco.MjModel, camera: str | CameraView | None) -> None:
    """Raise UnknownNameError (listing the model's cameras) if `camera` names none of them."""
    if isinstance(camera, str) and mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera) < 0:
        raise UnknownNameError("camera", camera, [model.camera(i).name for i in range(model.ncam)])


def make_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """A `mujoco.Renderer` of width x height [px], or OffscreenRenderingError saying what to install."""
    ensure_offscreen_gl()
    try:
        return mujoco.Renderer(model, height=height, width=width)
    except Exception as exc:  # GL context creation raises various errors
        raise OffscreenRenderingError(f"cannot create an offscreen OpenGL context ({exc}). {gl_help()}") from exc


def render_image(sim: SimHandle, width: int, height: int, camera: str | CameraView | None,
                 view: CameraView) -> np.ndarray:
    """One RGB image (height, width, 3) uint8 of the current state, from a named model camera,
    a CameraView, or `view` when camera is None."""
    r = make_renderer(sim.model, width, height)
    try:
        sim.ensure_kinematics()
        _update_scene(r, sim.data, camera, view)
        return r.render().copy()
    finally:
        r.close()


def _update_scene(renderer: mujoco.Renderer, data: mujoco.MjData, camera: str | CameraView | None,
                  view: CameraView) -> None:
    if isinstance(camera, str):
        renderer.update_scene(data, camera=camera)
    else:
        cam = mujoco.MjvCamera()
        (camera if isinstance(camera, CameraView) else view).apply(cam)
        renderer.update_scene(data, camera=cam)
