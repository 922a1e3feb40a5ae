"""Contacts as PhysX makes them: friction combined by the materials' combine modes, stiff
contact response. Applied to the World's model when the stage compiles (`compile_stage`).

Friction. MuJoCo combines the friction of two touching geoms of equal `priority` by taking the
larger; PhysX combines the two materials' coefficients by their combine modes, `average` by
default (a 0.05 box on a 0.5 ramp slides with 0.275, not 0.5). For every pair of bodies where
that changes a coefficient, the body pair is excluded from MuJoCo's dynamic contacts and each
of its geom pairs becomes an explicit MuJoCo `<pair>` with the PhysX coefficient, every other
contact parameter mixed as MuJoCo mixes it (condim max, margin and gap summed, solref/solimp
weighted by solmix) and MuJoCo's collision filters kept (contype/conaffinity, same or
parent-child body, two static bodies, the model's own excludes). A geom of higher `priority`
keeps deciding alone, as in MuJoCo (the Franka's finger pads do: their grasp is as authored).
Combine modes: "average", "min", "multiply", "max"; of two different modes the later in that
list applies (PhysX's precedence). A shape with no physics material has PhysX's default
friction, 0.5 (`PHYSX_DEFAULT_FRICTION`); a robot's geoms keep their model's friction with
mode "average". MuJoCo uses one sliding coefficient: the dynamic friction.

Stiffness. Every contact parameter left at MuJoCo's default (solref time constant 0.02 s,
solimp (0.9, 0.95, 0.001)) is made stiff: a time constant of two integration substeps (the
current ones), the stiffest MuJoCo allows, and impedance `CONTACT_SOLIMP`; resting objects then sink < 0.01 mm
instead of 0.1-0.4 mm. What an impact penetrates is bounded by how far a body travels between
two contact checks, which `manip.sim.core.substeps` keeps below 2 mm.
"""

from __future__ import annotations

import itertools
from collections import defaultdict

import mujoco
import numpy as np

from manip.errors import InvalidInputError

#: PhysX's combine modes, in its order of precedence (of two modes, the later one applies).
COMBINE_MODES = ("average", "min", "multiply", "max")
#: Friction of a surface with no physics material (PhysX's default material, static = dynamic).
PHYSX_DEFAULT_FRICTION = 0.5
#: Time constant of contacts left at MuJoCo's default [s]: below any substep, so that MuJoCo
#: raises it to two substeps (its `refsafe` rule), the stiffest it allows, whatever the
#: substep (`manip.sim.core.substeps` shortens it during fast motion).
CONTACT_TIMECONST = 1e-5
#: Contact impedance (MuJoCo solimp dmin, dmax, width) of contacts left at MuJoCo's default.
CONTACT_SOLIMP = (0.99, 0.999, 0.001)
_DEFAULT_SOLREF = (0.02, 1.0)
_DEFAULT_SOLIMP = (0.9, 0.95, 0.001)


#: Margin [m] of an explicit pair switched off (`switch_pairs`): no geom comes within reach.
PAIR_OFF_MARGIN = -1e9


def switch_pairs(model: mujoco.MjModel, geom: int) -> None:
    """After `geom`'s contype/conaffinity changed in the compiled model: its explicit pairs, which
    MuJoCo collides whatever the filters, follow them: a pair whose two geoms both collide gets
    its margin back (the geoms' margins summed, as built), any other is put out of reach
    (`PAIR_OFF_MARGIN`)."""
    for i in np.flatnonzero((model.pair_geom1 == geom) | (model.pair_geom2 == geom)):
        g1, g2 = model.pair_geom1[i], model.pair_geom2[i]
        on = all(model.geom_contype[g] or model.geom_conaffinity[g] for g in (g1, g2))
        model.pair_margin[i] = model.geom_margin[g1] + model.geom_margin[g2] if on else PAIR_OFF_MARGIN


def check_combine_mode(mode: str, what: str = "friction_combine_mode") -> str:
    """`mode` if it is one of COMBINE_MODES, else InvalidInputError naming `what`."""
    if mode not in COMBINE_MODES:
        raise InvalidInputError(f"{what} must be one of {', '.join(COMBINE_MODES)}; got {mode!r}")
    return mode


def combine(f1: float, mode1: str, f2: float, mode2: str) -> float:
    """The coefficient PhysX uses for two materials' coefficients `f1`, `f2` and combine modes."""
    mode = max(mode1, mode2, key=COMBINE_MODES.index)
    if mode == "average":
        return 0.5 * (f1 + f2)
    if mode == "min":
        return min(f1, f2)
    if mode == "multiply":
        return f1 * f2
    return max(f1, f2)


def stiffen_contacts(spec: mujoco.MjSpec) -> None:
    """Give every geom whose solref/solimp are MuJoCo's defaults the stiff contact response
    (time constant CONTACT_TIMECONST, which MuJoCo raises to two substeps, and CONTACT_SOLIMP)."""
    for g in spec.geoms:
        if np.allclose(g.solref, _DEFAULT_SOLREF):
            g.solref = [CONTACT_TIMECONST, 1.0]
        if np.allclose(g.solimp[:3], _DEFAULT_SOLIMP):
            imp = list(g.solimp)
            imp[:3] = CONTACT_SOLIMP
            g.solimp = imp


def compile_with_physx_friction(spec: mujoco.MjSpec, modes: dict[str, str]) -> mujoco.MjModel:
    """Compile `spec` with PhysX's friction combining (see the module docstring).

    Args:
        spec: the assembled World.
        modes: {geom name: combine mode} of the geoms with a physics material; others "average".

    Returns:
        The compiled model (compiled twice when explicit pairs were needed).
    """
    for k, g in enumerate(spec.geoms):  # explicit pairs name their geoms
        if not g.name:
            g.name = f"__manip_geom_{k}"
    model = spec.compile()
    excluded = {frozenset((e.bodyname1, e.bodyname2)) for e in spec.excludes}
    explicit = {frozenset((p.geomname1, p.geomname2)) for p in spec.pairs}
    overrides = _body_pairs_to_override(model, modes, excluded, explicit)
    if not overrides:
        return model
    excludes = [(model.body(b1).name, model.body(b2).name) for b1, b2 in overrides]
    pairs = [_pair(model, g1, g2, modes) for geom_pairs in overrides.values() for g1, g2 in geom_pairs]
    del model  # freed before the second compile: one model at a time in memory
    for b1, b2 in excludes:
        spec.add_exclude(bodyname1=b1, bodyname2=b2)
    for pair in pairs:
        spec.add_pair(**pair)
    return spec.compile()


def _filtered(model: mujoco.MjModel, b1: int, b2: int, moving: set[int]) -> bool:
    """MuJoCo's filters of dynamic contacts between bodies b1 and b2: the same or
    parent-child weld groups (the world excepted), or two weld groups without DoF (`moving`:
    the weld groups with DoF; mocap bodies have none)."""
    w1, w2 = model.body_weldid[b1], model.body_weldid[b2]
    if w1 == w2:
        return True
    p1, p2 = model.body_weldid[model.body_parentid[w1]], model.body_weldid[model.body_parentid[w2]]
    if (p1 == w2 and w2 != 0) or (p2 == w1 and w1 != 0):
        return True
    return w1 not in moving and w2 not in moving


def _body_pairs_to_override(model, modes, excluded, explicit) -> dict[tuple[int, int], list[tuple[int, int]]]:
    """{(body1, body2): [(geom1, geom2), ...]} of the body pairs whose contacts need explicit
    pairs: some compatible geom pair of equal priority whose PhysX friction differs from
    MuJoCo's maximum."""
    by_body: dict[int, list[int]] = defaultdict(list)
    for g in range(model.ngeom):
        if model.geom_contype[g] or model.geom_conaffinity[g]:
            by_body[int(model.geom_bodyid[g])].append(g)
    moving = {int(model.body_weldid[b]) for b in range(model.nbody) if model.body_dofnum[b] > 0}
    out = {}
    for b1, b2 in itertools.combinations(sorted(by_body), 2):
        n1, n2 = model.body(b1).name, model.body(b2).name
        if frozenset((n1, n2)) in excluded or _filtered(model, b1, b2, moving):
            continue
        pairs, differs = [], False
        for g1 in by_body[b1]:
            for g2 in by_body[b2]:
                if not ((model.geom_contype[g1] & model.geom_conaffinity[g2])
                        or (model.geom_contype[g2] & model.geom_conaffinity[g1])):
                    continue
                if frozenset((model.geom(g1).name, model.geom(g2).name)) in explicit:
                    continue
                pairs.append((g1, g2))
                if model.geom_priority[g1] == model.geom_priority[g2]:
                    f1, f2 = model.geom_friction[g1, 0], model.geom_friction[g2, 0]
                    m1 = modes.get(model.geom(g1).name, "average")
                    m2 = modes.get(model.geom(g2).name, "average")
                    differs |= not np.isclose(combine(f1, m1, f2, m2), max(f1, f2))
        if differs:
            out[(b1, b2)] = pairs
    return out


def _pair(model: mujoco.MjModel, g1: int, g2: int, modes: dict[str, str]) -> dict:
    """`MjSpec.add_pair` arguments for geoms g1, g2: the parameters MuJoCo would mix, friction PhysX's."""
    n1, n2 = model.geom(g1).name, model.geom(g2).name
    pr1, pr2 = model.geom_priority[g1], model.geom_priority[g2]
    f1, f2 = model.geom_friction[g1], model.geom_friction[g2]
    if pr1 != pr2:
        w = g1 if pr1 > pr2 else g2
        condim = int(model.geom_condim[w])
        fr = model.geom_friction[w]
        solref, solimp = model.geom_solref[w], model.geom_solimp[w]
    else:
        condim = int(max(model.geom_condim[g1], model.geom_condim[g2]))
        slide = combine(f1[0], modes.get(n1, "average"), f2[0], modes.get(n2, "average"))
        fr = np.array([slide, max(f1[1], f2[1]), max(f1[2], f2[2])])
        s1, s2 = model.geom_solmix[g1], model.geom_solmix[g2]
        w1 = 0.5 if s1 + s2 < mujoco.mjMINVAL else s1 / (s1 + s2)
        r1, r2 = model.geom_solref[g1], model.geom_solref[g2]
        solref = np.minimum(r1, r2) if (r1[0] <= 0 or r2[0] <= 0) else w1 * r1 + (1 - w1) * r2
        solimp = w1 * model.geom_solimp[g1] + (1 - w1) * model.geom_solimp[g2]
    return dict(geomname1=n1, geomname2=n2, condim=condim, friction=[fr[0], fr[0], fr[1], fr[2], fr[2]],
                solref=list(solref), solimp=list(solimp), margin=float(model.geom_margin[g1] + model.geom_margin[g2]),
                gap=float(model.geom_gap[g1] + model.geom_gap[g2]))
