"""The shortcut, the repairs and straight motions check fewer configurations and give the same
answers (MotionBenchMaker's cage and bookshelf with the Panda): candidates screened a few at a
time (`shortcut.SCREEN_BATCH`) against all at once, `Validity.screened` after `screen` against
`segments`, the repairs' known segments, and `motion` with a short first batch."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest

from manip import MotionGenerator, WorldConfig
from manip.benchmarking.mbm_problems import default_dataset_path, load_mbm_problems
from manip.benchmarking.verify import Verifier
from manip.collision import segments as segments_module
from manip.collision.checker import CollisionChecker
from manip.planning.path import shortcut as shortcut_module
from manip.planning.path.search import search_path
from manip.planning.path.shortcut import shortcut
from manip.planning.validity import Validity


@pytest.fixture(scope="module")
def cases():
    """(Validity, start, goal, searched path) of three valid problems per scene whose straight
    line is blocked."""
    path = default_dataset_path()
    if not path.exists():
        pytest.skip(f"MotionBenchMaker data not found at {path}")
    mg = MotionGenerator("franka")
    verifier = Verifier(mg.config)
    out = []
    for scene in ("cage_panda", "bookshelf_small_panda"):
        found = 0
        for p in load_mbm_problems(path, scenes=[scene], limit_per_scene=15):
            if found == 3 or not verifier.check_problem(p).valid:
                continue
            mg.update_world(WorldConfig.from_dict(p.world))
            v0 = mg.validity
            v = Validity(mg.checker.snapshot(), v0.kinematics, v0.resolution, v0.search_resolution)
            start, goal = np.asarray(p.start, float), np.asarray(p.goal, float)
            if v.motion(start, goal):
                continue
            searched, _ = search_path(start, goal[None], v, np.random.default_rng(found), time.perf_counter() + 60)
            assert searched is not None and len(searched) > 2
            out.append((v, start, goal, searched))
            found += 1
    assert len(out) == 6
    return out


class _Counted:
    """Counts the configurations `CollisionChecker._check` is asked about."""

    def __init__(self, monkeypatch):
        self.configurations = 0
        check = CollisionChecker._check

        def counted(checker, Q, *args, **kwargs):
            self.configurations += Q.shape[0]
            return check(checker, Q, *args, **kwargs)

        monkeypatch.setattr(CollisionChecker, "_check", counted)


def test_shortcut_screens_a_few_at_a_time_with_the_same_paths(cases, monkeypatch):
    counted = _Counted(monkeypatch)
    checked = {}
    for batch in (None, 4, 1):
        monkeypatch.setattr(shortcut_module, "SCREEN_BATCH", batch)
        counted.configurations = 0
        paths = [shortcut(searched, v.segments, np.random.default_rng(7), time.perf_counter() + 60, screen=v.screen,
                          screened=v.screened) for v, _, _, searched in cases]
        checked[batch] = (counted.configurations, paths)
    for batch in (4, 1):
        assert all(np.array_equal(a, b) for a, b in zip(checked[None][1], checked[batch][1]))
    assert checked[4][0] < 0.95 * checked[None][0]
    for (v, _, _, _), path in zip(cases, checked[4][1]):
        assert v.path(path)


def test_screened_is_segments_after_the_screen(cases):
    rng = np.random.default_rng(0)
    for v, start, goal, searched in cases:
        Q0 = np.concatenate([searched[:-1], rng.uniform(v.kinematics.lower, v.kinematics.upper, (20, 7))])
        Q1 = np.concatenate([searched[1:], Q0[-20:] + rng.normal(scale=0.2, size=(20, 7))])
        ok = v.screen(Q0, Q1)
        both = ok.copy()
        both[ok] = v.screened(Q0[ok], Q1[ok])
        segments = v.segments(Q0, Q1)
        assert np.array_equal(both, segments)
        assert segments[:len(searched) - 1].all() and not segments.all()


def test_motion_answers_the_same_with_a_short_first_batch(cases, monkeypatch):
    rng = np.random.default_rng(1)
    ends = [np.concatenate([searched, [goal], rng.uniform(v.kinematics.lower, v.kinematics.upper, (15, 7))])
            for v, _, goal, searched in cases]
    counted = _Counted(monkeypatch)
    answers, checked = {}, {}
    for lead in (10**6, 8):   # one batch (as before) against 8 first
        monkeypatch.setattr(segments_module, "MOTION_LEAD", lead)
        counted.configurations, out = 0, []
        for (v, start, goal, searched), E in zip(cases, ends):
            out += [v.motion(start, q) for q in E] + [v.motion(a, b) for a, b in itertools.pairwise(searched)]
        answers[lead], checked[lead] = out, counted.configurations
    assert answers[8] == answers[10**6] and 0 < sum(answers[8]) < len(answers[8])
    assert checked[8] < checked[10**6]
