"""The compiled coarse search (`planning.path.compiled_search`) on real problems: valid paths by
the exact checker, the same paths as the Python RRT-Connect for a seed, and a clean failure."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import default_dataset_path, load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.planning.path import search as search_module
from manip.planning.path.compiled_search import CompiledChecks
from manip.planning.path.rrt_connect import informed_sampler, rrt_connect
from manip.planning.validity import Validity


@pytest.fixture(scope="module")
def mg() -> MotionGenerator:
    return MotionGenerator("franka")


@pytest.fixture(scope="module")
def problems(mg):
    """Two valid problems of each of the cage (a bug trap) and bookshelf_small whose straight line
    is blocked (so that the search runs)."""
    path = default_dataset_path()
    if not path.exists():
        pytest.skip(f"MotionBenchMaker data not found at {path}")
    verifier = Verifier(mg.config)
    out = []
    for scene in ("cage_panda", "bookshelf_small_panda"):
        found = 0
        for p in load_mbm_problems(path, scenes=[scene], limit_per_scene=12):
            if found < 2 and verifier.check_problem(p).valid:
                mg.update_world(WorldConfig.from_dict(p.world))
                if not mg.checker.motion_valid(np.asarray(p.start, float), np.asarray(p.goal, float), 0.08):
                    out.append(p)
                    found += 1
    assert len(out) == 4
    return out


def _validity(mg: MotionGenerator, problem) -> Validity:
    mg.update_world(WorldConfig.from_dict(problem.world))
    v = mg.validity
    return Validity(mg.checker.snapshot(), v.kinematics, v.resolution, v.search_resolution)


def _search(v: Validity, start, goals, seed: int, compiled: bool, max_iterations: int = 20000, sample=None):
    checks = search_module.compiled_checks(v) if compiled else None
    if compiled:
        assert isinstance(checks, CompiledChecks)
    return rrt_connect(start, goals, v.kinematics.lower, v.kinematics.upper, v.coarse_motion,
                       np.random.default_rng(seed), time.perf_counter() + 600.0, advance=v.coarse_advance,
                       max_iterations=max_iterations, sample=sample, compiled=checks)


def test_compiled_search_matches_python_and_is_valid(mg, problems):
    for p in problems:
        v = _validity(mg, p)
        start, goal = np.asarray(p.start, float), np.asarray(p.goal, float)
        for seed in (0, 1):
            path, its = _search(v, start, goal[None], seed, compiled=True)
            assert path is not None, (p.scene, p.index, seed)
            assert np.array_equal(path[0], start) and np.array_equal(path[-1], goal)
            # every segment free at the search resolution, by the exact checker
            for a, b in itertools.pairwise(path):
                assert mg.checker.motion_valid(a, b, v.search_resolution)
            ref, ref_its = _search(v, start, goal[None], seed, compiled=False)
            assert its == ref_its and np.array_equal(path, ref), (p.scene, p.index, seed)


def test_compiled_search_is_deterministic_and_keeps_the_generator_in_step(mg, problems):
    v = _validity(mg, problems[0])
    start, goal = np.asarray(problems[0].start, float), np.asarray(problems[0].goal, float)
    rngs = [np.random.default_rng(7), np.random.default_rng(7)]
    paths = []
    for rng, compiled in zip(rngs, (True, False)):
        checks = search_module.compiled_checks(v) if compiled else None
        paths.append(rrt_connect(start, goal[None], v.kinematics.lower, v.kinematics.upper, v.coarse_motion, rng,
                                 time.perf_counter() + 600.0, advance=v.coarse_advance, compiled=checks)[0])
    again = _search(v, start, goal[None], 7, compiled=True)[0]
    assert np.array_equal(paths[0], paths[1]) and np.array_equal(paths[0], again)
    # the search drew as many numbers from the generator as the Python one
    assert rngs[0].random() == rngs[1].random()


def test_compiled_search_with_goal_roots_and_informed_samples(mg, problems):
    p = problems[2]
    v = _validity(mg, p)
    start, goal = np.asarray(p.start, float), np.asarray(p.goal, float)
    goals = np.stack([goal, np.clip(goal + 0.05, v.kinematics.lower, v.kinematics.upper)])
    goals = goals[v.configs(goals)]
    sample = informed_sampler(start, goal, 3.0 * float(np.linalg.norm(goal - start)), v.kinematics.lower,
                              v.kinematics.upper)
    a, ia = _search(v, start, goals, 3, compiled=True, max_iterations=300, sample=sample)
    b, ib = _search(v, start, goals, 3, compiled=False, max_iterations=300, sample=sample)
    assert ia == ib
    assert (a is None and b is None) or np.allclose(a, b, rtol=0, atol=1e-9)


def test_compiled_search_fails_cleanly_within_its_cap(mg):
    """The goal lies outside a closed shell around the robot: no path; None after the cap."""
    walls = {"floor": ([3, 3, 0.02], [0, 0, -0.06]), "roof": ([3, 3, 0.02], [0, 0, 1.3]),
             "front": ([0.02, 3, 1.4], [0.75, 0, 0.6]), "back": ([0.02, 3, 1.4], [-0.75, 0, 0.6]),
             "left": ([3, 0.02, 1.4], [0, 0.75, 0.6]), "right": ([3, 0.02, 1.4], [0, -0.75, 0.6])}
    mg.update_world(WorldConfig.from_dict({"cuboid": {k: {"dims": d, "pose": [*c, 1, 0, 0, 0]}
                                                      for k, (d, c) in walls.items()}}))
    v = Validity(mg.checker.snapshot(), mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
    start = mg.default_joint_positions
    goal = np.array([0.0, 1.5, 0.0, -0.1, 0.0, 1.6, 0.785])   # the arm stretched out through the front wall
    assert v.configs(start[None])[0] and not v.configs(goal[None])[0]
    path, its = _search(v, start, goal[None], 0, compiled=True, max_iterations=150)
    assert path is None and its == 150
    assert _search(v, start, goal[None], 0, compiled=False, max_iterations=150) == (None, 150)


def test_compiled_search_is_off_where_it_cannot_answer(mg, problems, monkeypatch):
    v = _validity(mg, problems[0])
    assert search_module.compiled_checks(v) is not None
    strict_fine = Validity(v.checker, v.kinematics, v.resolution, v.resolution, certified=True)
    assert search_module.compiled_checks(strict_fine) is None   # its advances certify
    monkeypatch.setattr(search_module, "COMPILED_SEARCH", False)
    assert search_module.compiled_checks(v) is None


def test_compiled_search_stops_at_the_deadline(mg, problems):
    v = _validity(mg, problems[0])
    start, goal = np.asarray(problems[0].start, float), np.asarray(problems[0].goal, float)
    checks = search_module.compiled_checks(v)
    path, its = rrt_connect(start, goal[None], v.kinematics.lower, v.kinematics.upper, v.coarse_motion,
                            np.random.default_rng(0), time.perf_counter() - 1.0, advance=v.coarse_advance,
                            compiled=checks)
    assert path is None and its == 1


def test_kernel_narrowphase_decides_the_cuboid_worlds_and_keeps_the_searches(mg, problems, monkeypatch):
    """MotionBenchMaker's worlds are cuboids and cylinders and the Panda's meshes are convex: the
    kernel decides every candidate (coal none), and the searches are those of coal's answers."""
    from manip.planning.path import compiled_search

    for p in problems[::2]:
        v = _validity(mg, p)
        start, goal = np.asarray(p.start, float), np.asarray(p.goal, float)
        runs = {}
        for on in (True, False):
            monkeypatch.setattr(compiled_search, "KERNEL_NARROWPHASE", on)
            checks = search_module.compiled_checks(v)
            assert checks.narrow == on
            path, its = rrt_connect(start, goal[None], v.kinematics.lower, v.kinematics.upper, v.coarse_motion,
                                    np.random.default_rng(0), time.perf_counter() + 600.0, advance=v.coarse_advance,
                                    compiled=checks)
            runs[on] = (path, its, checks.counts)
        (a, ia, ca), (b, ib, cb) = runs[True], runs[False]
        assert ia == ib and np.array_equal(a, b), (p.scene, p.index)
        assert ca[3] > 0 and ca[0] == 0          # kernel decided, coal none
        assert cb[3] == 0 and cb[0] == ca[3]     # coal decided the same configurations
        assert search_module.compiled_checks(v, fine=True).narrow is False   # never the repairs


def _coarse(v: Validity, start, goal):
    checks = search_module.compiled_checks(v)
    path, its = rrt_connect(start, goal[None], v.kinematics.lower, v.kinematics.upper, v.coarse_motion,
                            np.random.default_rng(0), time.perf_counter() + 600.0, advance=v.coarse_advance,
                            compiled=checks)
    return path, its, checks.counts


def test_kernel_narrowphase_leaves_meshes_to_coal_and_skips_allowed_contacts(mg, monkeypatch):
    """A mesh obstacle's candidates go to coal, a cuboid's are decided in the kernel; with every
    contact of a block allowed, the search is the one of a world without it."""
    from manip.collision.shapes import Cuboid, Mesh
    from manip.planning.path import compiled_search

    box = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * 0.15
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],
                      [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    q0 = mg.default_joint_positions
    goal = np.clip(q0 + np.array([1.6, 0.4, 0.0, 0.3, 0.0, 0.0, 0.0]), mg.kinematics.lower, mg.kinematics.upper)
    pose = [0.35, 0.3, 0.45]
    found = {}
    for name, ob in (("mesh", Mesh("block", vertices=box, faces=faces, pose=pose)),
                     ("cuboid", Cuboid("block", dims=[0.3, 0.3, 0.3], pose=pose))):
        mg.update_world(WorldConfig([ob]))
        v = Validity(mg.checker.snapshot(), mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
        assert not v.coarse_motion(q0, goal)   # the block is in the way
        found[name] = _coarse(v, q0, goal)
        links = sorted({p.name for p in mg.checker.state.parts})
        allowed = mg.checker.allowing([(link, "block") for link in links])
        va = Validity(allowed, mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
        found[name + " allowed"] = _coarse(va, q0, goal)
        monkeypatch.setattr(compiled_search, "KERNEL_NARROWPHASE", False)
        found[name + " allowed, coal"] = _coarse(va, q0, goal)
        monkeypatch.setattr(compiled_search, "KERNEL_NARROWPHASE", True)
    mg.update_world(WorldConfig())
    v = Validity(mg.checker.snapshot(), mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
    empty = _coarse(v, q0, goal)
    assert found["mesh"][2][0] > 0       # coal decided the mesh's candidates (the kernel: self ones)
    assert found["cuboid"][2][3] > 0 and found["cuboid"][2][0] == 0
    assert found["mesh"][0] is not None and found["cuboid"][0] is not None
    for key in ("mesh allowed", "cuboid allowed", "mesh allowed, coal", "cuboid allowed, coal"):
        assert found[key][1] == empty[1] and np.array_equal(found[key][0], empty[0]), key


@pytest.mark.parametrize("shape", ["cuboid", "cylinder", "capsule"])
def test_kernel_narrowphase_with_an_attached_object_keeps_the_searches(mg, monkeypatch, shape):
    """An object carried by the hand (a box, cylinder or capsule part) around a block: the
    kernel's answers are coal's, so the search is the one with coal alone."""
    from manip.collision.checker import CollisionChecker
    from manip.collision.shapes import Capsule, Cuboid, Cylinder
    from manip.planning.path import compiled_search

    held = {"cuboid": Cuboid("held", dims=[0.04, 0.04, 0.08]), "cylinder": Cylinder("held", radius=0.02, height=0.08),
            "capsule": Capsule("held", radius=0.02, height=0.06)}[shape]
    carrier = CollisionChecker(mg.config)
    carrier.set_world(WorldConfig([Cuboid("block", dims=[0.3, 0.3, 0.3], pose=[0.35, 0.3, 0.45])]))
    carrier.attach_object(held, pose_in_link=[0.0, 0.0, 0.15], allowed_links=["panda_leftfinger", "panda_rightfinger"])
    v = Validity(carrier.snapshot(), mg.kinematics, mg.validity.resolution, mg.validity.search_resolution)
    start = mg.default_joint_positions
    goal = np.clip(start + np.array([1.6, 0.4, 0.0, 0.3, 0.0, 0.0, 0.0]), mg.kinematics.lower, mg.kinematics.upper)
    assert v.configs(np.array([start, goal])).all() and not v.coarse_motion(start, goal)
    runs = {}
    for on in (True, False):
        monkeypatch.setattr(compiled_search, "KERNEL_NARROWPHASE", on)
        runs[on] = _coarse(v, start, goal)
    assert runs[True][0] is not None
    assert runs[True][1] == runs[False][1] and np.array_equal(runs[True][0], runs[False][0])
    assert runs[True][2][3] == runs[False][2][0] > 0 and runs[True][2][0] == 0
