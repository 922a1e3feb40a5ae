"""benchmarks/plan_stages.py: the per-stage report and the settings A/B on real plans."""

from __future__ import annotations

import json

import pytest
from robot_constants import REPO_ROOT, load_script

from manip.errors import InvalidInputError
from manip.planning.trajopt.settings import TrajOptSettings


@pytest.fixture(scope="module")
def stages():
    return load_script(REPO_ROOT / "benchmarks" / "plan_stages.py", "plan_stages")


def test_a_b_with_the_default_value_gives_the_same_plans_and_counts_their_qps(stages, tmp_path, capsys):
    out = tmp_path / "rows.json"
    default = TrajOptSettings().tolerance
    assert stages.main(["--limit-per-scene", "1", "--scenes", "box_panda", "--set", f"tolerance={default!r}",
                        "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "| stage | share of stage time |" in text and "| trajopt |" in text
    rows = json.loads(out.read_text())["rows"]
    assert len(rows["A"]) == len(rows["B"]) == 2  # one problem, joint and pose goals
    for a, b in zip(rows["A"], rows["B"]):
        assert a["success"] and b["success"]
        assert a["motion_hash"] == b["motion_hash"]  # the same settings: the same motion
        assert a["counters"]["qp"][0] == b["counters"]["qp"][0] >= 1  # the optimiser ran and was counted
        assert a["stages"]["trajopt"] > 0
    assert "identical motions 2/2" in text and "QPs 1.000" in text


def test_a_b_with_another_value_changes_the_optimiser(stages, tmp_path, capsys):
    out = tmp_path / "rows.json"
    assert stages.main(["--limit-per-scene", "1", "--scenes", "box_panda", "--goal", "joint", "--set",
                        "first_iterations=0", "--json", str(out)]) == 0
    rows = json.loads(out.read_text())["rows"]
    a, b = rows["A"][0], rows["B"][0]
    assert a["success"] and b["success"]
    assert a["counters"]["qp"][0] != b["counters"]["qp"][0] or a["motion_hash"] != b["motion_hash"]


def test_unknown_or_bad_settings_fail_before_planning(stages):
    with pytest.raises(InvalidInputError, match="'no_such_field' is not a TrajOptSettings field"):
        stages.main(["--set", "no_such_field=1"])
    with pytest.raises(InvalidInputError, match="first_iterations"):
        stages.main(["--set", "first_iterations=-1"])


def test_the_counting_is_undone_after_a_run(stages):
    from manip.collision.checker import CollisionChecker
    from manip.planning.trajopt import qp

    before = (qp.solve, CollisionChecker._check)
    assert stages.main(["--limit-per-scene", "1", "--scenes", "box_panda", "--goal", "joint"]) == 0
    assert (qp.solve, CollisionChecker._check) == before


def test_a_b_of_a_module_constant_is_applied_to_variant_b_only_and_restored(stages, tmp_path, capsys):
    from manip.planning.path import shortcut as shortcut_module
    from manip.planning.path import search

    out = tmp_path / "rows.json"
    calls = {"A": 0, "B": 0}
    original = shortcut_module.remove_redundant

    def counted(*args, **kwargs):  # which variant's plans see the constant
        calls["B" if search.MAX_REPAIRS == 5 else "A"] += 1
        return original(*args, **kwargs)

    shortcut_module.remove_redundant = counted
    try:
        assert stages.main(["--limit-per-scene", "1", "--scenes", "table_pick_panda", "--goal", "joint", "--set",
                            "manip.planning.path.search:MAX_REPAIRS=5", "--json", str(out)]) == 0
    finally:
        shortcut_module.remove_redundant = original
    assert search.MAX_REPAIRS == 6  # restored
    assert calls["A"] > 0 and calls["B"] > 0
    data = json.loads(out.read_text())
    assert data["constants"] == {"manip.planning.path.search:MAX_REPAIRS": 5}
    assert len(data["rows"]["A"]) == len(data["rows"]["B"]) == 1
    assert "manip.planning.path.search.MAX_REPAIRS = 5" in capsys.readouterr().out


def test_unknown_module_constants_fail_before_planning(stages):
    with pytest.raises(InvalidInputError, match="has no constant 'NO_SUCH'"):
        stages.main(["--set", "manip.planning.path.search:NO_SUCH=1"])
    with pytest.raises(InvalidInputError, match="no module 'manip.no_such_module'"):
        stages.main(["--set", "manip.no_such_module:X=1"])


def test_the_trajopt_table_accounts_for_the_whole_stage_and_is_undone(stages, tmp_path, capsys):
    from manip.planning.trajopt import qp, sco

    before = (qp.piqp, qp.solve, sco._solve_qp)
    out = tmp_path / "rows.json"
    assert stages.main(["--limit-per-scene", "1", "--scenes", "box_panda", "--goal", "joint", "--trajopt-table",
                        "--json", str(out)]) == 0
    assert (qp.piqp, qp.solve, sco._solve_qp) == before
    text = capsys.readouterr().out
    assert "| part | share of the stage |" in text and "| PIQP solve |" in text and "| PIQP setup |" in text
    row = json.loads(out.read_text())["rows"]["A"][0]
    parts = row["parts"]
    assert parts["PIQP solve"][0] == parts["PIQP setup"][0] == row["counters"]["qp"][0] >= 1
    stage = sum(t for k, (_, t) in parts.items() if not k.startswith("validate"))
    # every part's time is the stage's (exclusive times of one call tree): they add up to the
    # optimiser's own CPU time and stay within the plan's
    assert row["counters"]["trajopt"][1] <= stage <= row["cpu"]


def test_a_b_against_another_checkout_plans_b_in_a_worker_with_that_tree(stages, tmp_path, capsys):
    out = tmp_path / "rows.json"
    # this checkout against itself: B planned by the worker process, the same motions
    assert stages.main(["--limit-per-scene", "1", "--scenes", "box_panda", "--tree", str(REPO_ROOT), "--json",
                        str(out)]) == 0
    text = capsys.readouterr().out
    assert f"B = the manip of {REPO_ROOT.resolve()}" in text and "identical motions 2/2" in text
    rows = json.loads(out.read_text())["rows"]
    for a, b in zip(rows["A"], rows["B"]):
        assert a["problem"] == b["problem"] and a["kind"] == b["kind"] and b["success"]
        assert a["counters"]["qp"][0] == b["counters"]["qp"][0] >= 1  # counted in the worker too
    with pytest.raises(InvalidInputError, match="not a checkout of manip"):
        stages.main(["--tree", str(tmp_path)])
    with pytest.raises(InvalidInputError, match="one B variant at a time"):
        stages.main(["--tree", str(REPO_ROOT), "--set", "tolerance=0.01"])
