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


def _box_mesh(edge: float, open_top: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """A cube of `edge` [m] centred on its frame as (8, 3) vertices, (12, 3) outward triangles
    (10 without its top face)."""
    V = (np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float) - 0.5) * edge
    F = np.array([[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
                  [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]])
    if open_top:
        F = F[[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]]
    return V, F


def test_world_meshes_are_surfaces_unless_solid_as_manip_reads_them(verifier):
    """manip reads a world mesh as a surface unless `"solid": true`: a robot inside a closed 3 m
    mesh box is free, inside the solid one it collides (README "Worlds"). The verifier counted
    every closed world mesh as a volume (the robot inside collided: a valid plan judged invalid)
    and refused meshes given by vertices and faces (`Mesh.to_dict` of a mesh built from arrays)."""
    from manip import MotionGenerator
    from manip.collision import Mesh, WorldConfig

    mg = MotionGenerator("franka")
    for open_top in (False, True):
        V, F = _box_mesh(3.0, open_top)
        for solid in ((False, True) if not open_top else (False,)):
            world = WorldConfig(mesh=[Mesh(name="room", vertices=V, faces=F, pose=[0.3, 0, 0.5, 1, 0, 0, 0],
                                           solid=solid)])
            mg.update_world(world)
            ours = verifier.in_collision(READY, world.to_dict())
            assert (ours is not None) == solid == mg.check_collision(READY), (open_top, solid, ours)
    # a surface still collides where its triangles are touched, and lying inside a link
    V, F = _box_mesh(0.3)
    through = {"mesh": {"slab": {"vertices": V.tolist(), "faces": F.tolist(), "pose": [0.3, 0, 0.5, 1, 0, 0, 0]}}}
    assert verifier.in_collision(READY, through) is not None
    c = link5_centre(verifier, READY)
    V, F = _box_mesh(0.01)
    pebble = {"mesh": {"pebble": {"vertices": V.tolist(), "faces": F.tolist(), "pose": c.tolist() + [1, 0, 0, 0]}}}
    assert verifier.in_collision(READY, pebble) == ("world/pebble", "panda_link5_0")
    mg.update_world(pebble)
    assert mg.check_collision(READY)
