"""No module of `manip` reads or writes another module's private attributes (read with `ast`).

A private attribute is a name with one leading underscore (`obj._x`, not a dunder). An access
`obj._x` in module M is cross-module unless `obj` is `self`, `cls`, `super()` or `type(self)`,
or `_x` is defined in M and in no other module (a method, a class attribute or a `self._x`
assignment): a private name that several modules define is ambiguous, so it counts too. The
few accesses left are listed in `ALLOWED`, each with its reason (at most 10).
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path
from robot_constants import REPO_ROOT

PACKAGE_ROOT = REPO_ROOT / "manip"

#: (module file relative to the repository, the access as written): why it stays.
ALLOWED: dict[tuple[str, str], str] = {
    ("manip/kinematics.py", "Pose._trusted"):
        "a Pose from arrays the batched FK has just computed (unit quaternions): no second validation",
    ("manip/jit.py", "dispatcher._cache"):
        "numba's Dispatcher keeps its cache there and has no public way to give it another one: the "
        "prebuilt kernels' cache replaces the FunctionCache that cache=True would install",
}


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _definitions(trees: dict[Path, ast.Module]) -> dict[str, set[Path]]:
    """Private name -> the modules defining it (def, class, assignment, string such as __slots__)."""
    defs: dict[str, set[Path]] = defaultdict(set)
    for path, tree in trees.items():
        for node in ast.walk(tree):
            name = None
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                name = node.name
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                name = node.attr
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                name = node.id
            elif isinstance(node, ast.Constant) and isinstance(node.value, str):
                name = node.value
            if name and _private(name):
                defs[name].add(path)
    return defs


def _own(value: ast.expr) -> bool:
    """`self`, `cls`, `super()` or `type(...)`: the object's own class."""
    if isinstance(value, ast.Name):
        return value.id in ("self", "cls")
    return isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id in ("super", "type")


def cross_module_accesses(root: Path = PACKAGE_ROOT) -> list[tuple[str, int, str]]:
    """(file relative to the repository, line, access) of every cross-module private access."""
    trees = {p: ast.parse(p.read_text(), str(p)) for p in sorted(root.rglob("*.py"))}
    defs = _definitions(trees)
    out = []
    for path, tree in trees.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and _private(node.attr) and not _own(node.value):
                if defs[node.attr] != {path}:
                    out.append((path.relative_to(root.parent).as_posix(), node.lineno, ast.unparse(node)))
    return out


def test_finds_a_planted_private_access(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "a.py").write_text("class A:\n    def __init__(self):\n        self._x = 1\n        self._y = 2\n"
                              "    def same(self, other):\n        return other._y + self._x\n")
    (pkg / "b.py").write_text("def f(a):\n    return a._x\nclass B(object):\n    def g(self):\n"
                              "        return super()._x\n")
    assert cross_module_accesses(pkg) == [("pkg/b.py", 2, "a._x")]


def test_no_module_reads_another_modules_private_attributes():
    found = cross_module_accesses()
    unexpected = [f"  {f}:{line}: {access}" for f, line, access in found if (f, access) not in ALLOWED]
    assert not unexpected, "cross-module private attribute accesses:\n" + "\n".join(unexpected)
    assert len(ALLOWED) <= 10
    stale = set(ALLOWED) - {(f, access) for f, _, access in found}
    assert not stale, f"allowed accesses that no longer occur (remove them): {sorted(stale)}"
