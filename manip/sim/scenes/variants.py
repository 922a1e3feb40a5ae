"""USD variant sets of a referenced asset, as Isaac 5's Franka examples select them
(`add_reference_to_stage(...).GetVariantSet("Gripper").SetVariantSelection("AlternateFinger")`,
"Mesh": "Quality" / "Performance", "Physics": "physx" / "mujoco").

manip's bundled models come in one variant each (the Franka: box finger pads, one mesh set,
MuJoCo physics): a selection is checked (a non-empty string), kept (`GetVariantSelection`)
and changes nothing, said once per variant set at INFO.
"""

from __future__ import annotations

import logging

from manip.errors import InvalidInputError

logger = logging.getLogger(__name__)


class VariantSet:
    """One variant set of a referenced prim (USD's `Usd.VariantSet`, the calls scripts make)."""

    def __init__(self, selections: dict[str, str], name: str, prim_path: str):
        self._selections = selections  # the prim's {set name: selection}, shared by its VariantSets
        self._name = name
        self._prim_path = prim_path

    def GetName(self) -> str:  # noqa: N802 (USD's method names)
        return self._name

    def SetVariantSelection(self, variant_name: str) -> bool:  # noqa: N802
        """Keep `variant_name` as this set's selection (the model does not change); True."""
        if not isinstance(variant_name, str) or not variant_name:
            raise InvalidInputError(f"variant name must be a non-empty str; got {variant_name!r}")
        if self._name not in self._selections:
            logger.info("%s: variant set %r = %r kept; manip's bundled model has one variant, nothing changes",
                        self._prim_path, self._name, variant_name)
        self._selections[self._name] = variant_name
        return True

    def GetVariantSelection(self) -> str:  # noqa: N802
        """The selection kept ("" until one is set, as USD's)."""
        return self._selections.get(self._name, "")

    def ClearVariantSelection(self) -> bool:  # noqa: N802
        self._selections.pop(self._name, None)
        return True

    def GetVariantNames(self) -> list[str]:  # noqa: N802
        """The selection kept, if any (manip's models list no variants of their own)."""
        selection = self.GetVariantSelection()
        return [selection] if selection else []
