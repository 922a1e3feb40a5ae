"""Asset paths: Isaac Sim's Nucleus asset paths resolved to the models bundled with manip.

Isaac scripts build robot paths as `get_assets_root_path() + "/Isaac/Robots/Franka/franka.usd"`.
manip has no USD and no Nucleus server: `get_assets_root_path()` is the folder of the
bundled robots (`robots/`), and `resolve_asset_path` maps the Isaac asset paths of the
tutorials onto the MuJoCo models there (`ISAAC_ASSETS`). Any other path must be an existing
MJCF (.xml) or URDF file.

Differences from Isaac (no USD): `franka.usd`, `franka_alt_fingers.usd` and Isaac 5's
`FrankaRobotics/FrankaPanda/franka.usd` (whatever its variants) are the same model here
(manip's Franka, box finger pads); the Jetbot (`Jetbot/jetbot.usd`, Isaac 5's
`NVIDIA/Jetbot/jetbot.usd`) is manip's own two-wheel robot with the dimensions of NVIDIA's
(wheel radius 0.03 m, wheel base 0.1125 m, same joint names).
"""

from __future__ import annotations

from pathlib import Path

from manip.robot_config import robots_root

#: Isaac asset path (relative to the assets root) -> bundled model (relative to `robots/`).
ISAAC_ASSETS: dict[str, str] = {
    "Isaac/Robots/Jetbot/jetbot.usd": "jetbot/jetbot.xml",
    "Isaac/Robots/Franka/franka.usd": "franka/franka.xml",
    "Isaac/Robots/Franka/franka_alt_fingers.usd": "franka/franka.xml",
    # Isaac Sim 5.x moved the Franka (its finger variants are USD variant sets there) and the Jetbot
    "Isaac/Robots/FrankaRobotics/FrankaPanda/franka.usd": "franka/franka.xml",
    "Isaac/Robots/NVIDIA/Jetbot/jetbot.usd": "jetbot/jetbot.xml",
}

MODEL_SUFFIXES = (".xml", ".mjcf", ".urdf")


def get_assets_root_path() -> str:
    """The folder of the bundled robot models (`robots/`), standing in for Isaac's Nucleus
    asset root: `<root>/Isaac/Robots/...` paths of `ISAAC_ASSETS` resolve to models in it,
    and each robot's MuJoCo model is also reachable directly as `<root>/<name>/<name>.xml`."""
    return str(robots_root())


def available_assets() -> list[str]:
    """Every asset path a script may reference: the Isaac paths of `ISAAC_ASSETS` (under the
    assets root) and the bundled model files."""
    root = robots_root()
    bundled = sorted(str(p) for p in root.glob("*/*.xml"))
    return [f"{root}/{k}" for k in ISAAC_ASSETS] + bundled


def _isaac_key(path: str) -> str | None:
    """The `ISAAC_ASSETS` key that `path` ends with (any prefix: assets root, omniverse://...)."""
    norm = path.replace("\\", "/")
    for key in ISAAC_ASSETS:
        if norm == key or norm.endswith("/" + key):
            return key
    return None


def resolve_asset_path(usd_path: str | Path) -> Path:
    """The model file to load for `usd_path`: an Isaac asset path of `ISAAC_ASSETS` gives its
    bundled model; any other path must be an existing .xml/.mjcf/.urdf file.

    Raises:
        FileNotFoundError: neither; the message lists the available assets.
    """
    key = _isaac_key(str(usd_path))
    if key is not None:
        return (robots_root() / ISAAC_ASSETS[key]).resolve()
    path = Path(usd_path).expanduser()
    if path.is_file():
        return path.resolve()
    listing = "\n  ".join(available_assets())
    hint = ""
    if path.suffix.lower() in (".usd", ".usda", ".usdc"):
        hint = " (manip has no USD: only the Isaac asset paths below map to bundled MuJoCo models)"
    raise FileNotFoundError(f"no asset at {usd_path}{hint}; available assets:\n  {listing}")
