"""What a large mesh obstacle costs: reading it, adding it to a planner's world, moving it, and
its decimated solid (issue 35, item 5).

Each case runs in a fresh process (its peak memory is its own): a 1e6-triangle height field
(a 2 m x 2 m terrain scan), given as arrays or read from a binary STL file. Run under the
benchmark lock, nothing else running:

    flock /tmp/s10/bench.lock python benchmarks/mesh_obstacles.py
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def terrain(n: int) -> tuple[np.ndarray, np.ndarray]:
    """An n x n height field (2 n^2 triangles) 2 m across, 0.3 m below the robot's base."""
    x, y = np.meshgrid(np.linspace(-1, 1, n + 1), np.linspace(-1, 1, n + 1))
    z = 0.05 * np.sin(5 * x) * np.cos(5 * y)
    V = np.c_[x.ravel() + 0.5, y.ravel(), z.ravel() - 0.3]
    i = np.arange(n)[:, None] * (n + 1) + np.arange(n)[None]
    a, b, c, d = i, i + 1, i + n + 1, i + n + 2
    F = np.r_[np.c_[a.ravel(), b.ravel(), d.ravel()], np.c_[a.ravel(), d.ravel(), c.ravel()]]
    return V, F


def write_binary_stl(path: Path, V: np.ndarray, F: np.ndarray) -> None:
    rec = np.zeros(len(F), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["v"] = V[F]
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + np.uint32(len(F)).tobytes())
        rec.tofile(f)


def _rss() -> tuple[float, float]:
    """(current, peak) resident memory of this process [MB]."""
    fields = {}
    with open("/proc/self/status") as f:
        for line in f:
            parts = line.split()
            if len(parts) > 1:
                fields[parts[0].rstrip(":")] = parts[1]
    return int(fields["VmRSS"]) / 1024, int(fields["VmHWM"]) / 1024


def run_case(case: str, n: int, stl: str) -> dict:
    """One case in this process: the time and memory of each stage."""
    import logging

    logging.disable(logging.WARNING)
    from manip import MotionGenerator
    from manip.collision.shapes import Mesh, _load_mesh_file

    mg = MotionGenerator("franka")
    q0 = mg.default_joint_positions
    mg.check_collision(q0)
    V, F = terrain(n)
    out: dict = {"case": case, "triangles": int(len(F))}
    base = _rss()[0]

    def stage(name: str, fn):
        t = time.perf_counter()
        value = fn()
        out[name] = {"s": round(time.perf_counter() - t, 3), "rss_mb": round(_rss()[0] - base, 1)}
        return value

    if case == "arrays":
        mesh = stage("mesh", lambda: Mesh("scan", vertices=V, faces=F))
    elif case == "stl":
        mesh = stage("mesh", lambda: Mesh("scan", file_path=stl))
    elif case == "stl_coal_loader":   # the reader before this change: coal's loader, one triangle at a time
        import coal

        def coal_read():
            bvh = coal.MeshLoader().load(stl, np.ones(3))
            Vc = np.array(bvh.vertices(), dtype=float).reshape(-1, 3)
            Fc = np.array([[t[0], t[1], t[2]] for t in (bvh.tri_indices(i) for i in range(bvh.num_tris))])
            return Mesh("scan", vertices=Vc, faces=Fc)
        mesh = stage("mesh", coal_read)
    elif case == "solid_check":   # the watertightness check and normals of a closed mesh (a decimated one)
        coarse = Mesh("scan", vertices=V, faces=F).decimated(0.01)
        out["solid_triangles"] = int(len(coarse.faces))
        mesh = stage("mesh", lambda: Mesh("scan", vertices=coarse.vertices, faces=coarse.faces, solid=True))
    elif case.startswith("decimated_"):
        cell = float(case.split("_")[1])
        mesh = stage("mesh", lambda: Mesh("scan", vertices=V, faces=F).decimated(cell))
        out["decimated_triangles"] = int(len(mesh.faces))
    else:
        raise SystemExit(f"unknown case {case}")
    del _load_mesh_file
    stage("add_obstacle", lambda: mg.add_obstacle(mesh))
    stage("update_obstacle_pose", lambda: mg.update_obstacle_pose("scan", [0.0, 0.0, -0.01]))
    stage("check_collision", lambda: mg.check_collision(q0))
    out["peak_mb"] = round(_rss()[1], 1)
    out["base_mb"] = round(base, 1)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=707, help="height field resolution (2 n^2 triangles)")
    parser.add_argument("--cases", default="arrays,stl,stl_coal_loader,decimated_0.02,decimated_0.01,solid_check")
    parser.add_argument("--case", help=argparse.SUPPRESS)
    parser.add_argument("--stl", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.case:
        print(json.dumps(run_case(args.case, args.n, args.stl)))
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "scan.stl"
        write_binary_stl(stl, *terrain(args.n))
        for case in args.cases.split(","):
            r = subprocess.run([sys.executable, __file__, "--case", case, "--n", str(args.n), "--stl", str(stl)],
                               capture_output=True, text=True, check=False)
            if r.returncode:
                print(case, "failed:", r.stderr[-2000:])
                return 1
            print(r.stdout.strip().splitlines()[-1])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
