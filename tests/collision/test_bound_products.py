"""The certificate's compiled table products (`manip.collision.bound_products`) equal numpy's."""

from __future__ import annotations

import numpy as np

from manip.collision.bound_products import contract, pair_motion, rows_times


def test_products_equal_numpys():
    rng = np.random.default_rng(0)
    S, G, K = 7, 5, 4
    D, T, A = rng.random((S, K)), rng.random((G, K, K)), rng.random((S, G, K))
    np.testing.assert_allclose(contract(D, T), np.einsum("sm,gkm->sgk", D, T), rtol=1e-12)
    np.testing.assert_allclose(rows_times(A, D), np.einsum("sgk,sk->sg", A, D), rtol=1e-12)
    a, b = np.array([0, 1, 3]), np.array([2, 4, 4])
    ma, mb = rng.random((3, K)), rng.random((3, K))
    rel = A[:, a] * ma[None] + A[:, b] * mb[None]
    np.testing.assert_allclose(pair_motion(A, a, b, ma, mb, D), np.einsum("spk,sk->sp", rel, D), rtol=1e-12)
