"""Deprecated module: the tutorial wrapper moved to `manip.compat` (`manip.TutorialMotionGen`).

`TutorialAPI` was a mixin of MotionGenerator; it is now the name of the wrapper class.
"""

from __future__ import annotations

from manip.compat import TutorialMotionGen, wxyz_to_xyzw, xyzw_to_wxyz

TutorialAPI = TutorialMotionGen

__all__ = ["TutorialAPI", "TutorialMotionGen", "wxyz_to_xyzw", "xyzw_to_wxyz"]
