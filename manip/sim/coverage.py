"""The Isaac core-API coverage table, generated from the code (docs/isaac_coverage.md).

For each Isaac class of `manip.sim.isaac_api.ISAAC_API` and each of its public members:
"implemented" (manip's class has it), "raises" (calling it raises NotImplementedError with
the reason: `NOT_SUPPORTED`), "differs" (implemented, with a difference: `DIFFERS`), or
"missing" (tests/sim/test_coverage.py fails on any). The same for the module-level
utilities. Regenerate with `python -m manip.sim.coverage > docs/isaac_coverage.md`.
"""

from __future__ import annotations

from dataclasses import dataclass

import manip.sim as sim
from manip.sim.isaac_api import DIFFERS, FUNCTIONS_NOT_SUPPORTED, ISAAC_API, ISAAC_FUNCTIONS, ISAAC_MODULES


@dataclass(frozen=True)
class Row:
    """One Isaac member: its class (or module), name, status and note."""

    owner: str
    member: str
    status: str
    note: str = ""


def _status(cls: type, owner: str, name: str) -> Row:
    member = getattr(cls, name, None)
    annotated = any(name in vars(k).get("__annotations__", {}) for k in cls.__mro__)  # set on each instance
    if member is None and not hasattr(cls, name) and not annotated:
        return Row(owner, name, "missing")
    target = member.fget if isinstance(member, property) else member
    why = getattr(target, "isaac_not_supported", None)
    if why is not None:
        return Row(owner, name, "raises", why)
    for klass in cls.__mro__:  # a difference noted for the class or a base class
        note = DIFFERS.get(klass.__name__, {}).get(name)
        if note:
            return Row(owner, name, "differs", note)
    return Row(owner, name, "implemented")


def class_rows() -> list[Row]:
    rows = []
    for owner, (_, members) in ISAAC_API.items():
        cls = getattr(sim, owner)
        rows += [_status(cls, owner, m) for m in dict.fromkeys(members)]
    return rows


def function_rows() -> list[Row]:
    rows = []
    for module, names in ISAAC_FUNCTIONS.items():
        namespace = getattr(sim, ISAAC_MODULES[module]) if module in ISAAC_MODULES else sim
        for name in names:
            fn = getattr(namespace, name, None)
            if fn is None:
                rows.append(Row(module, name, "missing"))
            elif name in FUNCTIONS_NOT_SUPPORTED:
                rows.append(Row(module, name, "raises", FUNCTIONS_NOT_SUPPORTED[name]))
            else:
                rows.append(Row(module, name, "implemented"))
    return rows


def markdown() -> str:
    """The coverage table as Markdown (what docs/isaac_coverage.md holds)."""
    rows = class_rows() + function_rows()
    counts = {s: sum(r.status == s for r in rows) for s in ("implemented", "differs", "raises", "missing")}
    out = ["# Isaac Sim core API coverage of manip.sim", "",
           "Generated from the code by `python -m manip.sim.coverage` (tests/sim/test_coverage.py keeps it",
           "true). Isaac's members as its 4.x core API documents them (`manip/sim/isaac_api.py`); `raises`:",
           "calling it raises NotImplementedError naming the member and why; `differs`: implemented, with",
           "the difference noted. Import everything from `manip.sim`.", "",
           "Totals: " + ", ".join(f"{n} {s}" for s, n in counts.items()) + ".", ""]
    for owner, (isaac, _) in ISAAC_API.items():
        out += [f"## {owner} (`{isaac}`)", "", "| member | status | note |", "|---|---|---|"]
        out += [f"| `{r.member}` | {r.status} | {r.note} |" for r in rows if r.owner == owner]
        out.append("")
    for module in ISAAC_FUNCTIONS:
        out += [f"## `{module}`", "", "| function | status | note |", "|---|---|---|"]
        out += [f"| `{r.member}` | {r.status} | {r.note} |" for r in rows if r.owner == module]
        out.append("")
    return "\n".join(out)


if __name__ == "__main__":
    import sys

    sys.stdout.write(markdown())
