"""Isaac's semantic labels (`omni.isaac.core.utils.semantics`): `add_update_semantics(prim,
"cube")` labels a prim (and, as in Replicator, every prim below it that has no label of its
own); the Camera's `semantic_segmentation` annotator reads them.

A prim is a path ("/World/Cube", "/World/Franka/panda_hand") or what `get_prim_at_path` returns.
Labels live on the stage (`Stage.semantics`: path -> {type: label}) and go with the prim.
"""

from __future__ import annotations

from manip.errors import InvalidInputError
from manip.sim.scenes.stage import get_current_stage, is_prim_path_valid


def _path(prim: object) -> str:
    path = prim if isinstance(prim, str) else getattr(prim, "prim_path", None)
    if path is None and hasattr(prim, "GetPath"):
        path = str(prim.GetPath())
    if not isinstance(path, str) or not is_prim_path_valid(path):
        raise InvalidInputError(f"prim must be a prim path of the stage or a prim (get_prim_at_path); got {prim!r}")
    return path


def _text(value: object, name: str) -> str:
    if not isinstance(value, str) or not value:
        raise InvalidInputError(f"{name} must be a non-empty string (e.g. 'cube'); got {value!r}")
    return value


def add_update_semantics(prim, semantic_label: str, type_label: str = "class", suffix: str = "") -> None:
    """Label `prim` with `semantic_label` of type `type_label` (replacing its label of that
    type); `suffix` (Isaac's name of several Semantics APIs on one prim) is accepted: one label
    per type is kept."""
    path = _path(prim)
    get_current_stage().semantics.setdefault(path, {})[_text(type_label, "type_label")] = \
        _text(semantic_label, "semantic_label")


def remove_all_semantics(prim, recursive: bool = False) -> None:
    """Remove the labels of `prim` (and of every prim below it when `recursive`)."""
    path = _path(prim)
    labels = get_current_stage().semantics
    for p in [p for p in labels if p == path or (recursive and p.startswith(path + "/"))]:
        del labels[p]


def get_semantics(prim) -> dict[str, tuple[str, str]]:
    """The labels set on `prim` itself, as Isaac's: {"Semantics_<type>": (type, label)}."""
    return {f"Semantics_{t}": (t, label) for t, label in get_current_stage().semantics.get(_path(prim), {}).items()}


def labels_of(path: str, type_label: str = "class") -> str | None:
    """The label of type `type_label` of the prim at `path`: its own, else its nearest labelled
    ancestor's (None: unlabelled)."""
    labels = get_current_stage().semantics
    while path:
        label = labels.get(path, {}).get(type_label)
        if label is not None:
            return label
        path = path.rpartition("/")[0]
    return None
