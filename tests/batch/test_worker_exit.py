"""manip.batch's local workers end when their caller is killed outright (kill -9, the OOM
killer), whatever the start method: forked workers, a fork server's (the default on Linux with
Python >= 3.12; the server itself lives until the caller and all its workers have gone) and
spawned ones."""

from __future__ import annotations

import json
import multiprocessing as mp
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from manip.batch.process_pool import PARENT_POLL, process_identity

CALLER = textwrap.dedent("""
    import json, multiprocessing as mp, multiprocessing.forkserver, sys, time
    import numpy as np
    from manip.batch import Problem, plan_stream
    q0 = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])
    problems = [Problem(world={}, start=q0, goal=q0 + 0.01 * (k % 20 + 1)) for k in range(60)]
    stream = plan_stream(problems, workers=2, start_method=sys.argv[1])
    next(stream)   # the pool runs; the caller holds it, with tasks queued
    server = getattr(getattr(mp.forkserver, "_forkserver", None), "_forkserver_pid", None)
    print(json.dumps({"workers": [p.pid for p in mp.active_children()], "server": server}), flush=True)
    time.sleep(600)
""")

linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc and the start methods of Linux")


@linux
@pytest.mark.parametrize("method", [m for m in ("fork", "forkserver", "spawn") if m in mp.get_all_start_methods()])
def test_a_killed_callers_workers_exit(method, tmp_path):
    caller = subprocess.Popen([sys.executable, "-c", CALLER, method], stdout=subprocess.PIPE, text=True,
                              cwd=tmp_path, start_new_session=True)
    try:
        line = caller.stdout.readline()
        assert line, f"the caller ended first (return code {caller.wait()})"
        seen = json.loads(line)
        procs = seen["workers"] + ([seen["server"]] if method == "forkserver" and seen["server"] else [])
        assert len(seen["workers"]) >= 2 and all(process_identity(p) is not None for p in procs), seen
        os.kill(caller.pid, signal.SIGKILL)
        caller.wait(timeout=60)
        deadline = time.monotonic() + 20 * PARENT_POLL + 10
        while time.monotonic() < deadline and any(process_identity(p) is not None for p in procs):
            time.sleep(0.05)
        assert [p for p in procs if process_identity(p) is not None] == [], \
            f"{method}: processes outlived their killed caller: {procs}"
    finally:
        if caller.poll() is None:
            caller.kill()
        try:
            os.killpg(caller.pid, signal.SIGKILL)   # whatever is left of its group
        except ProcessLookupError:
            pass


def test_a_process_identity_tells_a_live_process_from_a_gone_one():
    assert process_identity(os.getpid()) is not None
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    assert process_identity(int(done.stdout)) is None   # exited and reaped
