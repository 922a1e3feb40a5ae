"""Robot information (Isaac Sim tutorial port): the Franka's number of DoF, joint names and
every field of its dof_properties.

    python examples/robot_info.py
"""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--viewer", action="store_true", help="Open MuJoCo's interactive viewer (needs a display).")
    args = parser.parse_args(argv)

    from manip.sim import Franka, SimulationApp, World

    app = SimulationApp({"headless": not args.viewer})
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka(prim_path="/World/Franka", name="franka"))
    world.reset()
    print("num_dof:", franka.num_dof)
    print("dof_names:", franka.dof_names)
    props = franka.dof_properties
    print("dof_properties fields:", list(props.dtype.names))
    header = f"{'joint':22s}" + "".join(f"{f:>12s}" for f in props.dtype.names)
    print(header)
    for name, row in zip(franka.dof_names, props):
        print(f"{name:22s}" + "".join(f"{str(row[f]):>12s}" if isinstance(row[f], (bool,)) or f == "hasLimits"
                                      else f"{float(row[f]):12.4g}" for f in props.dtype.names))
    print("end effector pose:", franka.end_effector.get_world_pose())
    app.close()
    return 0 if franka.num_dof == 9 else 1


if __name__ == "__main__":
    sys.exit(main())
