"""The OpenGL backend of MuJoCo's offscreen renderer, chosen once, when rendering is first needed.

MuJoCo renders offscreen through GLFW (needs a display), EGL (GPU or Mesa; Debian/Ubuntu
package `libegl1`) or OSMesa (pure software; package `libosmesa6`). `import mujoco` picks
one from the `MUJOCO_GL` environment variable (GLFW when unset). Importing `manip.sim`
changes nothing; the first offscreen render calls `ensure_offscreen_gl()`, which, when
`MUJOCO_GL` is unset and there is no display (Linux), points MuJoCo's renderer at EGL (or
OSMesa) and records the choice in `MUJOCO_GL`.
"""

from __future__ import annotations

import ctypes.util
import logging
import os
import sys

logger = logging.getLogger(__name__)

_UNSET = object()
_chosen: object = _UNSET  # the result of the first ensure_offscreen_gl() call


def choose_gl_backend() -> str | None:
    """The MUJOCO_GL value to use headless: "egl" if libEGL is found, else "osmesa" if
    libOSMesa is found, else None."""
    if ctypes.util.find_library("EGL"):
        return "egl"
    if ctypes.util.find_library("OSMesa"):
        return "osmesa"
    return None


def has_display() -> bool:
    """Whether a window can be opened: DISPLAY or WAYLAND_DISPLAY is set, or not Linux."""
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")) or not sys.platform.startswith("linux")


def gl_help() -> str:
    """What to install and set for offscreen rendering (for error messages)."""
    return (
        f"MUJOCO_GL={os.environ.get('MUJOCO_GL', '(unset)')}. Offscreen rendering needs an OpenGL backend: "
        "install EGL (`sudo apt install libegl1`, set MUJOCO_GL=egl) or OSMesa (`sudo apt install libosmesa6`, "
        "set MUJOCO_GL=osmesa), and set MUJOCO_GL before Python imports mujoco."
    )


def ensure_offscreen_gl() -> str | None:
    """Make MuJoCo's renderer usable offscreen; called before each `mujoco.Renderer`, acts once.

    If mujoco chose GLFW (MUJOCO_GL unset) and there is no display, switch its renderer to
    EGL or OSMesa (whichever is installed) and set MUJOCO_GL to it. Otherwise keep mujoco's
    choice (MUJOCO_GL set by the user, or a display).

    Returns:
        The backend switched to ("egl" / "osmesa"), or None if mujoco's choice was kept
        (or nothing usable was found: creating the renderer then fails with `gl_help()`).
    """
    global _chosen
    if _chosen is _UNSET:
        _chosen = _switch_to_headless_backend()
    return _chosen  # type: ignore[return-value]


def _switch_to_headless_backend() -> str | None:
    if os.environ.get("MUJOCO_GL") or has_display():
        return None
    try:
        from mujoco.rendering.classic import gl_context
    except ImportError:  # another mujoco layout: leave it alone
        return None
    cls = getattr(gl_context, "GLContext", None)
    if cls is None or "glfw" not in cls.__module__:
        return None
    backend = choose_gl_backend()
    if backend is None:
        return None
    try:
        if backend == "egl":
            from mujoco.egl import GLContext
        else:
            from mujoco.osmesa import GLContext
    except Exception as exc:  # PyOpenGL bound to another platform, missing module...
        logger.debug("cannot switch MuJoCo's renderer to %s: %s", backend, exc)
        return None
    gl_context.GLContext = GLContext
    os.environ["MUJOCO_GL"] = backend
    logger.info("no display: MuJoCo renders offscreen through %s", backend)
    return backend
