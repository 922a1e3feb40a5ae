"""python -m manip.datagen: one writer per --out (a second run is refused, a crashed one holds
nothing), and a problem that raises is a failed row."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyarrow", reason="manip.datagen needs the datagen extra: pip install 'manip-robotics[datagen]'")
pytest.importorskip("pandas", reason="manip.datagen needs the datagen extra: pip install 'manip-robotics[datagen]'")

from manip.datagen import generate, read_dataset
from manip.datagen.__main__ import main
from manip.datagen.lock import LOCK_FILE, DatasetBusyError, writer_lock
from manip.datagen.problems import plan_ids, problem_id

ARGS = ["--scenes", "4", "--problems-per-scene", "3", "--kinds", "table,shelf", "--seed", "2", "--workers", "2",
        "--time-budget", "30", "--rows-per-part", "1", "--no-progress"]
IDS = sorted(problem_id(*t) for t in plan_ids(["table", "shelf"], 4, 3))
#: The runs started here are stopped (SIGSTOP) and killed by process group, read from /proc.
linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process groups and /proc (Linux)")


def command(out: Path) -> list[str]:
    return [sys.executable, "-m", "manip.datagen", *ARGS, "--out", str(out)]


def start(out: Path, wait_for_part: bool, log: Path) -> subprocess.Popen:
    """Start a run in a process group of its own (the run and its workers), its output in `log`;
    once it holds the folder (its pid in the lock file), or has written its first part file,
    stop the group (SIGSTOP), whatever the machine's speed. The caller sends SIGCONT or SIGKILL."""
    with open(log, "w") as f:  # a file, not a pipe: workers that outlive the run would hold a pipe open
        proc = subprocess.Popen(command(out), stdout=f, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    lock = out / LOCK_FILE

    def ready() -> bool:
        if wait_for_part:
            return bool(list(out.glob("part-*.parquet")))
        return lock.exists() and lock.read_text().startswith(f"pid {proc.pid} ")

    deadline = time.monotonic() + 300  # only so that a broken run cannot hang the suite
    while not ready() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.002)
    os.killpg(proc.pid, signal.SIGSTOP)
    assert proc.poll() is None, f"the run ended first: {log.read_text()}"
    return proc


def _group_alive(pgid: int) -> bool:
    """Whether a process of group `pgid` still runs (zombies of a reaped parent do not count)."""
    for status in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = status.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            return True
    return False


def files(out: Path) -> dict[str, tuple[int, int]]:
    return {p.name: (p.stat().st_size, p.stat().st_mtime_ns) for p in sorted(out.iterdir())}


@pytest.fixture(scope="module")
def refused(tmp_path_factory):
    """A run (frozen mid-way) and a second run of the same command on its folder; then the first
    goes on to its end. (folder, second run's CompletedProcess, first run's pid, files before and
    after the second run, the first run's return code and stdout)."""
    out = tmp_path_factory.mktemp("shared")
    log = out.parent / f"{out.name}.log"
    first = start(out, wait_for_part=False, log=log)  # stopped: it holds the folder
    try:
        before = files(out)
        second = subprocess.run(command(out), capture_output=True, text=True, timeout=300, check=False)
        after = files(out)
    finally:
        os.killpg(first.pid, signal.SIGCONT)
    first.wait(timeout=600)
    return out, second, first.pid, before, after, first.returncode, log.read_text()


@linux
def test_a_second_run_on_the_same_folder_is_refused_at_once_with_status_3(refused):
    out, second, first_pid, before, after, _, _ = refused
    assert second.returncode == 3, second.stderr
    err = second.stderr
    assert f"{out} is being written by another manip.datagen run (pid {first_pid} on " in err
    assert "use another --out" in err and "Traceback" not in err
    assert after == before  # it wrote nothing, renamed nothing


@linux
def test_the_first_run_ends_with_the_whole_dataset(refused):
    out, _, _, _, _, code, output = refused
    assert code == 0, output
    df = read_dataset(out)
    assert sorted(df.problem_id) == IDS  # every problem once
    assert df.success.all() and df.verified.all()
    assert not list(out.glob(".*.tmp"))


@linux
def test_a_killed_run_leaves_no_lock_and_a_rerun_completes_the_same_dataset(refused, tmp_path):
    out = tmp_path / "ds"
    crashed = start(out, wait_for_part=True, log=tmp_path / "crashed.log")  # stopped once a part is written
    os.kill(crashed.pid, signal.SIGKILL)  # the run's main process alone, as an OOM kill would
    crashed.wait(timeout=60)
    os.killpg(crashed.pid, signal.SIGCONT)  # its workers, while they outlive it, hold no lock
    written = len(read_dataset(out))
    assert 1 <= written <= len(IDS) and (out / LOCK_FILE).exists()
    try:
        rerun = subprocess.run(command(out), capture_output=True, text=True, timeout=600, check=False)
        # and they see that their parent is gone and exit (process_pool.PARENT_POLL)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and _group_alive(crashed.pid):
            time.sleep(0.1)
        assert not _group_alive(crashed.pid), "the crashed run's workers outlived it"
    finally:
        if _group_alive(crashed.pid):
            os.killpg(crashed.pid, signal.SIGKILL)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{written} already in" in rerun.stdout
    resumed = read_dataset(out).set_index("problem_id").sort_index()
    one_run = read_dataset(refused[0]).set_index("problem_id").sort_index()
    assert list(resumed.index) == IDS  # nothing lost, nothing twice
    for pid in IDS:  # the same rows as one uninterrupted run
        assert resumed.status[pid] == one_run.status[pid]
        np.testing.assert_array_equal(np.stack(resumed.positions[pid]), np.stack(one_run.positions[pid]))


def test_a_second_writer_in_the_same_process_is_refused(tmp_path):
    out = tmp_path / "ds"
    out.mkdir()
    with writer_lock(out):
        with pytest.raises(DatasetBusyError, match="being written by another manip.datagen run .in this process"):
            generate(out, scenes=1, problems_per_scene=1, workers=1)
        assert main(["--scenes", "1", "--problems-per-scene", "1", "--out", str(out), "--no-progress"]) == 3
    assert not list(out.glob("part-*"))  # nothing was planned
    # released: the folder can be written again
    with writer_lock(out):
        pass


def test_a_problem_that_raises_is_a_failed_row(tmp_path, capsys):
    out = tmp_path / "ds"
    # dt = 1 us: every motion would have more than MAX_SAMPLES samples, which the planner finds
    # only once it plans (the option alone is valid)
    args = ["--scenes", "2", "--problems-per-scene", "2", "--kinds", "table,box", "--workers", "2", "--no-progress",
            "--out", str(out)]
    assert main([*args, "--dt", "1e-6"]) == 0
    assert "4 raised (see their message)" in capsys.readouterr().out
    df = read_dataset(out)
    assert sorted(df.problem_id) == sorted(problem_id(*t) for t in plan_ids(["table", "box"], 2, 2))
    for _, row in df.iterrows():
        assert row.status == "raised" and not row.success and not row.verified
        assert row.message.startswith(f"problem '{row.problem_id}' raised InvalidInputError: dt: the motion lasts")
        assert row.positions is None and row.times is None
    # the dataset remembers its dt: a rerun with another is refused (status 2), the same one skips all
    assert main(args) == 2
    assert "dt" in capsys.readouterr().err
    assert main([*args, "--dt", "1e-6"]) == 0
    assert "4 already in" in capsys.readouterr().out
