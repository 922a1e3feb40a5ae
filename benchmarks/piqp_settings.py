#!/usr/bin/env python3
"""PIQP's settings and KKT solvers on the trajectory optimiser's QPs (issue 33, round eleven).

    python benchmarks/piqp_settings.py [--limit-per-scene 3] [--load QPS | --save QPS] [--repeat 2]

Records the QPs of the first N valid MotionBenchMaker problems per scene (`qp_record.record`: joint
and pose goals, seed 0; or loads them, `--save`/`--load` a pickle), then solves each with every
variant below, the variants alternating QP by QP (`time.thread_time`: setup and solve apart), and
prints per variant: the CPU per QP against PIQP's defaults at the tolerance the optimiser used
before round eleven (1e-6), the interior-point iterations, the QPs not solved, and how far the
control points are from that reference's (median and max, rad). Take the bench lock for the times.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import piqp
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: the QP's first variables: the free control points, dof * (N - 3) = 7 * 13 (the Panda, 16 pieces)
CONTROL = 91

#: name -> (solver class, settings); "eps" is the absolute tolerance (the relative ones a tenth of it)
VARIANTS = {
    "reference (eps 1e-6)": ("sparse", {"eps": 1e-6}),
    "eps 1e-5": ("sparse", {"eps": 1e-5}),
    "eps 1e-4": ("sparse", {"eps": 1e-4}),
    "scale cost": ("sparse", {"eps": 1e-6, "preconditioner_scale_cost": True}),
    "3 Ruiz passes": ("sparse", {"eps": 1e-6, "preconditioner_iter": 3}),
    "scale cost, 3 passes, eps 1e-4": ("sparse", {"eps": 1e-4, "preconditioner_scale_cost": True,
                                                  "preconditioner_iter": 3}),
    "scale cost, 1 pass, eps 3e-4 (round eleven)": ("sparse", {"eps": 3e-4, "preconditioner_scale_cost": True,
                                                               "preconditioner_iter": 1}),
    "sparse_ldlt_cond": ("sparse", {"eps": 1e-6, "kkt_solver": piqp.KKTSolver.sparse_ldlt_cond}),
    "sparse_multistage": ("sparse", {"eps": 1e-6, "kkt_solver": piqp.KKTSolver.sparse_multistage}),
    "DenseSolver": ("dense", {"eps": 1e-6}),
}


def solve(qp: dict, kind: str, settings: dict) -> tuple[np.ndarray | None, int, float, float]:
    """(solution or None, iterations, setup CPU [s], solve CPU [s]) of one recorded QP."""
    solver = piqp.SparseSolver() if kind == "sparse" else piqp.DenseSolver()
    s = solver.settings
    s.verbose = False
    for key, value in settings.items():
        if key == "eps":
            s.eps_abs = s.eps_duality_gap_abs = value
            s.eps_rel = s.eps_duality_gap_rel = value * 0.1
        else:
            setattr(s, key, value)
    P, G, A = qp["P"], qp["G"], qp["A"]
    if kind == "dense":  # the conversion is counted: the optimiser assembles CSC
        t = time.thread_time()
        P, G, A = P.toarray(), G.toarray(), None if A is None else A.toarray()
    else:
        t = time.thread_time()
    solver.setup(P, qp["q"], A, qp["b"], G, None, qp["h"], qp["lb"], qp["ub"])
    t1 = time.thread_time()
    status = solver.solve()
    t2 = time.thread_time()
    x = solver.result.x.copy() if status == piqp.PIQP_SOLVED else None
    return x, solver.result.info.iter, t1 - t, t2 - t1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit-per-scene", type=int, default=3)
    ap.add_argument("--load", default=None, help="a pickle of QPs saved by --save")
    ap.add_argument("--save", default=None, help="write the recorded QPs here")
    ap.add_argument("--repeat", type=int, default=2, help="passes over the QPs")
    args = ap.parse_args(argv)
    if args.load:
        with open(args.load, "rb") as f:
            qps = pickle.load(f)
    else:
        import qp_record

        qps = qp_record.record(args.limit_per_scene)
        for qp in qps:
            qp["G"] = sp.csc_matrix(qp.pop("G_T").T)
        if args.save:
            with open(args.save, "wb") as f:
                pickle.dump(qps, f)
    names = list(VARIANTS)
    cpu = dict.fromkeys(names, 0.0)
    setup = dict.fromkeys(names, 0.0)
    iters = dict.fromkeys(names, 0)
    failed = dict.fromkeys(names, 0)
    dx: dict = {n: [] for n in names}
    for _ in range(args.repeat):
        for qp in qps:
            ref = None
            for n in names:
                x, it, ts, tv = solve(qp, *VARIANTS[n])
                cpu[n] += ts + tv
                setup[n] += ts
                iters[n] += it
                failed[n] += x is None
                if n == names[0]:
                    ref = x
                elif x is not None and ref is not None:
                    dx[n].append(float(np.max(np.abs(x[:CONTROL] - ref[:CONTROL]))))
    count = args.repeat * len(qps)
    print(f"{len(qps)} QPs x {args.repeat}; CPU per QP against '{names[0]}'")
    print("| variant | CPU ratio | setup / solve [us] | iterations | not solved | control points from the reference "
          "(median / max) [rad] |")
    print("|---|---|---|---|---|---|")
    for n in names:
        d = dx[n]
        print(f"| {n} | {cpu[n] / cpu[names[0]]:.3f} | {1e6 * setup[n] / count:.0f} / "
              f"{1e6 * (cpu[n] - setup[n]) / count:.0f} | {iters[n] / count:.2f} | {failed[n]} | "
              f"{np.median(d) if d else 0:.1e} / {max(d) if d else 0:.1e} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
