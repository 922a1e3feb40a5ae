"""Self-collision pairs proved clear over the whole joint range, so the checks can skip them.

A pair of robot parts whose relative placement depends on at most `MAX_PROOF_JOINTS`
revolute joints (e.g. a wrist link and a flange link one joint further) is checked for
self-collision at every configuration although many such pairs can never touch. This
module proves it, per pair, over the box of those joints' limits (a revolute joint with a
range of 2 pi or more only needs one turn: the placement is 2 pi-periodic):

- The relative placement of parts a and b (carried by joints j_a and j_b) depends only on
  the joints that move one of them but not both (the symmetric difference of their chains).
- Moving those joints by at most h_k each (an L-inf cell around a configuration) moves any
  point x of a part by at most sum_k h_k D_k, where D_k bounds the distance of x from joint
  k's axis: for the part's own joint, from its sphere cover (which holds the geometry);
  for a joint further up, |x - o_k| (o_k: the origin of joint k, on its axis) by the
  placements between the two joints plus the part's extent. So if coal's exact distance
  of the pair at the cell's centre is d, the pair keeps at least d - sum_k h_k D_k over the
  whole cell. Ball by ball (`ball_slack`) the bound is tighter: two balls of the covers
  are at least max(d, their clearance) apart at the centre and each moves by at most
  sum_k h_k rho_k, rho_k its own distance from joint k's axis (the balls near the other
  part are usually near the axes); the cell keeps the larger of the two bounds.
- Cells are split (all joints halved) until every cell is proved to keep at least
  `PROOF_CLEARANCE`, or a centre comes within `PROOF_CLEARANCE` (the pair can touch: it
  stays checked), or `PROOF_QUERIES` distance queries are spent (not proved: it stays
  checked).

A proved pair gets a lower bound of its distance over every configuration; the checker
skips it while its self padding is below that bound. Nothing is sampled or assumed: a pair
is skipped only when coal could never report it in collision. Results are cached on disk
beside the sphere covers (`manip.collision.robot_geometry`).
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
from collections.abc import Sequence

import coal
import numpy as np

from manip.disk_cache import DiskCache
from manip.kinematics import Kinematics

logger = logging.getLogger(__name__)

#: Pairs whose relative placement depends on more joints than this are not tried.
MAX_PROOF_JOINTS = 2
#: [m] a proved pair keeps at least this distance at every configuration.
PROOF_CLEARANCE = 1e-3
#: Exact distance queries spent on one pair before giving up (the pair stays checked).
PROOF_QUERIES = 20000
#: [rad] the widest starting cell along each joint.
_START_WIDTH = 0.5
_VERSION = "proof-v2"
#: Results of this process, by cache key (the disk cache may be off).
_MEMORY: dict[str, float | None] = {}


def relative_joints(kinematics: Kinematics, joint_a: int, joint_b: int) -> list[int]:
    """Joints (indices of `Kinematics.joint_transforms`, 1..J) that move one of the two joint
    frames relative to the other: those on one frame's chain to the base but not both."""
    parent = [0] + [s.parent for s in kinematics.joint_specs]

    def chain(j: int) -> set[int]:
        out = set()
        while j > 0:
            out.add(j)
            j = parent[j]
        return out

    return sorted(chain(joint_a) ^ chain(joint_b))


def joint_reach(kinematics: Kinematics, part, k: int) -> float:
    """Bound [m] of the distance from joint k's axis of the points of `part` (k on its chain):
    for the part's own joint, the largest distance of its balls from the axis; for a joint
    further up, |x - o_k| <= the placements between the two joints + the part's extent."""
    specs = kinematics.joint_specs
    C, r = np.asarray(part.centres, dtype=float), np.asarray(part.radii, dtype=float)
    if r.size == 0:
        return 0.0
    if k == part.joint:
        axis = specs[k - 1].axis
        return float(np.max(np.linalg.norm(C - np.outer(C @ axis, axis), axis=1) + r))
    total, j = float(np.max(np.linalg.norm(C, axis=1) + r)), part.joint
    while j != k:
        total += float(np.linalg.norm(specs[j - 1].p_placement))
        j = specs[j - 1].parent
    return total


def _key(digests: Sequence[str], a: int, b: int, kinematics: Kinematics, rel: list[int], lo: np.ndarray,
         hi: np.ndarray, base: np.ndarray) -> str:
    h = hashlib.sha1(_VERSION.encode() + f"/{PROOF_CLEARANCE!r}/{PROOF_QUERIES}/{_START_WIDTH!r}".encode())
    h.update(f"{digests[a]}/{digests[b]}".encode())
    for s in kinematics.joint_specs:  # the whole chain: the placements between the parts
        h.update(s.R_placement.tobytes() + s.p_placement.tobytes() + s.axis.tobytes() + bytes([s.revolute]))
    h.update(np.asarray(rel, dtype=np.int64).tobytes() + lo.tobytes() + hi.tobytes() + base.tobytes())
    return h.hexdigest()


def prove_pair_clear(parts: Sequence, a: int, b: int, kinematics: Kinematics, *, digests: Sequence[str],
                     cache: DiskCache | None = None) -> float | None:
    """A lower bound [m] (>= PROOF_CLEARANCE) of the distance between parts a and b over
    every configuration within the joint limits, or None when it cannot be proved.

    Args:
        parts: the robot's parts (`RobotPart`: geometry, joint, placement R/p in the joint
            frame, sphere cover in the joint frame).
        a, b: indices into `parts`.
        kinematics: the robot's `Kinematics` (joint chain, limits).
        digests: one string per part identifying its geometry, placement and cover (the
            key of the on-disk cache, with the joint chain and limits).
        cache: the on-disk cache (None: no cache).
    """
    pa, pb = parts[a], parts[b]
    rel = relative_joints(kinematics, pa.joint, pb.joint)
    specs = kinematics.joint_specs
    if not rel or len(rel) > MAX_PROOF_JOINTS or not all(specs[k - 1].revolute for k in rel):
        return None
    qidx = np.array([specs[k - 1].q_index for k in rel], dtype=np.int64)
    lo = kinematics.lower[qidx].astype(float)
    hi = kinematics.upper[qidx].astype(float)
    turn = hi - lo >= 2.0 * math.pi
    hi = np.where(turn, lo + 2.0 * math.pi, hi)
    base = np.clip(np.zeros(kinematics.dof), kinematics.lower, kinematics.upper)
    chain_a = set(relative_joints(kinematics, pa.joint, 0))
    # speed bound per joint: the part it moves (a joint moves exactly one of the two)
    L = np.array([joint_reach(kinematics, pa if k in chain_a else pb, k) for k in rel])
    key = _key(digests, a, b, kinematics, rel, lo, hi, base)
    if key in _MEMORY:
        return _MEMORY[key]
    _MEMORY[key] = bound = _cached_or_proved(key, cache, pa, pb, kinematics, qidx, rel, lo, hi, L, base)
    return bound


def _cached_or_proved(key: str, cache: DiskCache | None, pa, pb, kinematics: Kinematics, qidx: np.ndarray,
                      rel: list[int], lo: np.ndarray, hi: np.ndarray, L: np.ndarray, base: np.ndarray) -> float | None:
    """The proof's result from the disk cache, else computed (and written to the cache)."""
    name = f"selfpair-{key}.json"
    file = cache.find(name) if cache is not None else None
    if file is not None:
        try:
            bound = json.loads(file.read_text())["bound"]
            return None if bound is None else float(bound)
        except (OSError, ValueError, KeyError):  # a corrupt entry is recomputed
            pass
    bound = _subdivide(pa, pb, kinematics, qidx, rel, lo, hi, L, base)
    if cache is not None:
        cache.write(name, lambda path: path.write_text(json.dumps({"bound": bound})))
    return bound


def ball_slack(kinematics: Kinematics, pa, pb, rel: list[int], R: np.ndarray, p: np.ndarray, H: np.ndarray,
                L: np.ndarray, d: np.ndarray) -> np.ndarray:
    """(M,) a lower bound [m] of the pair's distance over each of M cells, ball by ball.

    A point x in ball i of one part and y in ball j of the other are at least
    max(d, D_ij) apart at the cell's centre (d: the pair's exact distance, D_ij: the balls'
    clearance), and each moves by at most sum_k h_k rho_k over the cell, rho_k bounding the
    ball's distance from joint k's axis (at the centre, plus how far the joints below k
    can move the ball within the cell). Near balls usually lie close to the joints' axes,
    so this is far tighter than the part-wide bound for long links.

    Args:
        R, p: joint frames (M, J+1, 3, 3), (M, J+1, 3) at the cells' centres.
        H: (M, n) the cells' half widths along the joints `rel`; L: (n,) part-wide reaches.
        d: (M,) the exact distances at the centres [m].
    """
    specs = kinematics.joint_specs
    chains = {k: set(relative_joints(kinematics, k, 0)) for k in rel}

    def moves(part) -> tuple[np.ndarray, np.ndarray]:
        """Ball centres (M, K, 3) at the centres and their motion bounds (M, K)."""
        C, r = np.asarray(part.centres, dtype=float), np.asarray(part.radii, dtype=float)
        X = np.einsum("mij,kj->mki", R[:, part.joint], C) + p[:, part.joint][:, None, :]
        out = np.zeros(X.shape[:2])
        mine = set(relative_joints(kinematics, part.joint, 0))
        for t, k in enumerate(rel):
            if k not in mine:
                continue
            axis = np.einsum("mij,j->mi", R[:, k], specs[k - 1].axis)
            v = X - p[:, k][:, None, :]
            rho = np.linalg.norm(v - np.einsum("mki,mi->mk", v, axis)[:, :, None] * axis[:, None, :], axis=2) + r[None]
            below = [u for u, m in enumerate(rel) if m != k and m in mine and k in chains[m]]
            extra = H[:, below] @ L[below] if below else np.zeros(H.shape[0])
            out += H[:, t][:, None] * (rho + extra[:, None])
        return X, out

    Xa, Ma = moves(pa)
    Xb, Mb = moves(pb)
    ra, rb = np.asarray(pa.radii, dtype=float), np.asarray(pb.radii, dtype=float)
    D = np.linalg.norm(Xa[:, :, None, :] - Xb[:, None, :, :], axis=3) - ra[None, :, None] - rb[None, None, :]
    return (np.maximum(d[:, None, None], D) - Ma[:, :, None] - Mb[:, None, :]).min(axis=(1, 2))


def _subdivide(pa, pb, kinematics: Kinematics, qidx: np.ndarray, rel: list[int], lo: np.ndarray, hi: np.ndarray,
               L: np.ndarray, base: np.ndarray) -> float | None:
    """The proof of `prove_pair_clear`: cells refined level by level (deterministic)."""
    n = qidx.size
    counts = np.maximum(1, np.ceil((hi - lo) / _START_WIDTH).astype(np.int64))
    axes = [lo[k] + (np.arange(counts[k]) + 0.5) * (hi[k] - lo[k]) / counts[k] for k in range(n)]
    C = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n)
    H = np.broadcast_to(0.5 * (hi - lo) / counts, C.shape).copy()
    request = coal.DistanceRequest()
    result = coal.DistanceResult()
    queries, bound = 0, math.inf
    while C.shape[0]:
        if queries + C.shape[0] > PROOF_QUERIES:
            return None
        Q = np.tile(base, (C.shape[0], 1))
        Q[:, qidx] = C
        R, p = kinematics.joint_transforms(Q)
        d = np.empty(C.shape[0])
        for i in range(C.shape[0]):
            tfs = []
            for part in (pa, pb):
                Rj, pj = R[i, part.joint], p[i, part.joint]
                tfs.append(coal.Transform3s(Rj @ part.R, pj + Rj @ part.p))
            result.clear()
            d[i] = coal.distance(pa.geometry, tfs[0], pb.geometry, tfs[1], request, result)
        queries += C.shape[0]
        if np.any(d <= PROOF_CLEARANCE):
            return None  # the pair comes within the clearance: it stays checked
        slack = np.maximum(d - H @ L, np.concatenate([
            ball_slack(kinematics, pa, pb, rel, R[s:s + 256], p[s:s + 256], H[s:s + 256], L, d[s:s + 256])
            for s in range(0, C.shape[0], 256)]))
        done = slack > PROOF_CLEARANCE
        if done.any():
            bound = min(bound, float(slack[done].min()))
        C, H = C[~done], H[~done] / 2.0
        if C.shape[0]:
            # every cell splits into 2^n children (each joint halved)
            signs = np.array(np.meshgrid(*[[-1.0, 1.0]] * n, indexing="ij")).reshape(n, -1).T  # (2^n, n)
            C = (C[:, None, :] + signs[None] * H[:, None, :]).reshape(-1, n)
            H = np.repeat(H, signs.shape[0], axis=0)
    return bound
