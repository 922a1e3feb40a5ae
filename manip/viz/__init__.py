"""`manip.viz`: see robots, worlds, plans and the simulation in the browser (viser).

Install with the optional extra: `pip install "manip-robotics[viz]"`. Modules, one idea each:
`server` (the viser server), `robot` (URDF visual meshes), `obstacles` (the planner's
world, attached objects), `playback` (a trajectory with play/pause and a time slider),
`interact` (the IK target gizmo), `spheres` (collision spheres), `sim_stream` (a
`manip.sim` World's bodies, streamed), `plots` (joint and benchmark plots, matplotlib
only), `viewer` (`Viewer`, all together).

`Viewer` and `SimStream` are imported on first use, so `manip.viz.plots` works without viser.
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import Any

__all__ = ["Viewer", "SimStream"]

_EXPORTS = {"Viewer": "manip.viz.viewer", "SimStream": "manip.viz.sim_stream"}


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'manip.viz' has no attribute '{name}'; it exports {', '.join(__all__)}")
    if importlib.util.find_spec("viser") is None:
        raise ImportError(f'manip.viz.{name} needs viser: pip install "manip-robotics[viz]"')
    return getattr(importlib.import_module(_EXPORTS[name]), name)
