"""Speed of `manip.sim`: the Franka with a cube, stepped headless through the World API.

    python benchmarks/sim.py [--seconds 20] [--repeats 3] [--video] [--web [--web-client]] [--write-md]

Scene: ground plane, Franka at the origin, a 5 cm 0.03 kg cube on the ground in front of
it. Each physics step (1/60 s, 9 MuJoCo substeps) the arm gets new position targets of a
smooth joint-space motion through `apply_action` (the wrapper work a controller causes) and
the cube pose and joint positions are read back. The process is pinned to one core.
Real-time factor = simulated time / wall time; the median of the repeats is reported.
`--web` adds the browser viewer's cost (`SimulationApp({"viewer": "web"})`, manip-robotics[viz]):
the same stepping while the World is streamed at 30 Hz of wall time, and the cost of one
streamed frame; `--web-client` keeps a headless chromium connected to it meanwhile.
`--write-md` replaces the `## Simulation` section of BENCHMARKS.md. Exit status 1 when the
real-time factor is below 20.
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import sys
import time
from pathlib import Path

import mujoco
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.report import cpu_model, replace_section  # noqa: E402
TARGET_RTF = 20.0


def machine() -> dict:
    cpu = cpu_model()
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(), "mujoco": mujoco.__version__,
            "numpy": np.__version__, "date": dt.datetime.now().strftime("%Y-%m-%d %H:%M"),
            "load": os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")}


def build():
    from manip.sim import DynamicCuboid, Franka, World, create_new_stage

    World.clear_instance()
    create_new_stage()
    world = World()
    world.scene.add_default_ground_plane()
    franka = world.scene.add(Franka("/World/Franka", name="franka"))
    cube = world.scene.add(DynamicCuboid("/World/cube", name="cube", position=[0.5, 0.0, 0.025], size=0.05,
                                         mass=0.03))
    world.reset()
    return world, franka, cube


def run_world(seconds: float, render: bool) -> float:
    """Wall time [s] of `seconds` of simulated time through the World API."""
    from manip.sim import ArticulationAction

    world, franka, cube = build()
    ctrl = franka.get_articulation_controller()
    home = franka.get_joint_positions()
    n = int(round(seconds / world.get_physics_dt()))
    amp = np.r_[0.4, 0.3, 0.3, 0.3, 0.5, 0.4, 0.6, 0.0, 0.0]
    t0 = time.perf_counter()
    for i in range(n):
        t = i * world.get_physics_dt()
        ctrl.apply_action(ArticulationAction(joint_positions=home + amp * np.sin(0.5 * np.pi * t)))
        world.step(render=render)
        cube.get_world_pose()
        franka.get_joint_positions()
    return time.perf_counter() - t0


def run_raw(seconds: float) -> float:
    """Wall time [s] of the same model stepped by bare `mujoco.mj_step` (no wrapper, no actions)."""
    world, _, _ = build()
    m, d = world.model, world.data
    n = int(round(seconds / world.get_physics_dt()))
    k = world.physics_substeps
    t0 = time.perf_counter()
    for _ in range(n):
        mujoco.mj_step(m, d, nstep=k)
    return time.perf_counter() - t0


WEB_RATE = 30.0  # [Hz] frames streamed per second of wall time


def run_world_web(seconds: float, client: bool) -> tuple[float, float, float, float, int]:
    """`run_world(seconds, render=True)` without a viewer, then with the web viewer streaming
    at WEB_RATE (paired runs, so both see the same machine load).

    Returns:
        (wall [s], CPU [s]) without the viewer, (wall [s], CPU [s]) with it (process CPU
        time: viser's server thread included), frames streamed.
    """
    import shutil
    import socket
    import subprocess
    import tempfile

    from manip.sim import SimulationApp

    c0 = time.process_time()
    wall_plain = run_world(seconds, True)
    cpu_plain = time.process_time() - c0
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    app = SimulationApp({"headless": False, "viewer": "web", "web_port": port, "web_rate": WEB_RATE,
                         "realtime": False})
    browser, profile = None, tempfile.TemporaryDirectory()
    try:
        build()  # compiles: the app starts serving
        chromium = shutil.which("chromium") or shutil.which("chromium-browser")
        if client and chromium:
            browser = subprocess.Popen(
                [chromium, "--headless", "--no-sandbox", "--disable-quic", "--no-first-run", "--use-angle=swiftshader",
                 "--enable-unsafe-swiftshader", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", f"--user-data-dir={profile.name}", "--window-size=800,600", app.viewer_url],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            deadline = time.monotonic() + 60
            while not app._web_server.get_clients() and time.monotonic() < deadline:
                time.sleep(0.2)
            time.sleep(3.0)  # the client receives the scene
        elif client:
            print("--web-client: no chromium found; streaming without a client", file=sys.stderr)
        c0 = time.process_time()
        wall = run_world(seconds, True)  # a new World: the app streams it with a new SimStream
        cpu = time.process_time() - c0
        return wall_plain, cpu_plain, wall, cpu, app._viewer.pushes - 1  # less the push on opening
    finally:
        app.close()
        if browser is not None:
            browser.terminate()
            browser.wait(timeout=30)
        profile.cleanup()


def run_video(seconds: float, path: Path) -> tuple[float, int]:
    world, franka, _ = build()
    world.start_recording(path, width=640, height=480, fps=30)
    n = int(round(seconds / world.get_physics_dt()))
    t0 = time.perf_counter()
    for _ in range(n):
        world.step(render=True)
    wall = time.perf_counter() - t0
    frames = world._recorder.frames
    world.stop_recording()
    return wall, frames


def table(res: dict) -> str:
    m = res["machine"]
    rows = [
        ("World.step(render=False) + apply_action + reads", f"{res['rtf_world']:.1f}x real time "
                                                           f"({res['ms_world']:.3f} ms per 1/60 s step)"),
        ("World.step(render=True), no viewer/recorder", f"{res['rtf_render']:.1f}x real time "
                                                       f"({res['ms_render']:.3f} ms per step)"),
        ("bare mujoco.mj_step, 9 substeps, same model", f"{res['rtf_raw']:.1f}x real time "
                                                        f"({res['ms_raw']:.3f} ms per step)"),
        ("wrapper overhead per step", f"{res['ms_world'] - res['ms_raw']:.3f} ms"),
    ]
    if "web_overhead" in res:
        client = "headless chromium connected" if res["web_client"] else "no browser connected"
        rows.append((f"World.step(render=True) streamed to the browser at {WEB_RATE:g} Hz ({client})",
                     f"{res['rtf_web']:.1f}x real time ({res['web_frames']} frames): wall time "
                     f"{100 * res['web_overhead']:+.0f} % (paired runs, median), CPU time {100 * res['web_cpu_overhead']:+.0f} %"))
        rows.append(("CPU per streamed frame (viser's server thread included)",
                     f"{res['web_ms_per_frame']:.2f} ms: {100 * res['web_realtime_share']:.1f} % of the wall time "
                     f"of a real-time run at {WEB_RATE:g} Hz"))
    if "video_ms_per_frame" in res:
        rows.append(("recording 640x480 MP4 at 30 fps (offscreen)",
                     f"{res['video_ms_per_frame']:.0f} ms per frame, {res['rtf_video']:.2f}x real time"))
    w = max(len(r[0]) for r in rows)
    lines = [
        f"Machine: {m['cpu']}, {m['cores']} cores (pinned to 1); Python {m['python']}, MuJoCo {m['mujoco']}, "
        f"NumPy {m['numpy']}; {m['date']}; load average at start {m['load']:.1f}",
        "",
        f"| {'measure'.ljust(w)} | result |",
        f"|{'-' * (w + 2)}|--------|",
    ]
    lines += [f"| {a.ljust(w)} | {b} |" for a, b in rows]
    return "\n".join(lines) + "\n"


def write_markdown(res: dict, args: argparse.Namespace, path: Path) -> None:
    section = (
        "## Simulation\n\n"
        f"`python benchmarks/sim.py --seconds {args.seconds:g} --repeats {args.repeats}"
        f"{' --video' if args.video else ''}{' --web' if args.web else ''}{' --web-client' if args.web_client else ''}"
        " --write-md` (Franka + 5 cm cube on the ground, physics_dt 1/60 s = "
        "9 MuJoCo substeps of 1.85 ms, smooth joint targets sent every step, median of the repeats; wall time "
        f"on a machine shared with other jobs). Target: >= {TARGET_RTF:g}x real time.\n\n"
        + table(res)
        + "\n"
    )
    replace_section(path, "## Simulation", section)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="simulated seconds per run")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--video", action="store_true", help="also time MP4 recording (needs EGL/OSMesa)")
    parser.add_argument("--web", action="store_true", help="also time the browser viewer (manip-robotics[viz])")
    parser.add_argument("--web-client", action="store_true", help="with --web: keep headless chromium connected")
    parser.add_argument("--write-md", action="store_true", help="update the Simulation section of BENCHMARKS.md")
    args = parser.parse_args(argv)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    res: dict = {"machine": machine()}
    steps = args.seconds * 60
    for key, fn in (("world", lambda: run_world(args.seconds, False)), ("render", lambda: run_world(args.seconds, True)),
                    ("raw", lambda: run_raw(args.seconds))):
        wall = float(np.median([fn() for _ in range(args.repeats)]))
        res[f"rtf_{key}"] = args.seconds / wall
        res[f"ms_{key}"] = 1e3 * wall / steps
        print(f"{key:7s} {res[f'rtf_{key}']:.1f}x real time, {res[f'ms_{key}']:.3f} ms/step", flush=True)
    if args.web:
        runs = np.array([run_world_web(args.seconds, args.web_client) for _ in range(args.repeats)])
        wall_plain, cpu_plain, wall, cpu, frames = runs.T
        res.update(rtf_web=args.seconds / float(np.median(wall)), web_frames=int(np.median(frames)),
                   web_overhead=float(np.median(wall / wall_plain - 1.0)),
                   web_cpu_overhead=float(np.median(cpu / cpu_plain - 1.0)),
                   web_ms_per_frame=1e3 * float(np.median((cpu - cpu_plain) / frames)), web_client=args.web_client)
        res["web_realtime_share"] = WEB_RATE * res["web_ms_per_frame"] / 1e3
        print(f"web     {res['rtf_web']:.1f}x real time, wall {100 * res['web_overhead']:+.0f} %, "
              f"CPU {100 * res['web_cpu_overhead']:+.0f} %, {res['web_ms_per_frame']:.2f} ms CPU per frame", flush=True)
    if args.video:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            wall, frames = run_video(min(args.seconds, 5.0), Path(tmp) / "bench.mp4")
        res["video_ms_per_frame"] = 1e3 * wall / max(frames, 1)
        res["rtf_video"] = min(args.seconds, 5.0) / wall
    print(table(res))
    if args.write_md:
        write_markdown(res, args, ROOT / "BENCHMARKS.md")
    return 0 if res["rtf_world"] >= TARGET_RTF else 1


if __name__ == "__main__":
    sys.exit(main())
