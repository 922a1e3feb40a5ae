"""The compiled projection and certificate of `OrientationConstraint` (`constraints.tilt_kernels`)
against the generic NumPy ones they replace."""

from __future__ import annotations

import numpy as np
import pytest

from manip import OrientationConstraint
from manip.constraints import certify, project


class _Generic(OrientationConstraint):
    """An OrientationConstraint without its compiled projection and certificate (the generic NumPy ones run)."""

    def project_alone(self, kinematics, q, max_steps, damping):
        return NotImplemented

    def hold_alone(self, kinematics, Q0, Q1, slack):
        return NotImplemented


@pytest.mark.parametrize("axis", [(0, 0, 1), (1, 0, 0), (0, -1, 0)])
def test_compiled_projection_and_certificate_agree_with_the_generic_ones(franka_kinematics, axis):
    """`OrientationConstraint.project_alone` / `hold_alone` (compiled) against the generic
    Gauss-Newton and bisection: the same projections, the same verdict on every segment
    (short ones that hold, long ones that leave the cone between their ends), with and without slack."""
    kin = franka_kinematics
    fast = OrientationConstraint(axis, (0, 0, 1), 0.1, link="panda_hand")
    slow = _Generic(axis, (0, 0, 1), 0.1, link="panda_hand")
    rng = np.random.default_rng(7)
    ends = []
    while len(ends) < 40:
        q = rng.uniform(kin.lower, kin.upper)
        a, b = project([fast], kin, q), project([slow], kin, q)
        assert (a is None) == (b is None)
        if a is not None:
            np.testing.assert_allclose(a, b, atol=1e-9)
            ends.append(a)
    Q0 = np.array(ends)
    verdicts = []
    for spread in (0.05, 0.3, 0.8):
        Q1 = [project([fast], kin, q + rng.normal(0.0, spread, kin.dof)) for q in Q0]
        keep = [i for i, q in enumerate(Q1) if q is not None]
        A, B = Q0[keep], np.array([Q1[i] for i in keep])
        for slack in (None, np.full(len(A), 0.01)):
            ok_f, bad_f, _, _ = certify._hold(fast, kin, A, B, slack)
            ok_s, bad_s, _, _ = certify._hold(slow, kin, A, B, slack)
            np.testing.assert_array_equal(ok_f, ok_s)
            np.testing.assert_array_equal(bad_f, bad_s)
            verdicts.append(ok_f)
    verdicts = np.concatenate(verdicts)
    assert verdicts.any() and not verdicts.all()  # both kinds of segment were met
