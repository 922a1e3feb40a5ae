"""Importing manip.sim changes no environment variable; the GL backend is chosen once, at the first render."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from manip.sim.core import gl_backend

_HEADLESS_ENV = {k: v for k, v in os.environ.items()
                 if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MUJOCO_GL", "PYOPENGL_PLATFORM")}


def _run(code: str) -> dict:
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          env=_HEADLESS_ENV)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_import_leaves_the_environment_unchanged():
    out = _run(
        "import json, os\n"
        "before = dict(os.environ)\n"
        "import manip.sim\n"
        "after = dict(os.environ)\n"
        "print(json.dumps({'added': sorted(set(after) - set(before)), 'removed': sorted(set(before) - set(after)),\n"
        "                  'changed': sorted(k for k in before if k in after and before[k] != after[k])}))\n"
    )
    assert out == {"added": [], "removed": [], "changed": []}


@pytest.mark.skipif(not sys.platform.startswith("linux") or gl_backend.choose_gl_backend() is None,
                    reason="needs Linux with EGL or OSMesa")
def test_first_render_without_display_picks_egl_or_osmesa():
    out = _run(
        "import json, os\n"
        "from manip.sim import World, DynamicCuboid\nfrom manip.sim.core import gl_backend\n"
        "w = World(); w.scene.add(DynamicCuboid('/World/c', name='c', size=0.1)); w.reset()\n"
        "before = os.environ.get('MUJOCO_GL')\n"
        "image = w.render_image(32, 24)\n"
        "print(json.dumps({'before': before, 'after': os.environ.get('MUJOCO_GL'), 'shape': list(image.shape),\n"
        "                  'chosen': gl_backend.ensure_offscreen_gl()}))\n"
    )
    backend = gl_backend.choose_gl_backend()
    assert out == {"before": None, "after": backend, "shape": [24, 32, 3], "chosen": backend}


def test_backend_is_chosen_once(monkeypatch):
    calls = []
    monkeypatch.setattr(gl_backend, "_chosen", gl_backend._UNSET)
    monkeypatch.setattr(gl_backend, "_switch_to_headless_backend", lambda: calls.append(1) or "egl")
    assert gl_backend.ensure_offscreen_gl() == "egl"
    assert gl_backend.ensure_offscreen_gl() == "egl"
    assert calls == [1]


def test_user_choice_is_kept(monkeypatch):
    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    assert gl_backend._switch_to_headless_backend() is None
    assert os.environ["MUJOCO_GL"] == "osmesa"
