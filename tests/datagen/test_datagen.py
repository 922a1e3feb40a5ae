"""python -m manip.datagen: a small dataset end to end, resumed after Ctrl-C, readable with pandas."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyarrow", reason="manip.datagen needs the datagen extra: pip install 'manip-robotics[datagen]'")
pd = pytest.importorskip("pandas", reason="manip.datagen needs the datagen extra: pip install 'manip-robotics[datagen]'")

from manip.batch import problem_seed  # noqa: E402
from manip.benchmarking.verify import default_verifier  # noqa: E402
from manip.datagen import read_dataset  # noqa: E402
from manip.datagen.__main__ import main  # noqa: E402
from manip.errors import InvalidInputError  # noqa: E402

ARGS = ["--scenes", "3", "--problems-per-scene", "2", "--kinds", "table,shelf,box", "--seed", "4",
        "--workers", "2", "--time-budget", "30"]


@pytest.fixture(scope="module")
def full_dir(tmp_path_factory) -> Path:
    """The folder of one uninterrupted run."""
    out = tmp_path_factory.mktemp("full")
    assert main([*ARGS, "--out", str(out), "--no-progress"]) == 0
    return out


@pytest.fixture(scope="module")
def full(full_dir) -> pd.DataFrame:
    """The dataset of one uninterrupted run, indexed by problem id."""
    return read_dataset(full_dir).set_index("problem_id").sort_index()


def test_rows_hold_verified_trajectories_of_their_problems(full):
    assert sorted(full.index) == [f"{k}-000000-{j:02d}" for k in ("box", "shelf", "table") for j in range(2)]
    assert sorted(full.scene_id.unique()) == ["box-000000", "shelf-000000", "table-000000"]
    verifier = default_verifier()
    for pid, row in full.iterrows():
        assert row.seed == problem_seed(4, pid)
        world = json.loads(row.world)
        assert not verifier.check_configuration(row.start, world, "start")[0]
        assert not verifier.check_configuration(row.goal, world, "goal")[0]
        assert row.success and row.verified and row.status == "success", pid
        assert row.message == "", pid  # planned within its time budget: the same on any machine
        positions = np.stack(row.positions)
        assert positions.shape == (len(row.times), 7) and np.stack(row.velocities).shape == positions.shape
        np.testing.assert_allclose(positions[0], row.start, atol=1e-6)
        np.testing.assert_allclose(positions[-1], row.goal, atol=1e-3)
        assert row["dt"] > 0 and row.times[-1] == pytest.approx(row.motion_time)
        assert json.loads(row.timings)["total"] == pytest.approx(row.plan_time)


def test_ctrl_c_keeps_the_written_rows_and_a_rerun_completes_the_same_dataset(full, tmp_path):
    out = tmp_path / "ds"
    args = [*ARGS, "--scenes", "12"]  # the scenes of `full` and 9 more (ids do not depend on the count)
    cmd = [sys.executable, "-m", "manip.datagen", *args, "--out", str(out), "--rows-per-part", "1", "--no-progress"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(out.glob("part-*.parquet")) and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    written = read_dataset(out)
    if proc.returncode == 0:  # pragma: no cover  (finished before the signal arrived)
        pytest.skip("the run finished before Ctrl-C")
    assert proc.returncode == 130, err
    assert "run the same command to resume" in err
    assert 1 <= len(written) < 24
    assert not list(out.glob(".*.tmp"))
    rerun = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{len(written)} already in" in rerun.stdout and "problems/s" in rerun.stdout
    resumed = read_dataset(out).set_index("problem_id").sort_index()
    assert len(resumed) == 24 and resumed.index.is_unique  # every problem once
    assert set(full.index) <= set(resumed.index)
    for pid in full.index:
        np.testing.assert_array_equal(np.stack(resumed.positions[pid]), np.stack(full.positions[pid]))


def test_a_rerun_with_other_settings_is_refused(full, tmp_path, capsys):
    out = tmp_path / "ds"
    out.mkdir()
    (out / "_manifest.json").write_text(json.dumps({"format": 1, "seed": 5}))
    assert main([*ARGS, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "other settings" in err and "seed" in err


@pytest.mark.parametrize("args, words", [
    (["--kinds", "table,attic"], ["kinds", "attic", "shelf"]),
    (["--scenes", "0"], ["scenes"]),
    (["--problems-per-scene", "-1"], ["problems_per_scene"]),
    (["--time-budget", "0"], ["time_budget"]),
    (["--search-iterations", "0"], ["search_iterations", "None"]),
    (["--backend", "process", "--ray-address", "auto"], ["ray_address", 'backend="ray"']),
])
def test_bad_arguments_are_clear_errors(tmp_path, capsys, args, words):
    assert main(["--out", str(tmp_path / "x"), "--no-progress", *args]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err


def test_reading_an_empty_folder_says_so(tmp_path):
    with pytest.raises(InvalidInputError, match="no part"):
        read_dataset(tmp_path)


def test_read_dataset_gives_the_dataset_order_whatever_the_order_rows_were_written(full_dir, tmp_path):
    import pyarrow.parquet as pq

    dataset_order = [f"{k}-000000-{j:02d}" for k in ("table", "shelf", "box") for j in range(2)]
    table = pq.read_table(full_dir)
    # the same rows written in another order (as other workers or a resumed run would)
    out = tmp_path / "shuffled"
    out.mkdir()
    (out / "_manifest.json").write_text((full_dir / "_manifest.json").read_text())
    ids = table.column("problem_id").to_pylist()
    pq.write_table(table.take([ids.index(i) for i in reversed(dataset_order)]), out / "part-000000.parquet")
    assert list(pd.read_parquet(out).problem_id) == dataset_order[::-1]
    for folder in (full_dir, out):
        df = read_dataset(folder)
        assert list(df.problem_id) == dataset_order and list(df.index) == list(range(6))
        part = read_dataset(folder, columns=["status", "positions"])
        assert list(part.columns) == ["status", "positions"]
        assert all(np.array_equal(np.stack(a), np.stack(b)) for a, b in zip(part.positions, df.positions))
    with pytest.raises(InvalidInputError, match="unknown dataset column.*'positon'.*positions"):
        read_dataset(out, columns=["positon"])


def test_an_unusable_out_folder_is_a_clear_error(tmp_path, capsys):
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    assert main(["--out", str(a_file), "--no-progress"]) == 2
    assert f"cannot use {a_file} as the dataset folder" in capsys.readouterr().err
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "_manifest.json").write_text("{not json")
    assert main(["--out", str(broken), "--no-progress"]) == 2
    assert "not a manip.datagen manifest" in capsys.readouterr().err


def test_kinds_given_as_one_string_to_generate_is_named(tmp_path):
    from manip.datagen import generate

    with pytest.raises(InvalidInputError, match="list of names.*the string 'table'"):
        generate(tmp_path / "ds", kinds="table")
    assert not (tmp_path / "ds").exists()


def test_a_dataset_of_another_shipped_robot(tmp_path, capsys):
    from manip.benchmarking.verify import Verifier

    out = tmp_path / "ur5"
    args = ["--robot", "ur5", "--scenes", "2", "--problems-per-scene", "2", "--kinds", "table,shelf", "--seed", "1",
            "--workers", "2", "--time-budget", "30", "--out", str(out), "--no-progress"]
    assert main(args) == 0
    df = read_dataset(out)
    assert list(df.problem_id) == [f"{k}-000000-{j:02d}" for k in ("table", "shelf") for j in range(2)]
    verifier = Verifier("ur5")
    for _, row in df.iterrows():
        world = json.loads(row.world)
        assert row.robot == "ur5" and len(row.start) == 6
        assert not verifier.check_configuration(row.start, world, "start")[0]
        assert not verifier.check_configuration(row.goal, world, "goal")[0]
        assert row.success and row.verified, row.problem_id
        t = np.stack(row.positions)
        assert t.shape == (len(row.times), 6)
        check = verifier.verify_trajectory(world, np.asarray(row.times), t, np.stack(row.velocities),
                                           np.stack(row.accelerations), start_q=row.start, goal_q=row.goal)
        assert check.valid, check.reasons
    capsys.readouterr()
    assert main([*args[2:], "--robot", "xarm7"]) == 2   # the same folder, another robot
    assert "other settings" in capsys.readouterr().err
    assert main(["--robot", "ur3", "--out", str(tmp_path / "x"), "--no-progress"]) == 2
    assert "robot 'ur3' not found; available: dual_franka, dual_ur5, franka" in capsys.readouterr().err
