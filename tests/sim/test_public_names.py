"""The public faces: `manip.sim.__all__` and `manip.__all__` list names, never submodules."""

from __future__ import annotations

import ast
import types
import warnings
from pathlib import Path

import manip
import manip.sim

SIM_INIT = Path(manip.sim.__file__)


def test_sim_all_is_a_literal_list_of_names_and_no_submodule():
    tree = ast.parse(SIM_INIT.read_text())
    assigned = [n for n in tree.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                and any(getattr(t, "id", None) == "__all__" for t in getattr(n, "targets", [getattr(n, "target", None)]))]
    assert len(assigned) == 1 and isinstance(assigned[0].value, ast.List)
    literal = [ast.literal_eval(e) for e in assigned[0].value.elts]
    assert literal == manip.sim.__all__ and len(set(literal)) == len(literal)
    modules = [n for n in manip.sim.__all__ if isinstance(getattr(manip.sim, n), types.ModuleType)]
    assert not modules
    public = {n for n in dir(manip.sim) if not n.startswith("_") and n != "annotations"
              and not isinstance(getattr(manip.sim, n), types.ModuleType)}
    assert public == set(manip.sim.__all__)  # every public name is listed


def test_star_import_binds_no_module_over_the_standard_librarys():
    namespace: dict = {}
    exec("import types\nfrom manip.sim import *", namespace)
    assert namespace["types"] is types
    exec("from manip.sim import carb", namespace)
    assert callable(namespace["carb"].log_error)


def test_manip_all_exports_no_deprecated_or_private_name():
    assert "TutorialAPI" not in manip.__all__
    assert not [n for n in manip.__all__ if n.startswith("_")]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert manip.TutorialAPI is manip.TutorialMotionGen
    assert any(issubclass(w.category, DeprecationWarning) for w in caught)
