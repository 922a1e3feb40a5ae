"""Compatibility layers: the names of other tools' APIs, on top of manip's typed API.

- `TutorialMotionGen`: the Isaac Sim pick-and-place tutorial's cuRobo wrapper
  (`from manip import TutorialMotionGen as CuroboMotionGenerator`).
"""

from __future__ import annotations

from manip.compat.tutorial import TutorialMotionGen, wxyz_to_xyzw, xyzw_to_wxyz

__all__ = ["TutorialMotionGen", "wxyz_to_xyzw", "xyzw_to_wxyz"]
