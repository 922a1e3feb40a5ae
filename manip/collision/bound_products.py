"""The products of `certify.certify_path`'s motion-bound tables, as compiled loops.

They were numpy matrix products; numpy's BLAS runs a product of this size on every core, and on
a 2-core machine shared with other work the second thread cost 10-20 x the product itself
(BENCHMARKS.md, "Two arms"). A loop on one core takes well under a millisecond.
"""

from __future__ import annotations

import numpy as np

from manip.jit import kernel


@kernel
def contract(D: np.ndarray, T: np.ndarray) -> np.ndarray:
    """out[s, g, k] = sum_m D[s, m] T[g, k, m]: D (S, M), T (G, K, M) -> (S, G, K)."""
    S, M = D.shape
    G, K = T.shape[0], T.shape[1]
    out = np.zeros((S, G, K))
    for s in range(S):
        for g in range(G):
            for k in range(K):
                acc = 0.0
                for m in range(M):
                    acc += D[s, m] * T[g, k, m]
                out[s, g, k] = acc
    return out


@kernel
def rows_times(A: np.ndarray, D: np.ndarray) -> np.ndarray:
    """out[s, g] = sum_k A[s, g, k] D[s, k]: A (S, G, K), D (S, K) -> (S, G)."""
    S, G, K = A.shape
    out = np.zeros((S, G))
    for s in range(S):
        for g in range(G):
            acc = 0.0
            for k in range(K):
                acc += A[s, g, k] * D[s, k]
            out[s, g] = acc
    return out


@kernel
def pair_motion(rho_seg: np.ndarray, a: np.ndarray, b: np.ndarray, mask_a: np.ndarray, mask_b: np.ndarray,
                 D: np.ndarray) -> np.ndarray:
    """out[s, k] = sum_j (rho_seg[s, a[k], j] mask_a[k, j] + rho_seg[s, b[k], j] mask_b[k, j]) D[s, j]:
    the motion bound (S, P) of each part pair (a[k], b[k]) relative to each other on each segment."""
    S, K = D.shape
    P = a.shape[0]
    out = np.zeros((S, P))
    for s in range(S):
        for k in range(P):
            acc = 0.0
            for j in range(K):
                acc += (rho_seg[s, a[k], j] * mask_a[k, j] + rho_seg[s, b[k], j] * mask_b[k, j]) * D[s, j]
            out[s, k] = acc
    return out
