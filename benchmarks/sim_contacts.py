"""Cost of manip.sim's contact model (issue 32): ten 5 cm cubes dropped from 1 m onto the
ground, then resting; CPU milliseconds per World physics step (1/60 s).

    python benchmarks/sim_contacts.py

While a cube falls fast the substeps shorten (`manip.sim.core.substeps`: at most 2 mm of
travel between contact checks); the stiff contacts and the PhysX friction pairs
(`manip.sim.scenes.contact_model`) apply throughout.
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from manip.sim import World, DynamicCuboid  # noqa: E402


def main() -> int:
    w = World()
    w.scene.add_default_ground_plane()
    for i in range(10):
        w.scene.add(DynamicCuboid(f"/World/c{i}", name=f"c{i}", position=[0.2 * i, 0, 1.0], size=0.05))
    w.reset()
    t = time.process_time()
    for _ in range(120):  # 2 s: the fall (0.45 s), the landing and settling
        w.step(render=False)
    fall = (time.process_time() - t) / 120 * 1e3
    t = time.process_time()
    for _ in range(120):  # 2 s at rest
        w.step(render=False)
    rest = (time.process_time() - t) / 120 * 1e3
    print(f"CPU ms per physics step: falling and landing {fall:.3f}, resting {rest:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
