"""Isaac's segmentation annotators from MuJoCo's segmentation render (a geom id per pixel):
each geom's body is a prim (its name is the prim path: "/World/Cube", "/World/Franka/panda_hand"),
and a prim's semantic label is its own or its nearest labelled ancestor's
(`manip.sim.utils.semantics.add_update_semantics`).

Layouts, as Isaac's annotators with `colorize=False`:
- semantic_segmentation: {"data": (H, W) uint32, "info": {"idToLabels": {"0": {"class":
  "BACKGROUND"}, "1": {"class": "UNLABELLED"}, "2": {"class": "cube"}, ...}}}: 0 where no surface
  is seen, 1 for surfaces without a label, one id per label (set) seen.
- instance_id_segmentation: {"data": (H, W) uint32, "info": {"idToLabels": {"0": "BACKGROUND",
  "1": "UNLABELLED", "2": "/World/Cube", ...}}}: one id per prim (MuJoCo body) seen; 1 for
  surfaces of no prim (MuJoCo's world body).
"""

from __future__ import annotations

import mujoco
import numpy as np

from manip.errors import InvalidInputError
from manip.sim.utils.semantics import labels_of


def init_params(params: dict | None, annotator: str) -> dict:
    """Isaac's `init_params` of a segmentation annotator, checked: {"colorize": False,
    "semanticTypes": [...]} (colorized images are not made here)."""
    params = dict(params or {})
    unknown = set(params) - {"colorize", "semanticTypes"}
    if unknown:
        raise InvalidInputError(f"{annotator} init_params has unknown keys {sorted(unknown)}; "
                                f"known: colorize (False), semanticTypes")
    if params.get("colorize", False):
        raise InvalidInputError(f"{annotator} with colorize=True is not available (ids only): pass "
                                "{'colorize': False} and colour the ids yourself")
    types = params.get("semanticTypes", ["class"])
    if isinstance(types, str) or not types or not all(isinstance(t, str) and t for t in types):
        raise InvalidInputError(f"semanticTypes must be a non-empty list of label types (e.g. ['class']); got {types!r}")
    return {"semanticTypes": list(types)}


def _bodies(model: mujoco.MjModel, seg: np.ndarray) -> np.ndarray:
    """(H, W) body index of the geom seen at each pixel, -1 where none."""
    geom = (seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM)) & (seg[..., 0] >= 0)
    return np.where(geom, model.geom_bodyid[np.where(geom, seg[..., 0], 0)], -1)


def semantic_segmentation(model: mujoco.MjModel, seg: np.ndarray, semantic_types=("class",)) -> dict:
    """Isaac's semantic_segmentation of a segmentation render `seg` (H, W, 2) (see the module)."""
    bodies = _bodies(model, seg)
    data = np.zeros(bodies.shape, dtype=np.uint32)
    id_to_labels = {"0": {semantic_types[0]: "BACKGROUND"}, "1": {semantic_types[0]: "UNLABELLED"}}
    ids: dict[tuple, int] = {}
    for b in np.unique(bodies[bodies >= 0]):
        path = model.body(int(b)).name
        key = tuple(labels_of(path, t) if b > 0 else None for t in semantic_types)
        if all(label is None for label in key):
            data[bodies == b] = 1
            continue
        if key not in ids:
            ids[key] = len(ids) + 2
            id_to_labels[str(ids[key])] = {t: label for t, label in zip(semantic_types, key) if label is not None}
        data[bodies == b] = ids[key]
    return {"data": data, "info": {"idToLabels": id_to_labels}}


def instance_id_segmentation(model: mujoco.MjModel, seg: np.ndarray) -> dict:
    """Isaac's instance_id_segmentation of a segmentation render `seg` (H, W, 2) (see the module)."""
    bodies = _bodies(model, seg)
    data = np.zeros(bodies.shape, dtype=np.uint32)
    data[bodies == 0] = 1
    id_to_labels = {"0": "BACKGROUND", "1": "UNLABELLED"}
    for k, b in enumerate(np.unique(bodies[bodies > 0])):
        data[bodies == b] = k + 2
        id_to_labels[str(k + 2)] = model.body(int(b)).name
    return {"data": data, "info": {"idToLabels": id_to_labels}}
