"""Build robots/<name>/<name>.xml (MuJoCo MJCF) and its meshes from the robot's URDF, SRDF and robot.yaml.

The builder is `manip.sim.scenes.mjcf_builder.build_mjcf` (MuJoCo's URDF compiler plus the yaml's
drives, gripper, contact excludes and home keyframe).

Usage (from the repository root)::

    .venv/bin/python robots/tools/make_mjcf.py franka ur5          # write the named robots
    .venv/bin/python robots/tools/make_mjcf.py path/to/my_arm      # your own robot folder (or its robot.yaml)
    .venv/bin/python robots/tools/make_mjcf.py --all               # every robot with an 'mjcf' entry
    .venv/bin/python robots/tools/make_mjcf.py --all --check       # exit 1 if a file is stale

A robot given by name or path needs an `mjcf:` entry in its robot.yaml (the file to write,
relative to the yaml's folder). Exit status: 0 done, 1 a file is stale (--check), 2 a robot
that cannot be loaded or has no `mjcf:` entry.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROBOTS = Path(__file__).resolve().parents[1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", help="robot names (folders under robots/) or paths of robot folders")
    parser.add_argument("--all", action="store_true", help="every robot whose robot.yaml names an mjcf file")
    parser.add_argument("--check", action="store_true", help="only check that the files are up to date")
    args = parser.parse_args()
    sys.path.insert(0, str(ROBOTS.parent))
    from manip.errors import ManipError
    from manip.robot_config import available_robots, load_robot_config
    from manip.sim.scenes.mjcf_builder import build_mjcf, write_mjcf

    names = available_robots() if args.all else args.robots
    if not names:
        parser.error("name robots or pass --all")
    stale = 0
    for name in names:
        try:
            cfg = load_robot_config(name)
        except ManipError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        if cfg.mjcf_path is None:
            if args.all:
                continue
            print(f"error: {cfg.folder / 'robot.yaml'} has no 'mjcf:' entry (the MJCF file to write, e.g. "
                  f"'mjcf: {cfg.name}.xml')", file=sys.stderr)
            return 2
        if args.check:
            text, assets = build_mjcf(cfg)
            ok = cfg.mjcf_path.is_file() and cfg.mjcf_path.read_text() == text and all(
                (cfg.mjcf_path.parent / "assets" / a).is_file() for a in assets)
            print(f"{cfg.mjcf_path}: {'up to date' if ok else 'STALE: rerun ' + Path(__file__).name}")
            stale += not ok
        else:
            print(f"wrote {write_mjcf(cfg)}")
    return 1 if stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
