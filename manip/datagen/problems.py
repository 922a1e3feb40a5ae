"""The problems of a dataset: seeded scenes and collision-free start/goal pairs in each.

Scene `s` (0-based over the whole dataset) is of kind `kinds[s % len(kinds)]` and is scene
number `i = s // len(kinds)` of that kind: the first problem that
`manip.benchmarking.scenes.make_problems(kind, 1, scene_seed(seed, kind, i))` makes (the
seeded generator of the benchmarks, given a seed of its own per scene, so that any scene is
made in constant time by whichever worker plans it). Pair 0 of a scene is the generator's
own start/goal (a goal inside the structure); pairs 1.. are random configurations within
the joint limits that the independent verifier finds free of self and world collision, drawn
from a generator seeded by (seed, kind, scene, pair). A problem's id names all of this:
"table-000003-01" is pair 1 of table scene 3; it does not depend on the number of scenes,
so a larger rerun extends a dataset.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from manip.benchmarking.scenes import SCENE_KINDS, make_problems
from manip.benchmarking.verify import Verifier, default_verifier
from manip.errors import InvalidInputError
from manip.validation import integer

log = logging.getLogger(__name__)

#: Random configurations tried per start or goal of an extra pair.
MAX_TRIES = 500
#: Smallest L-inf distance between the start and the goal of an extra pair [rad].
MIN_DISTANCE = 0.3


@dataclass(frozen=True)
class DataProblem:
    """One problem of a dataset.

    Attributes:
        id: "<kind>-<scene:06d>-<pair:02d>".
        kind: scene kind.
        scene: index of the scene among those of its kind.
        pair: index of the start/goal pair in the scene.
        world: the scene in cuRobo's world format.
        start: (dof,) start [rad].
        goal: (dof,) goal [rad].
    """

    id: str
    kind: str
    scene: int
    pair: int
    world: dict = field(repr=False)
    start: np.ndarray = field(repr=False)
    goal: np.ndarray = field(repr=False)

    @property
    def scene_id(self) -> str:
        """"<kind>-<scene:06d>"."""
        return f"{self.kind}-{self.scene:06d}"


def problem_id(kind: str, scene: int, pair: int) -> str:
    """The id of pair `pair` of scene `scene` of `kind`."""
    return f"{kind}-{scene:06d}-{pair:02d}"


def check_kinds(kinds: Sequence[str]) -> tuple[str, ...]:
    """`kinds` as a tuple; unknown or repeated kinds raise InvalidInputError listing the valid ones."""
    if isinstance(kinds, str):
        raise InvalidInputError(f"kinds must be a list of names among {list(SCENE_KINDS)} (e.g. ['table', 'shelf']); "
                                f"got the string {kinds!r}")
    kinds = tuple(kinds)
    bad = [k for k in kinds if k not in SCENE_KINDS]
    if bad or not kinds or len(set(kinds)) != len(kinds):
        raise InvalidInputError(f"kinds must be distinct names among {list(SCENE_KINDS)}; got {list(kinds)}")
    return kinds


def plan_ids(kinds: Sequence[str], scenes: int, per_scene: int) -> list[tuple[str, int, int]]:
    """(kind, scene, pair) of every problem of a dataset, in order."""
    kinds = check_kinds(kinds)
    scenes = integer(scenes, "scenes", 1)
    per_scene = integer(per_scene, "problems_per_scene", 1)
    return [(kinds[s % len(kinds)], s // len(kinds), j) for s in range(scenes) for j in range(per_scene)]


def _random_free(verifier: Verifier, world: dict, rng: np.random.Generator, away_from: np.ndarray | None) -> np.ndarray:
    for _ in range(MAX_TRIES):
        q = rng.uniform(verifier.lower, verifier.upper)
        if away_from is not None and np.abs(q - away_from).max() < MIN_DISTANCE:
            continue
        if not verifier.check_configuration(q, world, "q")[0]:
            return q
    raise RuntimeError(f"no collision-free configuration in {MAX_TRIES} random draws")  # pragma: no cover


def scene_seed(seed: int, kind: str, scene: int) -> int:
    """The generator seed of scene `scene` of `kind` in a dataset of seed `seed` (in [0, 2**32))."""
    key = (SCENE_KINDS.index(kind), integer(scene, "scene", 0))
    return int(np.random.SeedSequence(integer(seed, "seed", 0), spawn_key=key).generate_state(1)[0])


def make_scene(kind: str, scene: int, pairs: Sequence[int], seed: int,
               verifier: Verifier | None = None, robot: str = "franka") -> list[DataProblem]:
    """Build pairs `pairs` of scene `scene` of `kind` (constant time in `scene`).

    Args:
        kind: scene kind.
        scene: index of the scene among those of its kind.
        pairs: the start/goal pairs wanted (0 = the generator's own).
        seed: dataset seed (>= 0).
        verifier: the judge of collision-free configurations (default: the Franka
            verifier; give the robot's own for another robot).
        robot: the robot (its scenes are the Franka's scaled by its reach,
            `manip.benchmarking.scenes.make_problems`).

    Returns:
        One problem per pair, in the order of `pairs`.
    """
    v = verifier or (default_verifier() if robot == "franka" else Verifier(robot))
    base = make_problems(kind, 1, scene_seed(seed, kind, scene), v, robot=robot)[0]
    out = []
    for pair in pairs:
        if pair == 0:
            start, goal = np.array(base.start), np.array(base.goal)
        else:
            rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(SCENE_KINDS.index(kind), scene, pair)))
            start = _random_free(v, base.world, rng, None)
            goal = _random_free(v, base.world, rng, start)
        out.append(DataProblem(problem_id(kind, scene, pair), kind, scene, pair, base.world, start, goal))
    return out
