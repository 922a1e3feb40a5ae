"""`CollisionState`: one state of a `CollisionChecker`'s robot and world, read-only.

The checker builds its tables (the robot's parts and sphere covers, the obstacles, the
broadphase tables, the motion-bound constants) and swaps new ones in at each edit. A
`CollisionState` is those tables of one moment, handed out whole (`CollisionChecker.state`):
the certificate of continuous motions (`collision.certify`), the clearance model of the
trajectory optimiser (`collision.clearance`) and the planners' validity questions
(`planning.validity`) read it through its fields and methods, never through the
checker's private attributes. Nothing in it changes after it is built: later edits of the
checker build a new state.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

if TYPE_CHECKING:
    from manip.collision.shapes import Obstacle
    from manip.collision.tables import SphereTable
    from manip.kinematics import Kinematics

__all__ = ["CollisionState"]


@dataclass(frozen=True, eq=False)
class CollisionState:
    """The tables of one state of a checker's robot and world (see the module docstring).

    Attributes:
        kinematics: the robot's `Kinematics`.
        parts: (G,) the robot's collision parts and attached objects (`collision.tables.Part`:
            name, joint, placement in the joint frame, coal geometry and hull, sphere cover).
        obstacles: (O,) the world's obstacles, in the world's order.
        obstacle_geometries: (O,) their coal geometries (in their own frames).
        obstacle_transforms: (O,) their coal placements in the base frame.
        padding: clearance [m] kept from the world.
        self_padding: clearance [m] kept between links.
        always_colliding: (part, obstacle) index pairs of parts fixed to the base that
            collide with an obstacle: when not empty, every configuration collides.
        fine: the fine sphere cover of every part (`collision.tables.SphereTable`: centres
            (S, 3) [m] in their joint frames, radii (S,) [m], joint (S,), part (S,)).
        motion_bounds: the robot-side constants of the certificate's motion bound.
        world_tables: the parts' broadphase tables against obstacles (`broadphase.world_candidates`).
        moving_world_parts: True when some part moves with a joint (else only
            `always_colliding` can hit the world).
        obstacle_tables: the obstacles' broadphase tables (shapes, poses, bounding balls).
        self_tables: the self pairs' broadphase tables (`broadphase.self_candidates`).
        self_pairs: (P, 2) the part pairs of `self_tables`, in its order.
        allowed_world: (G, O) bool, the (part, obstacle) pairs never checked (contacts allowed,
            `CollisionChecker.allowing`), or None.
        occupancy_maps: (obstacle index, tables) of the occupancy maps among the obstacles
            (`collision.occupancy`: bounded by their own kernels, not by `obstacle_tables`).
    """

    kinematics: Kinematics
    parts: tuple
    obstacles: tuple[Obstacle, ...]
    obstacle_geometries: tuple
    obstacle_transforms: tuple
    padding: float
    self_padding: float
    always_colliding: tuple[tuple[int, int], ...]
    fine: SphereTable
    motion_bounds: Any  # a `collision.certify.MotionBoundTables` (certify reads this state)
    world_tables: tuple
    moving_world_parts: bool
    obstacle_tables: tuple
    self_tables: tuple
    self_pairs: np.ndarray
    allowed_world: np.ndarray | None
    _collides: Callable[..., np.ndarray]
    _motion_free: Callable[[np.ndarray, np.ndarray, float], bool]
    _segments_free: Callable[[np.ndarray, np.ndarray, float], np.ndarray]
    _advance: Callable[[np.ndarray, np.ndarray, float], tuple[Any, int]]
    occupancy_maps: tuple = ()
    _collides_given: Callable[..., bool] | None = None

    @property
    def every_configuration_collides(self) -> bool:
        """True when a part fixed to the base collides with the world (`always_colliding`)."""
        return bool(self.always_colliding)

    def joint_transforms(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint frames R (N, J+1, 3, 3), p (N, J+1, 3) [m] of configurations Q (N, dof)."""
        return self.kinematics.joint_transforms(Q)

    def collides(self, Q: np.ndarray) -> np.ndarray:
        """(N,) bool: which configurations of Q (N, dof) collide (the checker's exact answer;
        no input checks)."""
        return self._collides(Q)

    def collides_given(self, R: np.ndarray, p: np.ndarray, kind: np.ndarray, i: np.ndarray, j: np.ndarray) -> bool:
        """True when the configuration with joint frames R (1, J+1, 3, 3), p (1, J+1, 3) [m]
        collides, given its broadphase candidates computed on these tables, in the order to try
        them: kind (T,) 0 = world (part i, obstacle j), 1 = self (parts i, j) (coal decides; no
        occupancy maps)."""
        return self._collides_given(R, p, kind, i, j)

    def motion_free(self, q0: np.ndarray, q1: np.ndarray, resolution: float) -> bool:
        """True when the straight motion q0 -> q1 (dof,) is free, checked every `resolution`
        [rad] (`CollisionChecker.motion_valid` without input checks)."""
        return self._motion_free(q0, q1, resolution)

    def segments_free(self, Q0: np.ndarray, Q1: np.ndarray, resolution: float) -> np.ndarray:
        """(M,) bool: `motion_free` of the segments Q0[m] -> Q1[m] (M, dof), checked together."""
        return self._segments_free(Q0, Q1, resolution)

    def advance(self, q0: np.ndarray, q1: np.ndarray, resolution: float) -> tuple[float | None, int]:
        """(t of the first colliding sample on q0 -> q1 or None, the number of intervals) from a
        collision-free q0 (its own sample is not checked; `CollisionChecker.first_collision`)."""
        return self._advance(q0, q1, resolution)
