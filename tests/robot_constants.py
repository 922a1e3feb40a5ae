"""Constants shared by the tests (imported as `from robot_constants import ...`; a unique
module name, since tests/ and tests/sim/ both have a conftest)."""

import importlib.util
import sys
from pathlib import Path

#: The repository's root folder (tests/ mirrors manip/, so a test's depth varies).
REPO_ROOT = Path(__file__).resolve().parents[1]

#: The Franka's ready configuration [rad] (robots/franka/robot.yaml).
FRANKA_READY = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
#: A hand pointing down, as [qx, qy, qz, qw] (the tutorial wrapper's order); (w, x, y, z) = (0, 1, 0, 0).
DOWN_XYZW = (1.0, 0.0, 0.0, 0.0)


def load_script(path: Path, name: str):
    """The module of the script at `path` (an example, a benchmark, a tool), imported as `name`
    (registered in sys.modules, so its dataclasses and pickles resolve)."""
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod
