"""Generate robots/franka/franka.xml: the generic builder (`make_mjcf.py franka`) on the Franka.

Kept for the scripts and tests that call `generate(urdf, srdf)`; the Franka's drive gains,
finger contact and gravity setting are in robots/franka/robot.yaml (`sim:`).

Usage (from the repository root)::

    .venv/bin/python robots/tools/make_franka_mjcf.py            # writes robots/franka/franka.xml
    .venv/bin/python robots/tools/make_franka_mjcf.py --check    # exit 1 if the file is stale
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROBOTS = Path(__file__).resolve().parents[1]
OUT = ROBOTS / "franka" / "franka.xml"


def generate(urdf_path: Path, srdf_path: Path) -> str:
    """Return the MJCF text of the Franka (robots/franka/robot.yaml with these URDF and SRDF)."""
    import dataclasses

    from manip.robot_config import load_robot_config
    from manip.sim.scenes.mjcf_builder import build_mjcf

    cfg = load_robot_config("franka")
    if Path(urdf_path).resolve() != cfg.urdf_path or Path(srdf_path).resolve() != cfg.srdf_path:
        cfg = dataclasses.replace(cfg, urdf_path=Path(urdf_path).resolve(), srdf_path=Path(srdf_path).resolve())
    return build_mjcf(cfg)[0]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check that franka.xml is up to date")
    args = parser.parse_args()
    sys.path.insert(0, str(ROBOTS.parent))
    from manip.robot_config import load_robot_config
    from manip.sim.scenes.mjcf_builder import write_mjcf

    cfg = load_robot_config("franka")
    if args.check:
        current = OUT.read_text() if OUT.exists() else ""
        if current != generate(cfg.urdf_path, cfg.srdf_path):
            print(f"{OUT} is stale: rerun {Path(__file__).name}")
            return 1
        print(f"{OUT} is up to date")
        return 0
    print(f"wrote {write_mjcf(cfg, OUT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
