"""Fixtures of the simulation tests: every test starts with no World and an empty stage."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _every_test_in_a_fresh_world(fresh_world):
    """`fresh_world` (tests/conftest.py) around every simulation test."""
    yield


SLIDER_MJCF = """
<mujoco>
  <worldbody>
    <body name="cart">
      <joint name="slide" type="slide" axis="1 0 0"/>
      <geom type="box" size="0.05 0.05 0.05" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture
def slider_file(tmp_path):
    """A 1 kg cart on a frictionless, unactuated slide joint along x (no collisions)."""
    p = tmp_path / "slider.xml"
    p.write_text(SLIDER_MJCF)
    return p
