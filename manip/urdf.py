"""Reading a robot's URDF and SRDF: the joint tree, limits, disabled collision pairs.

What manip needs from a robot description beyond what Pinocchio builds: the SRDF's
`<disable_collisions link1= link2=/>` pairs (for manip's own self-collision checker), the
pairs of adjacent links (the fallback when there is no SRDF), the movable joints of the
chain between two links, and a URDF whose continuous joints are revolute joints (the
planner works with bounded joints; Pinocchio would build continuous joints as unbounded
cos/sin joints with two coordinates).
"""

from __future__ import annotations

import logging
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from manip import package_uri
from manip.errors import RobotConfigError, UnknownNameError

logger = logging.getLogger(__name__)

#: Joint types a robot's arm may use (others are fixed or unsupported).
MOVABLE_TYPES = ("revolute", "continuous", "prismatic")
#: Range [rad] given to a continuous joint: one full turn either way.
CONTINUOUS_RANGE = (-2.0 * math.pi, 2.0 * math.pi)


@dataclass(frozen=True)
class UrdfJoint:
    """One URDF joint.

    Attributes:
        name: joint name.
        type: "revolute", "continuous", "prismatic", "fixed", ...
        parent: parent link name.
        child: child link name.
        lower, upper: position limits [rad or m] (CONTINUOUS_RANGE for continuous joints;
            None when the URDF gives none).
        velocity: velocity limit [rad/s or m/s] (None when the URDF gives none).
        effort: effort limit [N m or N] (None when the URDF gives none).
    """

    name: str
    type: str
    parent: str
    child: str
    lower: float | None
    upper: float | None
    velocity: float | None
    effort: float | None


class UrdfTree:
    """The links and joints of a URDF file.

    Args:
        path: the .urdf file.

    Raises:
        RobotConfigError: the file is not a readable URDF.
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        try:
            self.root = ET.parse(self.path).getroot()
        except (OSError, ET.ParseError) as exc:
            raise RobotConfigError(f"{self.path}: not a readable URDF ({exc})") from exc
        if self.root.tag != "robot":
            raise RobotConfigError(f"{self.path}: the root element is <{self.root.tag}>, expected <robot>")
        if self.root.find("link") is None:
            raise RobotConfigError(f"{self.path}: no <link> element: not a URDF (an SRDF given as the URDF?)")
        self.name = self.root.get("name", self.path.stem)
        self.links: list[str] = [el.get("name") for el in self.root.findall("link")]
        self._collision = {el.get("name"): el.find("collision") is not None for el in self.root.findall("link")}
        self.joints: dict[str, UrdfJoint] = {}
        for el in self.root.findall("joint"):
            limit = el.find("limit")

            def attr(key: str, el_=limit) -> float | None:
                return None if el_ is None or el_.get(key) is None else float(el_.get(key))

            jtype = el.get("type", "")
            lower, upper = (CONTINUOUS_RANGE if jtype == "continuous" else (attr("lower"), attr("upper")))
            self.joints[el.get("name")] = UrdfJoint(
                el.get("name"), jtype, el.find("parent").get("link"), el.find("child").get("link"),
                lower, upper, attr("velocity"), attr("effort"))
        self.parent_joint: dict[str, UrdfJoint] = {j.child: j for j in self.joints.values()}
        roots = [name for name in self.links if name not in self.parent_joint]
        if len(roots) != 1:
            raise RobotConfigError(f"{self.path}: expected one root link, found {roots}")
        self.root_link = roots[0]

    def collision_meshes(self) -> list[tuple[str, str]]:
        """(link, mesh filename as written) of every `<collision>` mesh."""
        return [(el.get("name"), mesh.get("filename", "")) for el in self.root.findall("link")
                for mesh in el.findall("collision/geometry/mesh")]

    def missing_meshes(self, package_dirs: list[str] | None = None) -> list[str]:
        """The collision mesh filenames that resolve to no file as ROS tools resolve them
        (`manip.package_uri.resolve`); `package_dirs`: more folders D in which
        `package://PKG/rest` is also looked for as `D/PKG/rest` (as Pinocchio does)."""
        missing = []
        for _, uri in self.collision_meshes():
            try:
                package_uri.resolve(uri, self.path)
                continue
            except RobotConfigError:
                pass
            found = uri.startswith(package_uri.PACKAGE) and any(
                Path(f"{d}/{uri[len(package_uri.PACKAGE):]}").is_file() for d in package_dirs or [])
            if not found and uri not in missing:
                missing.append(uri)
        return missing

    def has_collision(self, link: str) -> bool:
        """Whether the link has `<collision>` geometry."""
        return self._collision.get(link, False)

    def check_link(self, link: str, what: str = "link") -> None:
        """Raise UnknownNameError if `link` is not a link of the URDF (`what` names it in the message)."""
        if link not in self._collision:
            raise UnknownNameError(what if what == "link" else f"link ({what})", link, self.links)

    def ancestors(self, link: str) -> list[str]:
        """The links from `link` up to the root (both included)."""
        self.check_link(link)
        out = [link]
        while out[-1] in self.parent_joint:
            out.append(self.parent_joint[out[-1]].parent)
        return out

    def chain_joints(self, base_link: str, tip_link: str) -> list[UrdfJoint]:
        """The movable joints from `base_link` to `tip_link`, base first.

        Raises:
            UnknownNameError: unknown link.
            RobotConfigError: `tip_link` is not below `base_link`.
        """
        self.check_link(base_link)
        up = self.ancestors(tip_link)
        if base_link not in up:
            raise RobotConfigError(f"{self.path}: link '{tip_link}' is not below '{base_link}'")
        links = up[: up.index(base_link)]
        joints = [self.parent_joint[link] for link in reversed(links)]
        return [j for j in joints if j.type in MOVABLE_TYPES]

    def deepest_link(self, base_link: str) -> str:
        """The link below `base_link` with the most movable joints above it (ties: the one
        with the most links above it, then URDF order): the tool frame of a serial arm."""
        best, best_n = base_link, (0, 0)
        for link in self.links:
            up = self.ancestors(link)
            if base_link in up and link != base_link:
                n = (len(self.chain_joints(base_link, link)), len(up))
                if n > best_n:
                    best, best_n = link, n
        return best

    def adjacent_pairs(self) -> list[tuple[str, str]]:
        """Pairs of links with collision geometry that touch through a joint: each such link
        with its nearest ancestor that has collision geometry (links without geometry in
        between are skipped, as MoveIt's setup assistant does)."""
        pairs = []
        for link in self.links:
            if not self.has_collision(link):
                continue
            for up in self.ancestors(link)[1:]:
                if self.has_collision(up):
                    pairs.append((up, link))
                    break
        return pairs

    def bounded_xml(self) -> str:
        """The URDF text with every continuous joint made revolute within CONTINUOUS_RANGE."""
        root = ET.fromstring(ET.tostring(self.root))
        for el in root.findall("joint"):
            if el.get("type") == "continuous":
                el.set("type", "revolute")
                limit = el.find("limit")
                if limit is None:
                    limit = ET.SubElement(el, "limit", effort="0", velocity="0")
                limit.set("lower", repr(CONTINUOUS_RANGE[0]))
                limit.set("upper", repr(CONTINUOUS_RANGE[1]))
        return ET.tostring(root, encoding="unicode")


def build_model(urdf_path: str | Path) -> pin.Model:
    """The Pinocchio model of a URDF, continuous joints made revolute (`UrdfTree.bounded_xml`)."""
    return pin.buildModelFromXML(UrdfTree(urdf_path).bounded_xml())


def _srdf_root(path: str | Path) -> ET.Element:
    """The root element of an SRDF file.

    Raises:
        RobotConfigError: unreadable, not rooted at <robot>, or a URDF (it has <link> elements).
    """
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise RobotConfigError(f"{path}: not a readable SRDF ({exc})") from exc
    if root.tag != "robot":
        raise RobotConfigError(f"{path}: the root element is <{root.tag}>, expected <robot>")
    if root.find("link") is not None:
        raise RobotConfigError(f"{path}: has <link> elements: a URDF, not an SRDF (URDF given as the SRDF?)")
    return root


def srdf_disabled_pairs(path: str | Path) -> list[tuple[str, str]]:
    """The `<disable_collisions link1= link2=/>` pairs of an SRDF file.

    Raises:
        RobotConfigError: the file is not a readable SRDF or a pair lacks a link name.
    """
    pairs = []
    for el in _srdf_root(path).iter("disable_collisions"):
        a, b = el.get("link1"), el.get("link2")
        if not a or not b:
            raise RobotConfigError(f"{path}: <disable_collisions> needs link1 and link2; got {el.attrib}")
        pairs.append((a, b))
    return pairs


def srdf_group_states(path: str | Path) -> dict[str, dict[str, float]]:
    """The SRDF's named configurations: {state name: {joint name: value}}, in file order.

    Raises:
        RobotConfigError: the file is not a readable SRDF or a joint value is not a number.
    """
    states: dict[str, dict[str, float]] = {}
    for el in _srdf_root(path).iter("group_state"):
        values = {}
        for j in el.findall("joint"):
            try:
                v = [float(x) for x in (j.get("value") or "").split()]
            except ValueError:
                v = []
            if not v:
                raise RobotConfigError(f"{path}: group_state '{el.get('name')}': joint {j.attrib} needs a "
                                       "numeric value")
            if len(v) == 1:  # a multi-dof joint (a floating base's "x y z qx qy qz qw") is never an arm joint
                values[j.get("name")] = v[0]
        states[el.get("name")] = values
    return states


def srdf_virtual_joints(path: str | Path) -> list[str]:
    """The names of an SRDF's `<virtual_joint>`s (a floating base's joint: not in the URDF)."""
    return [el.get("name") for el in _srdf_root(path).iter("virtual_joint") if el.get("name")]


def srdf_end_effector_links(path: str | Path) -> list[str]:
    """The `parent_link` of each `<end_effector>` of an SRDF, in file order."""
    return [el.get("parent_link") for el in _srdf_root(path).iter("end_effector") if el.get("parent_link")]


def disabled_pairs(tree: UrdfTree, srdf_path: Path | None, extra: list[tuple[str, str]],
                   disable_adjacent: bool = False) -> tuple[tuple[str, str], ...]:
    """The link pairs the self-collision checker skips: the SRDF's pairs (or, without an
    SRDF or with an SRDF that lists no pair, the adjacent links, with a log line), the
    adjacent links if asked, and `extra`.

    Raises:
        UnknownNameError: a pair names a link the URDF does not have (the links are listed).

    Returns:
        Sorted unique pairs, each (a, b) with a < b.
    """
    pairs = list(extra)
    listed = srdf_disabled_pairs(srdf_path) if srdf_path is not None else []
    pairs += listed
    if srdf_path is None or not listed or disable_adjacent:
        adjacent = tree.adjacent_pairs()
        if srdf_path is None:
            logger.info("%s: no SRDF; the %d pairs of adjacent links are not checked for self-collision, "
                        "all other pairs are", tree.path.name, len(adjacent))
        elif not listed and not disable_adjacent:
            logger.warning("%s lists no <disable_collisions> pair; the %d pairs of adjacent links are not checked "
                           "for self-collision, all other pairs are (a robot.yaml says so with collision: "
                           "disable_adjacent_links: true)", Path(srdf_path).name, len(adjacent))
        pairs += adjacent
    known = set(tree.links)
    unknown = sorted({name for pair in pairs for name in pair} - known)
    if unknown:  # a misspelt link: the pair meant to be disabled would be checked, unnoticed
        source = f"<disable_collisions> of {srdf_path}" if srdf_path is not None else "disabled pairs"
        raise UnknownNameError(f"link ({source}; not in {tree.path.name})", unknown[0], tree.links)
    return tuple(sorted({tuple(sorted(p)) for p in pairs if p[0] in known and p[1] in known and p[0] != p[1]}))


def default_ee_link(tree: UrdfTree, base: str, srdf_path: Path | None) -> str:
    """The tool link when none is given: the `parent_link` of the SRDF's first end effector
    below `base`, else `tree.deepest_link(base)`; the choice is logged as a warning."""
    if srdf_path is not None:
        for link in srdf_end_effector_links(srdf_path):
            if link in tree.links and link != base and base in tree.ancestors(link):
                logger.warning("%s: ee_link not given; using '%s' (the SRDF's end_effector parent_link)",
                               tree.path.name, link)
                return link
    ee = tree.deepest_link(base)
    logger.warning("%s: ee_link not given; using '%s' (the deepest link)", tree.path.name, ee)
    return ee


def within_limits(values: list[float], joints: list[UrdfJoint], lower: np.ndarray, upper: np.ndarray,
                  tol: float = 1e-9) -> np.ndarray | None:
    """`values` (one per joint) within [lower, upper], a revolute or continuous joint's value
    turned by whole turns (2 pi: the same pose) where that brings it within; None if a value
    cannot be brought within its limits.

    Args:
        values: (dof,) joint values [rad or m].
        joints: the joints (their types say which may turn).
        lower, upper: (dof,) limits [rad or m].
        tol: slack on the limits.
    """
    out = []
    for value, joint, lo, hi in zip(values, joints, lower, upper):
        if joint.type in ("revolute", "continuous") and not lo - tol <= value <= hi + tol:
            value = value + 2.0 * math.pi * math.ceil((lo - tol - value) / (2.0 * math.pi))
        if not lo - tol <= value <= hi + tol:
            return None
        out.append(min(max(value, lo), hi))
    return np.array(out, dtype=float)


#: The free-flyer joint's name in Pinocchio's convention: SRDF states may set it (not a URDF joint).
_FREE_FLYER = "root_joint"


def default_configuration(given: np.ndarray | str | None, spec: list[UrdfJoint], lower: np.ndarray, upper: np.ndarray,
                           srdf_path: Path | None, where: str, urdf_joints: set[str] = frozenset()) -> np.ndarray:
    """The default configuration of `manip.robot_config.config_from_urdf` (see its docstring):
    `given`, else the SRDF's first group_state of the arm joints within the limits, else the middle
    of the limits. `urdf_joints`: the URDF's joint names (a state naming others has a misspelt joint)."""
    n = len(spec)
    names = [j.name for j in spec]
    states = srdf_group_states(srdf_path) if srdf_path is not None and (given is None or isinstance(given, str)) else {}

    def fit(state: dict[str, float]) -> np.ndarray | None:
        return within_limits([state[j] for j in names], spec, lower, upper)

    if isinstance(given, str):
        if given not in states:
            raise UnknownNameError("group_state (default_joint_positions)", given, states)
        missing = [j for j in names if j not in states[given]]
        if missing:
            raise RobotConfigError(f"group_state '{given}' does not set the arm joints {missing}")
        q = fit(states[given])
        if q is None:
            raise RobotConfigError(f"group_state '{given}' is outside the joint limits "
                                   f"[{lower.tolist()}, {upper.tolist()}]: {states[given]}")
        return q
    if given is None:
        known = set(urdf_joints) | {_FREE_FLYER} | (set(srdf_virtual_joints(srdf_path)) if states else set())
        problems = []   # why each state setting arm joints was not used
        partial = []
        for state, values in states.items():
            unset = [j for j in names if j not in values]
            if len(unset) == len(names):
                continue  # a state of another group (the hand, ...)
            unknown = [j for j in values if urdf_joints and j not in known]
            if unset and unknown:  # a misspelt arm joint: never fall back silently
                raise RobotConfigError(
                    f"{srdf_path}: group_state '{state}' sets no value for the arm joint(s) {unset} and names "
                    f"joint(s) {unknown} that the URDF ({where}) does not have (misspelt?); the arm joints: "
                    f"{', '.join(names)}. Fix the SRDF, or give default_joint_positions.")
            if unset:
                partial.append(f"'{state}' sets no value for {unset}")
                continue
            q = fit(values)
            if q is not None:
                if unknown:
                    logger.warning("%s: the SRDF's group_state '%s' names joints not in the URDF (ignored): %s",
                                   where, state, unknown)
                if not np.array_equal(q, [values[j] for j in names]):
                    logger.warning("%s: default configuration: the SRDF's group_state '%s' turned by whole "
                                   "turns into the joint limits: %s", where, state, np.round(q, 6).tolist())
                return q
            out = [f"{j} = {values[j]} outside [{lo:g}, {hi:g}]" for j, lo, hi in zip(names, lower, upper)
                   if within_limits([values[j]], [spec[names.index(j)]], np.array([lo]), np.array([hi])) is None]
            problems.append(f"group_state '{state}': {'; '.join(out)}")
        if problems:  # a value typo (15.7 for 1.57) must not become the middle of the limits
            raise RobotConfigError(
                f"{srdf_path}: no group_state gives a default configuration within the joint limits: "
                f"{'; '.join(problems)}. Fix the SRDF, or give default_joint_positions.")
        if partial:
            logger.warning("%s: no default configuration: no SRDF group_state sets every arm joint (%s); using "
                           "the middle of the limits", where, "; ".join(partial))
        else:
            logger.warning("%s: no default configuration (%s); using the middle of the limits", where,
                           "the SRDF has no group_state of the arm joints" if srdf_path is not None else "no SRDF")
        return (lower + upper) / 2.0
    try:
        default = np.asarray(given, dtype=float)
    except (TypeError, ValueError) as exc:
        raise RobotConfigError(f"default_joint_positions must be {n} numbers [rad] or a group_state name; "
                               f"got {given!r}") from exc
    if default.shape != (n,) or not np.all(np.isfinite(default)) or np.any(default < lower) \
            or np.any(default > upper):
        raise RobotConfigError(f"default_joint_positions must be {n} finite values within the limits "
                               f"[{lower.tolist()}, {upper.tolist()}]; got {given!r}")
    return default.copy()
