"""The viewer in a real browser: headless Debian chromium opens the page and the robot is drawn.

Run it with chromium installed (`apt-get install chromium`; `.ci/run` installs it where
apt-get is available): `python -m pytest tests/viz/test_viz_browser.py`. It skips when no
chromium is found.
"""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

pytest.importorskip("viser", reason="the viewer needs the viz extra: pip install 'manip[viz]'")
imageio = pytest.importorskip("imageio.v3", reason="reading the screenshot needs imageio (the video extra)")

from manip import MotionGenerator  # noqa: E402
from manip.viz import Viewer  # noqa: E402

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(url: str, png, profile) -> None:
    """Let headless chromium render `url` (software WebGL) for 6 s of virtual time and save a PNG."""
    subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader",  # WebGL without a GPU
         f"--user-data-dir={profile}", f"--screenshot={png}", "--window-size=800,600",
         "--virtual-time-budget=6000", url],
        check=True, capture_output=True, timeout=180)


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")
def test_the_browser_draws_the_robot(tmp_path, port):
    mg = MotionGenerator("franka")
    v = Viewer(mg, port=port, verbose=False, gizmo=False, grid=False)  # nothing but the robot
    try:
        png = tmp_path / "viewer.png"
        screenshot(v.url, png, tmp_path / "profile")
    finally:
        v.close()
    rgb = imageio.imread(png)[..., :3].astype(int)
    assert rgb.shape == (600, 800, 3)
    h, w, _ = rgb.shape
    centre = rgb[h // 5: 4 * h // 5, w // 5: 4 * w // 5]  # the robot stands at the camera's target
    drawn = ~np.all(centre >= 245, axis=-1)  # the page is white
    grey = np.ptp(centre, axis=-1) < 12  # the Panda is white and dark grey: no hue
    shaded = np.max(centre, axis=-1) < 200  # its grey joint caps and shaded sides
    assert (drawn & grey).mean() > 0.02, "nothing robot-coloured drawn where the robot stands"
    assert (shaded & grey).sum() > 500, "no shaded robot surfaces drawn"
