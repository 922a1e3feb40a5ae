"""Robots placed inside each other, found at reset before MuJoCo's contact solver meets them.

Two Frankas at the same place (or one's links through the other's) make MuJoCo's contact
forces explode in the first steps (NaN accelerations) or leave the arms tangled. At every
`world.reset()` the compiled initial state is checked: a contact between links of two
different referenced robots deeper than `OVERLAP_DEPTH` raises `RobotsOverlapError` naming
the robots, the links, how deep and where. A robot moved after the reset (`set_world_pose`,
`ArticulationView.set_world_poses`) is checked against the others where it lands
(`check_moved_robot`): into another, the move raises and the robot stays where it was. A robot
added after a reset enters the model, and this check, at the next reset. Links brought into
another robot by joint commands are not checked: MuJoCo's contacts push them apart, as PhysX's do.
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip.sim.scenes.stage import SimulationError

#: [m] robots' links interpenetrating deeper than this at reset are an error (a touch is not).
OVERLAP_DEPTH = 0.005


class RobotsOverlapError(SimulationError):
    """Two robots' links interpenetrate in the state a reset starts from; the message says which and where."""


def check_moved_robot(core, cores) -> None:
    """Raise `RobotsOverlapError` when the robot `core`, just teleported, interpenetrates another
    of `cores` (the contacts are recomputed: MuJoCo's kinematics and collision, no step)."""
    m, d = core.sim.model, core.sim.data
    mujoco.mj_kinematics(m, d)
    mujoco.mj_collision(m, d)
    core.sim.mark_stale()
    check_robot_overlaps(m, d, cores, moved=core)


def check_robot_overlaps(model: mujoco.MjModel, data: mujoco.MjData, cores, moved=None) -> None:
    """Raise `RobotsOverlapError` when links of two robots (`ArticulationCore`s, each with
    `body_ids`, `body_names` and `ref.prim_path`) interpenetrate deeper than `OVERLAP_DEPTH` in
    `data` (contacts up to date: after `mj_forward`). A robot nested under another's prim
    path (a gripper mounted on an arm) is not checked against it. `moved`: only pairs with
    that core (a robot teleported after the reset)."""
    if len(cores) < 2 or data.ncon == 0:
        return
    owner = np.full(model.nbody, -1)
    for k, core in enumerate(cores):
        owner[core.body_ids] = k
    n = data.ncon
    geoms = np.asarray(data.contact.geom[:n])
    dist = np.asarray(data.contact.dist[:n])
    worst: dict[tuple[int, int], int] = {}
    for i in np.flatnonzero(dist < -OVERLAP_DEPTH):
        b1, b2 = model.geom_bodyid[geoms[i, 0]], model.geom_bodyid[geoms[i, 1]]
        k1, k2 = int(owner[b1]), int(owner[b2])
        if k1 < 0 or k2 < 0 or k1 == k2 or _nested(cores[k1], cores[k2]):
            continue
        if moved is not None and moved is not cores[k1] and moved is not cores[k2]:
            continue
        key = (min(k1, k2), max(k1, k2))
        if key not in worst or dist[i] < dist[worst[key]]:
            worst[key] = int(i)
    if not worst:
        return
    parts = []
    for (k1, k2), i in worst.items():
        a, b = cores[k1], cores[k2]
        pos = np.round(np.asarray(data.contact.pos[i]), 3).tolist()
        parts.append(f"{a.ref.prim_path} (base at {np.round(a.ref.position, 3).tolist()} m) and {b.ref.prim_path} "
                     f"(base at {np.round(b.ref.position, 3).tolist()} m): {a.ref.prim_path}'s "
                     f"{_link(model, a, geoms[i])} is {-dist[i] * 1e3:.0f} mm inside {b.ref.prim_path}'s "
                     f"{_link(model, b, geoms[i])} at {pos} m")
    if moved is not None:
        raise RobotsOverlapError(
            f"moving {moved.ref.prim_path} puts it inside another robot (MuJoCo would push them apart violently or "
            "report NaN accelerations): " + "; ".join(parts) + f". {moved.ref.prim_path} was left where it was: "
            "give a pose clear of the other robots")
    raise RobotsOverlapError(
        "robots overlap in the state the reset starts from (MuJoCo would push them apart violently or report "
        "NaN accelerations): " + "; ".join(parts) + ". Place them apart (position= when adding them, or "
        "set_world_pose and set_default_state), then reset again")


def _nested(a, b) -> bool:
    return a.ref.prim_path.startswith(b.ref.prefix) or b.ref.prim_path.startswith(a.ref.prefix)


def _link(model: mujoco.MjModel, core, pair: np.ndarray) -> str:
    """The name of the link of `core` among the contact's two geoms."""
    for g in pair:
        body = int(model.geom_bodyid[g])
        if body in core.body_ids:
            return core.body_names[int(np.flatnonzero(core.body_ids == body)[0])]
    return "a link"
