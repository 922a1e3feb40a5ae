"""Offscreen rendering and MP4 recording of a camera view.

MuJoCo renders offscreen through EGL (GPU or Mesa; Debian/Ubuntu package `libegl1`) or
OSMesa (pure software; package `libosmesa6`). The backend is chosen by the `MUJOCO_GL`
environment variable *before* MuJoCo is imported; `manip.sim` sets it to "egl" (or
"osmesa") when it is unset and there is no display. Writing MP4 needs the `video` extra
(`pip install manip[video]`: imageio + imageio-ffmpeg).
"""

from __future__ import annotations

import ctypes.util
import logging
import os
from pathlib import Path

import mujoco
import numpy as np

from manip.errors import InvalidInputError, ManipError

logger = logging.getLogger(__name__)


class OffscreenRenderingError(ManipError):
    """No offscreen OpenGL backend (EGL or OSMesa) is available, or MP4 writing is not installed."""


def choose_gl_backend() -> str | None:
    """The MUJOCO_GL value to use headless: "egl" if libEGL is found, else "osmesa" if
    libOSMesa is found, else None."""
    if ctypes.util.find_library("EGL"):
        return "egl"
    if ctypes.util.find_library("OSMesa"):
        return "osmesa"
    return None


def _gl_help() -> str:
    return (
        f"MUJOCO_GL={os.environ.get('MUJOCO_GL', '(unset)')}. Offscreen rendering needs an OpenGL backend: "
        "install EGL (`sudo apt install libegl1`, set MUJOCO_GL=egl) or OSMesa (`sudo apt install libosmesa6`, "
        "set MUJOCO_GL=osmesa), and set MUJOCO_GL before Python imports mujoco."
    )


class CameraView:
    """A free camera: look-at point [m], distance [m], azimuth and elevation [deg]."""

    def __init__(self, lookat=(0.2, 0.0, 0.2), distance: float = 2.0, azimuth: float = 135.0, elevation: float = -25.0):
        self.lookat = np.asarray(lookat, dtype=float)
        self.distance = float(distance)
        self.azimuth = float(azimuth)
        self.elevation = float(elevation)

    @classmethod
    def from_eye_target(cls, eye, target) -> CameraView:
        """The view from `eye` (3,) looking at `target` (3,) (Isaac's `set_camera_view`)."""
        eye = np.asarray(eye, dtype=float)
        target = np.asarray(target, dtype=float)
        v = target - eye
        dist = float(np.linalg.norm(v))
        if dist <= 0 or not np.isfinite(dist):
            raise InvalidInputError("camera eye and target must be distinct finite points")
        az = float(np.degrees(np.arctan2(v[1], v[0])))
        el = float(np.degrees(np.arcsin(v[2] / dist)))
        return cls(target, dist, az, el)

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

    def __init__(self, model: mujoco.MjModel, path: str | Path, camera, width: int, height: int, fps: float):
        try:
            import imageio.v2 as imageio
        except ImportError as exc:
            raise OffscreenRenderingError("writing MP4 needs the video extra: pip install 'manip[video]'") from exc
        if width <= 0 or height <= 0 or width > model.vis.global_.offwidth or height > model.vis.global_.offheight:
            raise InvalidInputError(
                f"frame size {width}x{height} must be positive and at most "
                f"{model.vis.global_.offwidth}x{model.vis.global_.offheight}"
            )
        if not fps > 0:
            raise InvalidInputError(f"fps must be > 0; got {fps}")
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.fps = float(fps)
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
        if isinstance(self.camera, str):
            self.renderer.update_scene(data, camera=self.camera)
        else:
            cam = mujoco.MjvCamera()
            (self.camera if isinstance(self.camera, CameraView) else view).apply(cam)
            self.renderer.update_scene(data, camera=cam)
        self._writer.append_data(self.renderer.render())
        self.frames += 1

    def close(self) -> None:
        self._writer.close()
        self.renderer.close()
        logger.info("wrote %d frames to %s", self.frames, self.path)


def _switch_to_headless_backend() -> bool:
    """If mujoco was imported before MUJOCO_GL was set (so it chose GLFW, which needs a
    display), point its renderer at EGL or OSMesa instead. Returns whether it switched."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or os.environ.get("MUJOCO_GL"):
        return False
    backend = choose_gl_backend()
    if backend is None:
        return False
    try:
        from mujoco.rendering.classic import gl_context

        if backend == "egl":
            from mujoco.egl import GLContext
        else:
            from mujoco.osmesa import GLContext
        gl_context.GLContext = GLContext
    except Exception as exc:  # PyOpenGL bound to another platform, missing module...
        logger.debug("cannot switch MuJoCo's renderer to %s: %s", backend, exc)
        return False
    os.environ["MUJOCO_GL"] = backend
    logger.info("no display: MuJoCo renders offscreen through %s", backend)
    return True


def make_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """A `mujoco.Renderer`, or OffscreenRenderingError saying what to install."""
    try:
        from mujoco.rendering.classic import gl_context

        cls = getattr(gl_context, "GLContext", None)
        if cls is not None and "glfw" in cls.__module__:
            _switch_to_headless_backend()  # GLFW without a display would fail (or abort)
    except ImportError:
        pass
    try:
        return mujoco.Renderer(model, height=height, width=width)
    except Exception as exc:  # GL context creation raises various errors
        raise OffscreenRenderingError(f"cannot create an offscreen OpenGL context ({exc}). {_gl_help()}") from exc
