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

pytest.importorskip("viser", reason="the viewer needs the viz extra: pip install 'manip-robotics[viz]'")
imageio = pytest.importorskip("imageio.v3", reason="reading the screenshot needs imageio (the video extra)")

from manip import MotionGenerator  # noqa: E402
from manip.viz import Viewer  # noqa: E402

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


#: Virtual time [ms] chromium gives the page before the screenshot, tried in turn: the
#: client receives the robot's meshes (several MB) over the websocket and renders them with
#: software WebGL, which takes longer on a loaded machine.
BUDGETS_MS = (8000, 20000, 40000)


def screenshot(url: str, png, profile, budget_ms: int) -> None:
    """Let headless chromium render `url` (software WebGL) for `budget_ms` of virtual time; save a PNG."""
    subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--use-angle=swiftshader", "--enable-unsafe-swiftshader",  # WebGL without a GPU
         f"--user-data-dir={profile}", f"--screenshot={png}", "--window-size=800,600",
         f"--virtual-time-budget={budget_ms}", url],
        check=True, capture_output=True, timeout=180)


def robot_pixels(image: np.ndarray) -> tuple[float, int]:
    """(fraction of robot-coloured pixels, number of shaded ones) where the robot stands.

    The crop is the middle of the 800x600 page left of the GUI panel; the page is white and
    the Panda white and dark grey, so robot pixels are hue-less non-white ones.
    """
    rgb = image[..., :3].astype(int)
    assert rgb.shape == (600, 800, 3)
    centre = rgb[150:450, 200:460]
    drawn = ~np.all(centre >= 245, axis=-1)
    grey = np.ptp(centre, axis=-1) < 12
    shaded = np.max(centre, axis=-1) < 200  # grey joint caps and shaded sides
    return float((drawn & grey).mean()), int((shaded & grey).sum())


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")
def test_the_browser_draws_the_robot(tmp_path, port):
    mg = MotionGenerator("franka")
    v = Viewer(mg, port=port, verbose=False, gizmo=False, grid=False)  # nothing but the robot
    try:
        for budget in BUDGETS_MS:
            png = tmp_path / f"viewer_{budget}.png"
            screenshot(v.url, png, tmp_path / f"profile_{budget}", budget)
            drawn, shaded = robot_pixels(imageio.imread(png))
            if drawn > 0.05 and shaded > 500:
                break
    finally:
        v.close()
    assert drawn > 0.05, f"nothing robot-coloured drawn where the robot stands ({drawn:.1%} of the pixels)"
    assert shaded > 500, f"no shaded robot surfaces drawn ({shaded} pixels)"
