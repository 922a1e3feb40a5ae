"""The planning modules on toy problems given as callables (no robot): a 2-D square with a
wall that has one gap, as pyroboplan tests its RRT."""

from __future__ import annotations

import time
from types import SimpleNamespace

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.planning.options import PlanOptions
from manip.planning.path.restarts import GAIN, shorter_way_round, time_length
from manip.planning.path.rrt_connect import informed_sampler, rrt_connect
from manip.planning.path.search import search_path
from manip.planning.path.shortcut import path_length, remove_redundant, shortcut

LOWER, UPPER = np.zeros(2), np.ones(2)
START, GOAL = np.array([0.1, 0.1]), np.array([0.9, 0.1])


def in_wall(q: np.ndarray) -> bool:
    """The wall x in [0.45, 0.55], except the gap y in [0.8, 0.9]."""
    return 0.45 <= q[0] <= 0.55 and not (0.8 <= q[1] <= 0.9)


def motion_valid(a: np.ndarray, b: np.ndarray, resolution: float = 0.005) -> bool:
    n = max(2, int(np.ceil(np.max(np.abs(b - a)) / resolution)) + 1)
    return not any(in_wall(q) for q in np.linspace(a, b, n))


def segments_valid(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    return np.array([motion_valid(a, b) for a, b in zip(A, B)])


def advance(a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    n = max(2, int(np.ceil(np.max(np.abs(b - a)) / 0.005)) + 1)
    pts = np.linspace(a, b, n)
    free = [not in_wall(q) for q in pts]
    if all(free):
        return b.copy()
    k = free.index(False) - 3  # stop a few steps before the contact
    return pts[k] if k > 0 else None


def assert_valid_path(path: np.ndarray) -> None:
    assert np.array_equal(path[0], START) and np.array_equal(path[-1], GOAL)
    assert all(motion_valid(a, b) for a, b in zip(path[:-1], path[1:]))


@pytest.mark.parametrize("with_advance", [False, True])
def test_rrt_connect_finds_the_gap(with_advance):
    path, iterations = rrt_connect(
        START, GOAL[None], LOWER, UPPER, motion_valid, np.random.default_rng(0), time.perf_counter() + 60.0,
        advance=advance if with_advance else None, step_size=0.2, short_step=0.05,
    )
    assert path is not None and iterations > 0
    assert_valid_path(path)
    assert np.max(path[:, 1]) >= 0.8  # it went through the gap


def test_rrt_connect_is_deterministic_for_a_seed():
    runs = [
        rrt_connect(START, GOAL[None], LOWER, UPPER, motion_valid, np.random.default_rng(7), time.perf_counter() + 60.0,
                    step_size=0.2)[0]
        for _ in range(2)
    ]
    np.testing.assert_array_equal(runs[0], runs[1])


def test_rrt_connect_gives_up_when_there_is_no_way():
    closed = lambda a, b: motion_valid(a, b) and not any(0.4 <= q[0] <= 0.6 for q in np.linspace(a, b, 50))  # noqa: E731
    path, _ = rrt_connect(START, GOAL[None], LOWER, UPPER, closed, np.random.default_rng(0), time.perf_counter() + 0.3,
                          step_size=0.2, max_iterations=300)
    assert path is None


def test_informed_samples_lie_where_a_shorter_path_can_pass():
    lower, upper = -np.ones(3), np.ones(3)
    start, goal = np.array([-0.5, 0.0, 0.0]), np.array([0.5, 0.0, 0.0])
    sample = informed_sampler(start, goal, 1.6, lower, upper)
    Q = np.array([sample(np.random.default_rng(s)) for s in range(400)])
    via = np.linalg.norm(Q - start, axis=1) + np.linalg.norm(Q - goal, axis=1)
    assert np.all(via <= 1.6 + 1e-9)  # a path through any sample is at most 1.6 long
    assert np.all((Q >= lower) & (Q <= upper))
    assert np.max(np.abs(Q[:, 1])) > 0.5  # the set is filled, not only the segment
    np.testing.assert_array_equal(sample(np.random.default_rng(7)), sample(np.random.default_rng(7)))
    # no longer than the straight line: samples on the segment
    on_line = informed_sampler(start, goal, 0.5, lower, upper)(np.random.default_rng(0))
    assert np.allclose(on_line[1:], 0.0) and -0.5 <= on_line[0] <= 0.5


def test_rrt_connect_draws_its_global_samples_from_the_given_sampler():
    """Samples only above the wall's gap: the trees grow through it, never below the start."""
    drawn = []

    def above(rng):
        drawn.append(np.array([rng.uniform(0.0, 1.0), rng.uniform(0.8, 1.0)]))
        return drawn[-1]

    path, _ = rrt_connect(START, GOAL[None], LOWER, UPPER, motion_valid, np.random.default_rng(0),
                          time.perf_counter() + 60.0, step_size=0.2, local_fraction=0.0, sample=above)
    assert path is not None and drawn
    assert_valid_path(path)
    assert np.min(path[:, 1]) >= START[1] - 1e-12


def test_shortcut_shortens_and_stays_valid():
    detour = np.array([START, [0.1, 0.95], [0.3, 0.95], [0.5, 0.85], [0.7, 0.95], [0.9, 0.95], GOAL])
    assert_valid_path(detour)
    short = shortcut(detour, segments_valid, np.random.default_rng(0), time.perf_counter() + 60.0, rounds=20)
    assert_valid_path(short)
    assert path_length(short) < path_length(detour) - 0.2


def test_remove_redundant_with_a_screen_keeps_the_same_waypoints_for_fewer_fine_checks():
    # a zig-zag through the gap: some jumps cross the wall, some do not
    path = np.array([START, [0.2, 0.5], [0.3, 0.85], [0.5, 0.85], [0.6, 0.9], [0.7, 0.5], [0.8, 0.3], GOAL])
    assert_valid_path(path)
    checked = []

    def screen(A, B):  # coarse: a necessary condition of `fine` below
        return np.array([motion_valid(a, b, resolution=0.1) for a, b in zip(A, B)])

    def fine(A, B):  # the validity the result must have (screen first, as `Validity.segments`)
        checked.append(len(A))
        return screen(A, B) & segments_valid(A, B)

    plain = remove_redundant(path, fine)
    fine_plain = sum(checked)
    checked.clear()
    screened = remove_redundant(path, fine, screen)
    np.testing.assert_array_equal(screened, plain)
    assert 2 < len(plain) < len(path)
    assert sum(checked) < fine_plain


def _coarse_search_validity() -> tuple[SimpleNamespace, object]:
    """A Validity stand-in whose coarse search can jump over the wall (fine checks cannot),
    and its coarse motion check."""
    coarse = lambda a, b: motion_valid(a, b, resolution=0.2)  # noqa: E731  (can jump over the wall)
    validity = SimpleNamespace(
        kinematics=SimpleNamespace(lower=LOWER, upper=UPPER), resolution=0.005, search_resolution=0.2,
        coarse_motion=coarse, motion=motion_valid, coarse_advance=None, advance=advance,
        segments=segments_valid, path=lambda p: bool(segments_valid(p[:-1], p[1:]).all()),
    )
    return validity, coarse


def test_search_path_repairs_coarse_edges_at_the_fine_resolution():
    validity, _ = _coarse_search_validity()
    path, _ = search_path(START, GOAL[None], validity, np.random.default_rng(1), time.perf_counter() + 60.0)
    assert path is not None
    assert_valid_path(path)


def test_plan_options_are_validated_with_the_valid_names_listed():
    opts = PlanOptions().updated({"time_budget": 2, "seed": 3, "smoothness": "smooth"})
    assert opts.time_budget == 2.0 and opts.seed == 3 and opts.smoothness == "smooth"
    with pytest.raises(InvalidInputError, match=r"unknown planning option\(s\) \['budget'\]; valid: .*time_budget"):
        PlanOptions().updated({"budget": 1})
    for bad in ({"dt": 0}, {"velocity_scale": 1.5}, {"seed": -1}, {"seed": 1.5}, {"smoothness": "fast"},
                {"duration": float("nan")}, {"trajopt": "yes"}, {"ik_solutions": 0}):
        with pytest.raises(InvalidInputError):
            PlanOptions().updated(bad)


def _two_gap_validity():
    """A wall x in [0.45, 0.55] with a near gap (y in [0.30, 0.40], close to the straight line
    y = 0.2) and a far one (y in [0.85, 0.95])."""
    def blocked(q):
        return 0.45 <= q[0] <= 0.55 and not (0.30 <= q[1] <= 0.40 or 0.85 <= q[1] <= 0.95)

    def motion(a, b):
        n = max(2, int(np.ceil(np.max(np.abs(b - a)) / 0.005)) + 1)
        return not any(blocked(q) for q in np.linspace(a, b, n))

    def segments(A, B):
        return np.array([motion(a, b) for a, b in zip(A, B)])

    return SimpleNamespace(
        kinematics=SimpleNamespace(lower=LOWER, upper=UPPER), resolution=0.005, search_resolution=0.005,
        coarse_motion=motion, motion=motion, coarse_advance=None, advance=None, segments=segments,
        path=lambda p: bool(segments(p[:-1], p[1:]).all()),
    )


def test_a_detour_is_replaced_by_a_shorter_way_round():
    """A path over the far gap is replaced by a restart's way through the near one (informed samples)."""
    validity = _two_gap_validity()
    start, goal = np.array([0.1, 0.2]), np.array([0.9, 0.2])
    far = np.array([start, [0.4, 0.9], [0.6, 0.9], goal])  # through the far gap: a detour
    assert validity.path(far)
    vmax = np.ones(2)
    shorten = lambda p: shortcut(p, validity.segments, np.random.default_rng(0), time.perf_counter() + 60.0)  # noqa: E731
    path = shorter_way_round(far, goal[None], validity, shorten, rng=np.random.default_rng(3),
                             deadline=time.perf_counter() + 60.0, velocity=vmax)
    assert validity.path(path) and np.array_equal(path[0], start) and np.array_equal(path[-1], goal)
    assert time_length(path, vmax) <= GAIN * time_length(far, vmax)
    assert np.max(path[:, 1]) < 0.6  # through the near gap


def test_a_path_that_is_no_detour_is_kept_without_searching():
    validity = _two_gap_validity()
    start, goal = np.array([0.1, 0.35]), np.array([0.9, 0.35])
    straight = np.array([start, [0.5, 0.35], goal])
    rng = np.random.default_rng(0)
    state = rng.bit_generator.state
    out = shorter_way_round(straight, goal[None], validity, lambda p: p, rng=rng, deadline=time.perf_counter() + 60.0,
                            velocity=np.ones(2))
    assert out is straight and rng.bit_generator.state == state  # no search drew from the generator


def test_search_path_repairs_stop_at_their_iteration_cap():
    validity, coarse = _coarse_search_validity()
    deadline = time.perf_counter() + 60.0
    # the same generator state: the same coarse search, then repairs through the gap
    _, coarse_only = rrt_connect(START, GOAL[None], LOWER, UPPER, coarse, np.random.default_rng(1), deadline)
    free, free_iterations = search_path(START, GOAL[None], validity, np.random.default_rng(1), deadline)
    assert free is not None and free_iterations - coarse_only > 2  # the repairs need several iterations
    for cap in (1, 2):
        path, iterations = search_path(START, GOAL[None], validity, np.random.default_rng(1), deadline,
                                       max_repair_iterations=cap)
        assert iterations - coarse_only <= cap
        assert path is None  # the repairs did not finish within the cap

