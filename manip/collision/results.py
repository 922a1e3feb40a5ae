"""What `CollisionChecker` returns: `Contact`, `CollisionReport`, `DistanceReport`, `PathCheck`,
and the `AttachedObject` it carries."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, NamedTuple

from manip.collision.shapes import Obstacle
from manip.pose import Pose

ContactKind = Literal["world", "self", "attached_world", "attached_self"]


@dataclass(frozen=True)
class Contact:
    """One colliding (or closest) pair.

    Attributes:
        kind: "world" (robot link vs obstacle), "self" (link vs link), "attached_world"
            (attached object vs obstacle) or "attached_self" (attached object vs link).
        a: the robot link or attached object.
        b: the obstacle or the other link.
        distance: signed distance [m] between the two (negative = penetration depth,
            approximate for meshes; see `CollisionChecker.distance`).
    """

    kind: ContactKind
    a: str
    b: str
    distance: float


@dataclass(frozen=True)
class CollisionReport:
    """What collides in one configuration (padding included).

    Attributes:
        in_collision: True if any pair collides.
        contacts: every colliding pair, deepest first.
    """

    in_collision: bool
    contacts: tuple[Contact, ...]

    @property
    def world_collision(self) -> bool:
        """True if the robot or an attached object touches an obstacle."""
        return any(c.kind in ("world", "attached_world") for c in self.contacts)

    @property
    def self_collision(self) -> bool:
        """True if two links (or an attached object and a link) touch."""
        return any(c.kind in ("self", "attached_self") for c in self.contacts)


@dataclass(frozen=True)
class DistanceReport:
    """Signed distances [m] of one configuration (without padding).

    Attributes:
        distance: min(world_distance, self_distance).
        world_distance: smallest distance between the robot (and attached objects) and
            the obstacles; +inf with no obstacles.
        self_distance: smallest distance over the enabled self-collision pairs.
        closest: the pair achieving `distance` (None if there is none).
    """

    distance: float
    world_distance: float
    self_distance: float
    closest: Contact | None


class PathCheck(NamedTuple):
    """Result of `CollisionChecker.path_valid`."""

    valid: bool
    first_invalid_segment: int | None


@dataclass(frozen=True, eq=False)
class AttachedObject:
    """An obstacle carried by a link.

    Attributes:
        obstacle: the shape (its `pose` is where it was when attached, base frame).
        link: the carrying link.
        pose_in_link: the shape's pose in the link frame.
        allowed_links: links never checked against it (those rigidly attached to the same
            joint as `link`, plus any given by the caller).
    """

    obstacle: Obstacle
    link: str
    pose_in_link: Pose
    allowed_links: tuple[str, ...]
