"""No import circles in `manip`: the graph of `manip.*` imports, read with `ast`, is acyclic.

Every `import` / `from ... import` statement counts, wherever it stands: at module level,
under `if TYPE_CHECKING:`, or inside a function (a lazy import that dodges a circle is a
circle too). Importing a package's submodule does not count as importing the package's
`__init__` (Python initialises the package first; that is not a circle).
"""

from __future__ import annotations

import ast
from pathlib import Path
from robot_constants import REPO_ROOT

PACKAGE_ROOT = REPO_ROOT / "manip"


def _module_name(path: Path, root: Path) -> str:
    rel = path.relative_to(root.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _modules(root: Path) -> dict[str, Path]:
    """Module name -> file; a package wins over a module file of the same name (as in Python)."""
    out: dict[str, Path] = {}
    for p in sorted(root.rglob("*.py")):
        name = _module_name(p, root)
        if name not in out or p.name == "__init__.py":
            out[name] = p
    return out


def _imports(name: str, path: Path, known: set[str]) -> dict[str, int]:
    """The `manip.*` modules that module `name` imports -> line of the first such import."""
    is_package = path.name == "__init__.py"
    out: dict[str, int] = {}

    def add(target: str, line: int) -> None:
        if target != name and target in known:
            out.setdefault(target, line)

    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                add(alias.name, node.lineno)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_package else name.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                source = ".".join(base + ([node.module] if node.module else []))
            else:
                source = node.module or ""
            for alias in node.names:
                sub = f"{source}.{alias.name}"
                add(sub if sub in known else source, node.lineno)
    return out


def import_graph(root: Path = PACKAGE_ROOT) -> tuple[dict[str, dict[str, int]], dict[str, Path]]:
    """{module: {imported module: line}} over every module of the package at `root`, and their files."""
    mods = _modules(root)
    known = set(mods)
    return {name: _imports(name, path, known) for name, path in mods.items()}, mods


def find_cycle(graph: dict[str, dict[str, int]]) -> list[str] | None:
    """One cycle as [m0, m1, ..., m0], or None (iterative depth-first search)."""
    state: dict[str, int] = {}  # 1 on the current path, 2 done
    for root in sorted(graph):
        if state.get(root):
            continue
        path = [root]
        stack = [iter(sorted(graph[root]))]
        state[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            elif not state.get(nxt):
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(graph[nxt])))
    return None


def _describe(cycle: list[str], graph: dict[str, dict[str, int]], files: dict[str, Path]) -> str:
    return "\n".join(f"  {a} -> {b}  ({files[a]}:{graph[a][b]})" for a, b in zip(cycle, cycle[1:]))


def test_finds_a_planted_cycle():
    graph = {"a": {"b": 1}, "b": {"c": 2}, "c": {"a": 3}, "d": {}}
    cycle = find_cycle(graph)
    assert cycle is not None and cycle[0] == cycle[-1] and set(cycle) == {"a", "b", "c"}
    assert find_cycle({"a": {"b": 1}, "b": {}}) is None


def test_sees_every_kind_of_import(tmp_path):
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from pkg.a import A\n")
    (pkg / "a.py").write_text("A = 1\ndef f():\n    from pkg import b\n")  # function level
    (pkg / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import pkg.sub.c\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "c.py").write_text("from .. import a\nfrom . import d\n")  # relative
    (pkg / "sub" / "d.py").write_text("import os\n")
    graph, files = import_graph(pkg)
    assert graph == {"pkg": {"pkg.a": 1}, "pkg.a": {"pkg.b": 3}, "pkg.b": {"pkg.sub.c": 3}, "pkg.sub": {},
                     "pkg.sub.c": {"pkg.a": 1, "pkg.sub.d": 2}, "pkg.sub.d": {}}
    assert find_cycle(graph) == ["pkg.a", "pkg.b", "pkg.sub.c", "pkg.a"]
    assert "pkg/b.py:3" in _describe(find_cycle(graph), graph, files)


def _in_sim(module: str) -> bool:
    return module == "manip.sim" or module.startswith("manip.sim.")


def test_manip_sim_has_no_import_cycle():
    graph, files = import_graph()
    sim = {m: {t: ln for t, ln in deps.items() if _in_sim(t)} for m, deps in graph.items() if _in_sim(m)}
    cycle = find_cycle(sim)
    assert cycle is None, "import cycle in manip.sim:\n" + _describe(cycle, graph, files)


def test_manip_has_no_import_cycle():
    graph, files = import_graph()
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle in manip:\n" + _describe(cycle, graph, files)
