"""manip.batch: parallel planning gives the single calls' results, survives dead workers, rejects bad input early."""

from __future__ import annotations

import json
import multiprocessing as mp
import os
import signal
import subprocess
import sys
import time
from collections import Counter

import numpy as np
import pytest

from manip import MotionGenerator, Pose, UnknownNameError
from manip.batch import BATCH_OPTIONS, Problem, plan_many, plan_stream, problem_seed
from manip.batch import process_pool, worker
from manip.batch.plan import run_tasks
from manip.batch.problem import prepare
from manip.benchmarking.scenes import make_problems
from manip.errors import InvalidInputError
from manip.planning.options import PlanOptions
from manip.planning.result import PlanStatus

# Budgets far above the planning times, so that a loaded machine cannot change a result.
OPTIONS = {"time_budget": 30.0}
# The options of a single call that plans as a batch problem with OPTIONS does (the batch's count
# budget for the search where the problem gives none).
SINGLE = {**BATCH_OPTIONS, **OPTIONS}
SEED = 7


@pytest.fixture(scope="module")
def problems() -> list[Problem]:
    """Table and shelf problems with joint goals, one pose goal, and one start in collision."""
    base = make_problems("table", 4, 0) + make_problems("shelf", 3, 0)
    out = [Problem(p.world, p.start, p.goal, options=OPTIONS, id=f"{p.scene}/{p.index}") for p in base]
    mg = MotionGenerator("franka")
    out.append(Problem(base[1].world, base[1].start, mg.fk(base[1].goal), options=OPTIONS, id="pose"))
    p = base[0]
    hand = mg.fk(p.start).position
    blocked = {"cuboid": {"block": {"dims": [0.2, 0.2, 0.2], "pose": [*hand.tolist(), 1.0, 0.0, 0.0, 0.0]}}}
    out.append(Problem(blocked, p.start, p.goal, options=OPTIONS, id="blocked"))
    return out


@pytest.fixture(scope="module")
def reference(problems):
    """The single planning calls, in this process, on a fresh generator per problem."""
    worker.warm_up(("franka",))  # compile the kernels outside the budgets
    out = {}
    for i, p in enumerate(problems):
        mg = MotionGenerator("franka", p.world)
        seed = problem_seed(SEED, p.id)
        if isinstance(p.goal, Pose):
            out[p.id] = mg.plan_pose(p.start, p.goal, seed=seed, **SINGLE)
        else:
            out[p.id] = mg.plan_joints(p.start, p.goal, seed=seed, **SINGLE)
    return out


def assert_same(result, ref) -> None:
    assert result.status is ref.status
    assert result.source == ref.source
    if ref.trajectory is None:
        assert result.trajectory is None
    else:
        np.testing.assert_array_equal(result.trajectory.positions, ref.trajectory.positions)
        np.testing.assert_array_equal(result.trajectory.velocities, ref.trajectory.velocities)
        assert result.trajectory.dt == ref.trajectory.dt


def test_reference_has_successes_and_a_failure(reference):
    statuses = [r.status for r in reference.values()]
    assert statuses.count(PlanStatus.SUCCESS) >= len(statuses) - 1
    assert reference["blocked"].status is PlanStatus.INVALID_START_WORLD_COLLISION
    assert reference["pose"].success and reference["pose"].position_error < 1e-3


@pytest.mark.parametrize("workers", [1, 2])
def test_plan_many_returns_the_single_calls_results_in_input_order(problems, reference, workers):
    results = plan_many(problems, workers=workers, seed=SEED, progress=False)
    assert len(results) == len(problems)
    for p, r in zip(problems, results):
        assert_same(r, reference[p.id])


OTHER_START_METHODS = [m for m in process_pool.START_METHODS
                       if m in mp.get_all_start_methods() and m != process_pool.default_start_method()]


@pytest.mark.parametrize("method", OTHER_START_METHODS)
def test_every_start_method_gives_the_single_calls_results(problems, reference, method):
    results = plan_many(problems, workers=2, seed=SEED, progress=False, start_method=method)
    for p, r in zip(problems, results):
        assert_same(r, reference[p.id])
    assert not mp.active_children()


# Set in the calling test process at run time: only a forked copy of it sees the value.
_CALLER_STATE: dict[str, int] = {}


def _origin(task):
    """Where a worker came from: its parent process, and what it inherited or preloaded."""
    return task.id, {"parent": os.getppid(), "caller_state": dict(_CALLER_STATE),
                     "server_warmed": "manip.batch.forkserver_warm" in sys.modules}


@pytest.mark.parametrize("method", [m for m in process_pool.START_METHODS if m in mp.get_all_start_methods()])
def test_workers_start_with_the_chosen_method(problems, method, monkeypatch):
    monkeypatch.setitem(_CALLER_STATE, "pid", os.getpid())
    tasks = prepare(problems[:4], SEED)
    origins = dict(run_tasks(tasks, workers=2, backend="process", job=_origin, start_method=method))
    assert sorted(origins) == sorted(t.id for t in tasks)
    for o in origins.values():
        # fork: a copy of this process (its imports and state included); forkserver: forked by the fork
        # server, which preloaded and warmed manip; spawn: a fresh interpreter started from here
        assert (o["parent"] == os.getpid()) is (method != "forkserver")
        assert o["caller_state"] == (_CALLER_STATE if method == "fork" else {})
        assert o["server_warmed"] is (method == "forkserver")


# Plans made in this process since the counter was installed (a forked worker starts with a copy).
_PLANS: list[int] = []


def _plans_before(task):
    """How many plans this worker made before its task (a warm-up plan is one)."""
    return task.id, len(_PLANS)


@pytest.mark.skipif("fork" not in mp.get_all_start_methods(), reason="needs the fork start method")
def test_workers_forked_from_a_warm_caller_skip_the_warm_up(problems, monkeypatch):
    worker.warm_up(("franka",))  # the caller (as process_pool.WARM_CALLER makes it on its first batch)
    plan = MotionGenerator.plan_joints

    def counted(self, *args, **kwargs):
        _PLANS.append(1)
        return plan(self, *args, **kwargs)

    monkeypatch.setattr(MotionGenerator, "plan_joints", counted)
    monkeypatch.setattr(sys.modules[__name__], "_PLANS", [])
    tasks = prepare(problems[:4], SEED)
    before = dict(run_tasks(tasks, workers=2, backend="process", job=_plans_before, start_method="fork"))
    assert before == {t.id: 0 for t in tasks}
    monkeypatch.setattr(process_pool, "WARM_CALLER", False)
    monkeypatch.setattr(worker, "_WARM", set())  # as if the caller had never warmed up: each worker does
    before = dict(run_tasks(tasks, workers=2, backend="process", job=_plans_before, start_method="fork"))
    assert before == {t.id: 1 for t in tasks}


def _blas_threads(task):
    """The thread counts of this worker's native thread pools (BLAS: numpy's OpenBLAS)."""
    from threadpoolctl import threadpool_info

    return task.id, [pool["num_threads"] for pool in threadpool_info()]


@pytest.mark.parametrize("method", [m for m in process_pool.START_METHODS if m in mp.get_all_start_methods()])
def test_workers_run_one_blas_thread(problems, method):
    """A worker is one CPU: its BLAS threads would compete with the other workers for the cores."""
    tasks = prepare(problems[:2], SEED)
    threads = dict(run_tasks(tasks, workers=2, backend="process", job=_blas_threads, start_method=method))
    assert sorted(threads) == sorted(t.id for t in tasks)
    assert all(counts and set(counts) == {1} for counts in threads.values()), threads


def test_default_start_method():
    method = process_pool.default_start_method()
    if sys.platform.startswith("linux"):
        assert method == ("fork" if sys.version_info < (3, 12) else "forkserver")
    else:
        assert method == "spawn"
    assert process_pool.check_start_method(None) == method


def test_options_may_be_a_plan_options(problems, reference):
    # PlanOptions(time_budget=30) is the dict {"time_budget": 30} with every other field at its default
    batch = [Problem(p.world, p.start, p.goal, options=PlanOptions(**OPTIONS), id=p.id) for p in problems[:3]]
    for p, r in zip(batch, plan_many(batch, workers=1, seed=SEED, progress=False)):
        assert_same(r, reference[p.id])


def test_options_not_given_take_the_batch_defaults(problems):
    # a dict without the key, or a PlanOptions field left at its default, is not given; an
    # explicit {"search_iterations": None} plans until the time budget, as a single call does
    given = [None, {"time_budget": 9.0}, PlanOptions(time_budget=9.0, trajopt=False), {"search_iterations": None},
             PlanOptions(search_iterations=500)]
    p = problems[0]
    tasks = prepare([Problem(p.world, p.start, p.goal, options=o, id=i) for i, o in enumerate(given)], SEED)
    assert [{k: v for k, v in t.options.items() if k != "seed"} for t in tasks] == [
        BATCH_OPTIONS,
        {**BATCH_OPTIONS, "time_budget": 9.0},
        {**BATCH_OPTIONS, "time_budget": 9.0, "trajopt": False},
        {**BATCH_OPTIONS, "search_iterations": None},
        {**BATCH_OPTIONS, "search_iterations": 500},
    ]
    assert BATCH_OPTIONS["search_iterations"] >= 1 and BATCH_OPTIONS["time_budget"] > PlanOptions().time_budget


def test_seed_changes_searched_paths_and_ids_default_to_indices(problems, reference):
    joint = [Problem(p.world, p.start, p.goal, options=OPTIONS) for p in problems[:7]]
    results = plan_many(joint, workers=2, seed=SEED + 1, progress=False)
    searched = [i for i, p in enumerate(problems[:7]) if reference[p.id].source in ("trajopt", "shortcut")]
    assert searched, "the problem set needs searched paths"
    assert all(r.success for r in results)
    assert any(not np.array_equal(results[i].trajectory.positions, reference[problems[i].id].trajectory.positions)
               for i in searched)
    assert problem_seed(SEED, 3) != problem_seed(SEED, "3") != problem_seed(SEED + 1, 3)


def test_a_killed_worker_costs_a_retry_not_a_problem(problems, reference, caplog):
    seen = Counter()
    killed = None
    with caplog.at_level("WARNING", logger="manip.batch.process_pool"):
        for pid, result in plan_stream(problems, workers=2, seed=SEED):
            seen[pid] += 1
            if killed is None:  # others are being planned or queued
                killed = mp.active_children()[0].pid
                os.kill(killed, signal.SIGKILL)
            assert_same(result, reference[pid])
    assert killed is not None
    assert "a worker died" in caplog.text
    assert sorted(seen) == sorted(p.id for p in problems)
    assert set(seen.values()) == {1}
    assert not mp.active_children()


def test_no_more_workers_start_than_there_are_problems(problems, reference):
    before = set(mp.active_children())
    stream = plan_stream(problems[:2], workers=4, seed=SEED)
    pid, result = next(stream)
    assert len(set(mp.active_children()) - before) == 2   # 4 asked, 2 problems: 2 warm-ups, not 4
    assert_same(result, reference[pid])
    stream.close()


def test_closing_the_stream_early_stops_the_workers(problems):
    # workers of earlier tests' pools may still be exiting on a loaded machine: only this
    # stream's workers are checked
    before = set(mp.active_children())
    stream = plan_stream(problems, workers=2, seed=SEED)
    next(stream)
    assert set(mp.active_children()) - before
    stream.close()
    assert not set(mp.active_children()) - before


@pytest.mark.parametrize("change, error, words", [
    ({"robot": "not_a_robot"}, UnknownNameError, ["robot 'not_a_robot'", "franka"]),
    ({"world": {"cuboid": {"box": {"dims": [0.1, 0.1]}}}}, InvalidInputError, ["problem 2", "malformed world"]),
    ({"world": [1, 2]}, InvalidInputError, ["world must be"]),
    ({"start": np.zeros(6)}, InvalidInputError, ["start", "(7,)"]),
    ({"goal": np.full(7, np.nan)}, InvalidInputError, ["goal", "finite"]),
    ({"goal": np.eye(4)}, InvalidInputError, ["goal must have shape (7,); got (4, 4)", "a pose goal is a manip.Pose"]),
    ({"options": {"time_budget": -1.0}}, InvalidInputError, ["time_budget"]),
    ({"options": {"speed": 2}}, InvalidInputError, ["speed", "valid"]),
    ({"options": {"search_iterations": 0}}, InvalidInputError, ["problem 2", "search_iterations", "None"]),
    ({"options": {"seed": 3}}, InvalidInputError, ["seed", "derived"]),
    ({"options": PlanOptions(time_budget=30.0, seed=3)}, InvalidInputError, ["options.seed", "default", "derived"]),
    ({"options": [("time_budget", 1.0)]}, InvalidInputError, ["options must be a dict", "PlanOptions", "list"]),
    ({"id": 0}, InvalidInputError, ["id 0", "unique"]),
])
def test_bad_input_raises_before_any_worker_starts(problems, change, error, words):
    fields = {"world": problems[2].world, "start": problems[2].start, "goal": problems[2].goal, "id": 2}
    fields.update(change)
    batch = [Problem(problems[0].world, problems[0].start, problems[0].goal, id=0),
             Problem(problems[1].world, problems[1].start, problems[1].goal, id=1),
             Problem(**fields)]
    with pytest.raises(error) as info:
        plan_many(batch, workers=2, progress=False)
    for w in words:
        assert w in str(info.value)
    assert not mp.active_children()


@pytest.mark.parametrize("kwargs, words", [
    ({"workers": 0}, ["workers", ">= 1"]),
    ({"backend": "dask"}, ["backend", "process", "ray"]),
    ({"seed": -1}, ["seed"]),
    ({"start_method": "thread"}, ["start_method", "spawn", "'thread'"]),
    ({"backend": "ray", "start_method": "spawn"}, ["start_method", 'backend="process"']),
    ({"ray_address": "auto"}, ["ray_address", 'backend="ray"', "backend='process'"]),
    ({"backend": "ray", "ray_address": 6379}, ["ray_address", '"auto"', "6379"]),
])
def test_bad_batch_arguments(problems, kwargs, words):
    with pytest.raises(InvalidInputError) as info:
        plan_stream(problems[:2], **kwargs)
    for w in words:
        assert w in str(info.value)
    with pytest.raises(InvalidInputError, match="iterable of manip.batch.Problem"):
        plan_many(problems[0], progress=False)
    assert not mp.active_children()


def test_a_robot_yaml_path_plans_as_its_motion_generator_does(tmp_path):
    # a user's robot folder (here the UR5's configuration, copied), named by its path as
    # MotionGenerator takes it; a path without a robot.yaml fails before any worker starts
    import yaml

    from manip.robot_config import robots_root

    cfg = yaml.safe_load((robots_root() / "ur5" / "robot.yaml").read_text())
    cfg.update(name="my_arm", mjcf=None)
    folder = tmp_path / "my_arm"
    folder.mkdir()
    (folder / "robot.yaml").write_text(yaml.safe_dump(cfg))
    mg = MotionGenerator(str(folder / "robot.yaml"))
    q0 = mg.default_joint_positions
    hand = mg.fk(q0)
    world = {"cuboid": {"post": {"dims": [0.05, 0.05, 0.3],
                                 "pose": [*(hand.position + [0.1, 0.1, 0.0]).tolist(), 1, 0, 0, 0]}}}
    goals = [q0 + np.array([0.6, 0.2, -0.2, 0.1, 0.0, 0.3]), Pose(hand.position + [0.0, 0.1, -0.1], hand.quaternion)]
    batch = [Problem(world, q0, goals[0], robot=folder, options=OPTIONS, id="joint"),
             Problem(world, q0, goals[1], robot=str(folder / "robot.yaml"), options=OPTIONS, id="pose")]
    results = plan_many(batch, workers=1, seed=SEED, progress=False)
    mg.update_world(world)
    refs = [mg.plan_joints(q0, goals[0], seed=problem_seed(SEED, "joint"), **SINGLE),
            mg.plan_pose(q0, goals[1], seed=problem_seed(SEED, "pose"), **SINGLE)]
    for r, ref in zip(results, refs):
        assert ref.success
        assert_same(r, ref)
    with pytest.raises(InvalidInputError, match="neither a robot.yaml file nor a folder"):
        plan_many([Problem(world, q0, goals[0], robot=tmp_path)], workers=2, progress=False)
    with pytest.raises(UnknownNameError, match="robot 'my_arm' not found"):
        plan_many([Problem(world, q0, goals[0], robot="my_arm")], workers=2, progress=False)
    assert not mp.active_children()


def test_a_from_urdf_robot_plans_in_a_batch_as_its_motion_generator_does():
    # a robot without a folder: its RobotConfig (MotionGenerator.from_urdf(...).config) is the Problem's robot
    from importlib import metadata
    from pathlib import Path

    root = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data")))
    urdf, srdf = root / "robots/ur_description/urdf/ur5_robot.urdf", root / "robots/ur_description/srdf/ur5.srdf"
    q0 = np.array([0.0, -2.2, 1.9, -1.383, -1.57, 0.0])
    mg = MotionGenerator.from_urdf(urdf, srdf, ee_link="tool0", default_joint_positions=q0, name="my_ur5")
    hand = mg.fk(q0)
    goals = [q0 + np.array([0.6, 0.2, -0.2, 0.1, 0.0, 0.3]), Pose(hand.position + [0.0, 0.1, -0.1], hand.quaternion)]
    batch = [Problem({}, q0, g, robot=mg.config, options=OPTIONS, id=i) for i, g in enumerate(goals)]
    batch.append(Problem({}, q0, goals[0], robot="ur5", options=OPTIONS, id="shipped"))  # same name space, no clash
    results = plan_many(batch, workers=2, seed=SEED, progress=False)
    refs = [mg.plan_joints(q0, goals[0], seed=problem_seed(SEED, 0), **SINGLE),
            mg.plan_pose(q0, goals[1], seed=problem_seed(SEED, 1), **SINGLE)]
    for r, ref in zip(results, refs):
        assert ref.success
        assert_same(r, ref)
    assert results[2].success
    with pytest.raises(InvalidInputError, match=r"goal must have shape \(6,\)"):
        plan_many([Problem({}, q0, np.zeros(7), robot=mg.config)], progress=False)
    assert not mp.active_children()



def test_full_robot_states_are_taken_as_the_arm_joints_as_a_single_call_takes_them(problems):
    # a simulated Franka's state (7 arm joints, then 2 fingers), as plan_joints takes it: the
    # batch refused it ("start must have shape (7,); got (9,)") where the single call plans it
    p = problems[0]
    fingers = [0.04, 0.04]
    full = Problem(p.world, np.r_[p.start, fingers], np.r_[p.goal, fingers], options=OPTIONS, id="full")
    (task,) = prepare([full], SEED)
    np.testing.assert_array_equal(task.start, p.start)
    np.testing.assert_array_equal(task.goal, p.goal)
    (result,) = plan_many([full], workers=1, seed=SEED, progress=False)
    ref = MotionGenerator("franka", p.world).plan_joints(np.r_[p.start, fingers], np.r_[p.goal, fingers],
                                                         seed=problem_seed(SEED, "full"), **SINGLE)
    assert ref.success
    assert_same(result, ref)
    # two Frankas: each arm's state in turn (18 values) -> the 14 arm joints
    duo = MotionGenerator("dual_franka").default_joint_positions
    state = np.r_[duo[:7], fingers, duo[7:], fingers]
    (task,) = prepare([Problem({}, state, state, robot="dual_franka")], 0)
    np.testing.assert_array_equal(task.start, duo)
    with pytest.raises(InvalidInputError, match=r"start must have shape \(7,\); got \(8,\)"):
        prepare([Problem({}, np.r_[p.start, 0.04], p.goal)], 0)

# What a fresh interpreter loads: the numba kernels after `worker.warm_up`, and those that
# planning problems of every scene kind (joint goals, a pose goal, a start in collision) adds.
KERNEL_PROBE = """
import gc, json
from numba.core.dispatcher import Dispatcher
from manip import MotionGenerator, Pose
from manip.batch import Problem, worker
from manip.batch.problem import prepare
from manip.benchmarking.scenes import SCENE_KINDS, make_problems

def loaded():
    # summed by name: numba keeps a second dispatcher of a kernel that a cached kernel calls
    # (the compiled search's callees), in an order gc.get_objects does not fix
    out = {}
    for d in gc.get_objects():
        if isinstance(d, Dispatcher):
            name = f"{d.py_func.__module__}.{d.py_func.__qualname__}"
            out[name] = out.get(name, 0) + len(d.overloads)
    return out

worker.warm_up(("franka",))
warm = loaded()
options = {"time_budget": 30.0}
problems = [Problem(p.world, p.start, p.goal, options=options, id=f"{kind}/{p.index}")
            for kind in SCENE_KINDS for p in make_problems(kind, 2, 0)]
p = problems[0]
mg = MotionGenerator("franka")
hand = mg.fk(p.start).position
problems.append(Problem(p.world, p.start, mg.fk(p.goal), options=options, id="pose"))
problems.append(Problem({"cuboid": {"block": {"dims": [0.2, 0.2, 0.2], "pose": [*hand.tolist(), 1, 0, 0, 0]}}},
                        p.start, p.goal, options=options, id="blocked"))
statuses = [worker.solve(task)[1].status.name for task in prepare(problems, 0)]
after = loaded()
print(json.dumps({"warm": sum(warm.values()), "statuses": statuses,
                  "new": {k: n - warm.get(k, 0) for k, n in after.items() if n != warm.get(k, 0)}}))
"""


def test_warm_up_loads_every_kernel_that_planning_meets():
    # in a fresh interpreter: this test process has loaded the kernels in other tests
    out = subprocess.run([sys.executable, "-c", KERNEL_PROBE], capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["warm"] > 0
    assert report["statuses"].count("SUCCESS") >= len(report["statuses"]) - 2
    assert report["statuses"][-1] == "INVALID_START_WORLD_COLLISION"
    assert report["new"] == {}, f"kernels loaded while planning after the warm-up: {report['new']}"


# ------------------------------------------------------------------ Ray (the ray extra)
def kept_pids(ray) -> list[int]:
    """Process ids of the actors kept warm after the last Ray batch."""
    from manip.batch import ray_backend

    return sorted(ray.get([a.pid.remote() for a in ray_backend.kept_actors()]))


def test_ray_two_node_cluster_gives_the_local_results_bit_for_bit(ray_cluster, problems, reference):
    assert ray_cluster.cluster_resources()["CPU"] == 2
    results = plan_many(problems, backend="ray", seed=SEED, progress=False)
    for p, r in zip(problems, results):
        assert_same(r, reference[p.id])


def test_ray_actors_stay_warm_for_the_next_batch_until_released(ray_cluster, problems, reference):
    from manip.batch import release_ray_actors, ray_backend

    release_ray_actors()
    plan_many(problems[:3], backend="ray", seed=SEED, progress=False)
    first = kept_pids(ray_cluster)
    assert len(first) == 2  # one per CPU of the cluster, kept after the batch
    results = plan_many(problems, backend="ray", seed=SEED, progress=False)
    for p, r in zip(problems, results):
        assert_same(r, reference[p.id])
    assert kept_pids(ray_cluster) == first  # the second batch ran on the same warm processes
    # a kept actor that dies while idle is replaced before the next batch uses it
    os.kill(first[0], signal.SIGKILL)
    results = plan_many(problems[:4], backend="ray", seed=SEED, progress=False)
    for p, r in zip(problems[:4], results):
        assert_same(r, reference[p.id])
    assert len(kept_pids(ray_cluster)) == 2 and first[0] not in kept_pids(ray_cluster)
    assert release_ray_actors() == 2
    assert ray_backend.kept_actors() == []
    # with KEEP_WARM the actors of a batch are released after that many idle seconds
    keep = ray_backend.KEEP_WARM
    ray_backend.KEEP_WARM = 2.0
    try:
        plan_many(problems[:2], backend="ray", seed=SEED, progress=False)
        assert len(ray_backend.kept_actors()) == 2
        deadline = time.monotonic() + 20.0
        while ray_backend.kept_actors() and time.monotonic() < deadline:
            time.sleep(0.1)
        assert ray_backend.kept_actors() == []
    finally:
        ray_backend.KEEP_WARM = keep


def test_ray_batches_on_two_threads_at_once_give_the_single_results(ray_cluster, problems, reference):
    from concurrent.futures import ThreadPoolExecutor

    from manip.batch import release_ray_actors, ray_backend

    release_ray_actors()
    halves = [problems[::2], problems[1::2]]
    with ThreadPoolExecutor(2) as threads:
        results = list(threads.map(lambda ps: plan_many(ps, backend="ray", workers=1, seed=SEED, progress=False), halves))
    for ps, rs in zip(halves, results):
        for p, r in zip(ps, rs):
            assert_same(r, reference[p.id])
    # one actor is kept: the batch that ended first, if the other still ran, stopped its own (the other might
    # have waited for its CPU); if they ran one after the other, the second took the first one's
    assert len(ray_backend.kept_actors()) == 1


def test_ray_more_workers_than_cpus_plan_on_the_cpus_there_are(ray_cluster, problems, reference):
    from manip.batch import release_ray_actors, ray_backend

    release_ray_actors()
    results = plan_many(problems, backend="ray", workers=3, seed=SEED, progress=False)  # the cluster has 2 CPUs
    for p, r in zip(problems, results):
        assert_same(r, reference[p.id])
    # the third never got a CPU: stopped, not kept (one of the two with a CPU may not have started
    # before the other planned the whole batch: not kept either)
    assert 1 <= len(ray_backend.kept_actors()) <= 2


def test_ray_batch_closed_early_does_not_keep_its_actors(ray_cluster, problems):
    from manip.batch import release_ray_actors, ray_backend

    release_ray_actors()
    stream = plan_stream(problems, backend="ray", seed=SEED)
    next(stream)
    stream.close()  # its actors may still be planning queued problems: they are stopped
    assert ray_backend.kept_actors() == []
    assert len(plan_many(problems[:2], backend="ray", seed=SEED, progress=False)) == 2  # the CPUs were freed


def test_ray_killed_actor_costs_a_retry_not_a_problem(ray_cluster, problems, reference):
    from manip.batch import release_ray_actors, ray_backend
    from manip.batch.problem import prepare

    release_ray_actors()  # frees the cluster's CPUs for the actors started here
    actors = ray_backend.start_actors(2, ("franka",))
    try:
        pids = ray_cluster.get([a.pid.remote() for a in actors])
        seen = Counter()
        for pid, result in ray_backend.run(prepare(problems, SEED), None, actors=actors):
            if not seen:
                os.kill(pids[1], signal.SIGKILL)
            seen[pid] += 1
            assert_same(result, reference[pid])
        assert sorted(seen) == sorted(p.id for p in problems)
        assert set(seen.values()) == {1}
        assert ray_cluster.get(actors[1].pid.remote()) != pids[1]  # restarted
    finally:
        for a in actors:
            ray_cluster.kill(a, no_restart=True)
