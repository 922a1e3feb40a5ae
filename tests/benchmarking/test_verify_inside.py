"""The independent verifier catches a part wholly inside another part's closed mesh.

coal's mesh tests see triangles only, so before `verify_inside` the verifier passed a
finger wholly inside panda_link5 (round two's franka/14 goal) and an obstacle wholly inside
a link as free.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from manip.benchmarking.verify import Verifier

#: the left finger wholly inside panda_link5 (tests/collision/test_part_inside_part.py)
FINGER_IN_LINK5 = np.array([-0.7005, 0.9538, 1.6255, -1.1995, 1.0952, -0.0043, 2.5645])
READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
#: a finger wholly inside panda_link5 that manip's check_collision passes as free (2 of 5000
#: uniformly random configurations, round three; tests/collision/test_part_inside_part.py)
RIGHT_FINGER_IN_LINK5 = np.array([2.237984, 0.386481, 1.831686, -1.353043, 2.881792, -0.011904, -0.720005])
LEFT_FINGER_IN_LINK5 = np.array([1.852394, -0.56329, 1.571227, -2.959354, 2.7396, -0.006162, 2.391773])


@pytest.fixture(scope="module")
def verifier() -> Verifier:
    return Verifier("franka")


def test_a_finger_inside_a_link_is_a_self_collision(verifier):
    pair = verifier.in_collision(FINGER_IN_LINK5)
    assert pair is not None and pair[0].startswith("panda_leftfinger") and pair[1] == "panda_link5_0", pair
    codes, reasons = verifier.check_configuration(FINGER_IN_LINK5, None, "goal")
    assert codes == ["goal_self_collision"] and "wholly inside" in reasons[0], reasons
    assert verifier.in_collision(READY) is None
    assert verifier.in_collision(RIGHT_FINGER_IN_LINK5) == ("panda_rightfinger_0", "panda_link5_0")
    assert verifier.in_collision(LEFT_FINGER_IN_LINK5) == ("panda_leftfinger_0", "panda_link5_0")
    hit = verifier.first_collision(np.stack([READY, FINGER_IN_LINK5]))
    assert hit is not None and hit[0] == 1


def link5_centre(verifier: Verifier, q: np.ndarray) -> np.ndarray:
    """The centre of panda_link5's mesh bounding box, base frame [m], at arm configuration q."""
    w = verifier._empty
    k = [g.name for g in w.gm.geometryObjects].index("panda_link5_0")
    pin.updateGeometryPlacements(verifier.model, verifier.data, w.gm, w.gd, verifier._full_q(q))
    V = np.asarray(w.gm.geometryObjects[k].geometry.vertices()).reshape(-1, 3)
    return w.gd.oMg[k].act((V.min(axis=0) + V.max(axis=0)) / 2)


def test_an_obstacle_inside_a_link_fails_the_trajectory(verifier):
    c = link5_centre(verifier, READY)
    world = {"sphere": {"pebble": {"radius": 0.01, "position": c.tolist()}}}
    assert verifier.in_collision(READY, world) == ("world/pebble", "panda_link5_0")
    t = np.array([0.0, 1.0])
    r = verifier.verify_trajectory(world, t, np.stack([READY, READY]), start_q=READY, goal_q=READY)
    assert not r.valid and r.collision_pair == ("world/pebble", "panda_link5_0"), r.reasons
    far = {"sphere": {"pebble": {"radius": 0.01, "position": (c + [0.0, 0.0, 0.5]).tolist()}}}
    assert verifier.verify_trajectory(far, t, np.stack([READY, READY]), start_q=READY, goal_q=READY).valid
