"""The house's layout rules: modules stay small and tests/ mirrors manip/."""

from __future__ import annotations

from robot_constants import REPO_ROOT

PACKAGE = REPO_ROOT / "manip"
TESTS = REPO_ROOT / "tests"
#: The largest module, in lines (the house style aims for ~500).
MAX_LINES = 600
#: Test folders that hold a package's helpers, not tests of a package of their own.
HELPER_FOLDERS = {"seeds", "listings", "__pycache__"}


def test_no_module_is_over_the_line_limit():
    long = {str(p.relative_to(REPO_ROOT)): n for p in PACKAGE.rglob("*.py")
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, f"modules over {MAX_LINES} lines: {long}"


def test_every_test_folder_mirrors_a_package():
    folders = [d for d in TESTS.rglob("*") if d.is_dir() and not (set(d.relative_to(TESTS).parts) & HELPER_FOLDERS)]
    orphans = [str(d.relative_to(TESTS)) for d in folders if not (PACKAGE / d.relative_to(TESTS) / "__init__.py").exists()]
    assert not orphans, f"test folders with no package of manip/ at the same place: {orphans}"
    for test in TESTS.rglob("test_*.py"):
        rel = test.relative_to(TESTS)
        if set(rel.parts) & HELPER_FOLDERS:
            continue
        assert (PACKAGE / rel.parent / "__init__.py").exists() or rel.parent.parts == (), rel
