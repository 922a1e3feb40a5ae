"""The dataset on disk: a folder of Parquet files, one row per planned problem.

    DIR/_manifest.json          the generation settings (a rerun must use the same)
    DIR/part-000000.parquet     rows flushed together (a row group each)
    DIR/part-000001.parquet ...

Every flush writes a new part file (to a hidden temporary name, then renamed), so an
interrupted run leaves only complete files and a rerun skips the problem ids already in
them. `read_dataset(DIR)` reads the whole folder in dataset order; `pandas.read_parquet(DIR)`
reads it in the order the rows were written (order of completion); files starting with "_"
or "." are ignored by pyarrow.

Columns: problem_id, scene_id, kind, scene, pair (ints), seed (the planning seed), robot,
world (JSON, cuRobo's format), start and goal ((dof,) lists [rad]), status, message (the
result's: empty, why a plan failed, or `planning.context.SAFETY_NET`), success, verified
(independent check of the trajectory), verify_reasons, source, plan_time [s],
timings (JSON: seconds per stage), motion_time [s], dt [s], times ((T,) [s]), positions,
velocities, accelerations ((T, dof) nested lists [rad, rad/s, rad/s^2]), path ((K, dof)
waypoints [rad]); dof = 7 for the Franka. Trajectory columns are null for failed plans.
"""

from __future__ import annotations

import json
import logging
import os
from pathlib import Path
from typing import Any

import numpy as np

from manip.datagen.job import Verdict
from manip.datagen.problems import DataProblem
from manip.errors import InvalidInputError
from manip.planning.result import PlanResult

log = logging.getLogger(__name__)

MANIFEST = "_manifest.json"
#: 2: the message column, and search_iterations among the settings.
FORMAT_VERSION = 2


def _pa() -> Any:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError as exc:
        raise InvalidInputError('writing a dataset needs pyarrow: pip install "manip-robotics[datagen]"') from exc
    return pa, pq


def _schema() -> Any:
    pa, _ = _pa()
    vec = pa.list_(pa.float64())
    mat = pa.list_(vec)
    return pa.schema([
        ("problem_id", pa.string()), ("scene_id", pa.string()), ("kind", pa.string()), ("scene", pa.int64()),
        ("pair", pa.int64()), ("seed", pa.int64()), ("robot", pa.string()), ("world", pa.string()),
        ("start", vec), ("goal", vec), ("status", pa.string()), ("message", pa.string()),
        ("success", pa.bool_()), ("verified", pa.bool_()),
        ("verify_reasons", pa.list_(pa.string())), ("source", pa.string()), ("plan_time", pa.float64()),
        ("timings", pa.string()), ("motion_time", pa.float64()), ("dt", pa.float64()), ("times", vec),
        ("positions", mat), ("velocities", mat), ("accelerations", mat), ("path", mat),
    ])


def make_row(problem: DataProblem, seed: int, robot: str, result: PlanResult, verdict: Verdict) -> dict[str, Any]:
    """One dataset row (a dict of the columns) of a planned problem."""
    traj = result.trajectory

    def arr(a: np.ndarray | None) -> list | None:
        return None if a is None else np.asarray(a).tolist()

    return {
        "problem_id": problem.id, "scene_id": problem.scene_id, "kind": problem.kind, "scene": problem.scene,
        "pair": problem.pair, "seed": seed, "robot": robot, "world": json.dumps(problem.world, sort_keys=True),
        "start": arr(problem.start), "goal": arr(problem.goal), "status": result.status.value,
        "message": result.message,
        "success": bool(result.success), "verified": verdict.verified, "verify_reasons": list(verdict.reasons),
        "source": result.source, "plan_time": float(result.plan_time), "timings": json.dumps(result.timings),
        "motion_time": float(result.motion_time), "dt": None if traj is None else float(traj.dt),
        "times": arr(None if traj is None else traj.times),
        "positions": arr(None if traj is None else traj.positions),
        "velocities": arr(None if traj is None else traj.velocities),
        "accelerations": arr(None if traj is None else traj.accelerations),
        "path": arr(result.path),
    }


def create_folder(out: str | Path) -> Path:
    """`out` as a Path, created (with its parents) if missing.

    Raises:
        InvalidInputError: `out` cannot be created (a file is in the way, no permission, ...).
    """
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InvalidInputError(f"cannot use {out} as the dataset folder: {exc.strerror or exc}") from exc
    return out


def open_folder(out: str | Path, settings: dict[str, Any]) -> Path:
    """Create `out` with a manifest of `settings`, or check that its manifest has the same ones.

    Raises:
        InvalidInputError: `out` holds a dataset made with other settings (they are listed),
            cannot be created or written, or its manifest is unreadable.
    """
    out = Path(out)
    manifest = out / MANIFEST
    settings = {"format": FORMAT_VERSION, **settings}
    try:
        out.mkdir(parents=True, exist_ok=True)
        old = json.loads(manifest.read_text()) if manifest.exists() else None
        if old is None:
            manifest.write_text(json.dumps(settings, indent=1, sort_keys=True) + "\n")
    except OSError as exc:
        raise InvalidInputError(f"cannot use {out} as the dataset folder: {exc.strerror or exc}") from exc
    except json.JSONDecodeError as exc:
        raise InvalidInputError(f"{manifest} is not a manip.datagen manifest ({exc}); use another --out") from exc
    if old is not None:
        if not isinstance(old, dict):
            raise InvalidInputError(f"{manifest} is not a manip.datagen manifest; use another --out")
        # a setting missing on one side is None (the default) there: a setting added later
        # (`dt`) keeps older datasets valid while it is left at its default
        diff = {k: (old.get(k), settings.get(k)) for k in sorted(set(old) | set(settings))
                if old.get(k) != settings.get(k)}
        if diff:
            raise InvalidInputError(
                f"{out} holds a dataset made with other settings (setting: (in {out}, now)): {diff}; "
                "use another --out or the same settings"
            )
    return out


def finished_ids(out: str | Path) -> set[str]:
    """The problem ids already written in `out` (empty when there is no part file)."""
    _, pq = _pa()
    ids: set[str] = set()
    for part in sorted(Path(out).glob("part-*.parquet")):
        ids.update(pq.read_table(part, columns=["problem_id"]).column("problem_id").to_pylist())
    return ids


class PartWriter:
    """Buffers rows and writes them as a new part file every `rows_per_part` rows (and on `flush`)."""

    def __init__(self, out: Path, rows_per_part: int = 256):
        self.out = out
        self.rows_per_part = rows_per_part
        self.rows: list[dict[str, Any]] = []
        self.written = 0
        existing = sorted(out.glob("part-*.parquet"))
        self._next = 1 + max((int(p.stem.split("-")[1]) for p in existing), default=-1)

    def add(self, row: dict[str, Any]) -> None:
        """Buffer one row; write a part file when the buffer is full."""
        self.rows.append(row)
        if len(self.rows) >= self.rows_per_part:
            self.flush()

    def flush(self) -> None:
        """Write the buffered rows as one part file (atomically: a temporary name, then a rename)."""
        if not self.rows:
            return
        pa, pq = _pa()
        table = pa.Table.from_pylist(self.rows, schema=_schema())
        name = f"part-{self._next:06d}.parquet"
        tmp = self.out / f".{name}.tmp"
        pq.write_table(table, tmp, compression="zstd")
        # the buffer is emptied before the rename: a Ctrl-C after it (the caller's `finally`
        # flushes again) can no longer write these rows a second time
        n, self.rows = len(self.rows), []
        os.replace(tmp, self.out / name)
        self._next += 1
        self.written += n
        log.info("wrote %d rows to %s", n, name)


def read_dataset(out: str | Path, columns: list[str] | None = None) -> Any:
    """The dataset in `out` as a pandas DataFrame, one row per problem, in dataset order.

    The rows are those of `pandas.read_parquet(out)` (which gives them in the order they
    were written: order of completion, which varies with the workers and across resumed
    runs), sorted into the dataset's own order: scene by scene as `--kinds` alternates
    (table-000000, shelf-000000, ..., table-000001, ...), pair by pair within a scene. The
    index is 0..n-1.

    Args:
        out: the dataset folder.
        columns: columns to read (None: all).

    Returns:
        A DataFrame with one row per problem; list columns hold NumPy arrays of arrays
        (`np.stack(df.positions[i])` is the (T, 7) positions of row i).

    Raises:
        InvalidInputError: pandas missing, no part file in `out`, or an unknown column.
    """
    try:
        import pandas as pd
    except ImportError as exc:
        raise InvalidInputError('reading a dataset needs pandas: pip install "manip-robotics[datagen]"') from exc
    if not any(Path(out).glob("part-*.parquet")):
        raise InvalidInputError(f"no part-*.parquet file in {out}")
    names = _schema().names
    if columns is not None:
        columns = list(columns)
        unknown = [c for c in columns if c not in names]
        if unknown:
            raise InvalidInputError(f"unknown dataset column(s) {unknown}; valid: {names}")
    read = None if columns is None else list(dict.fromkeys([*columns, "problem_id"]))
    df = pd.read_parquet(out, columns=read)
    try:
        kinds = json.loads((Path(out) / MANIFEST).read_text())["kinds"]
    except (OSError, ValueError, KeyError, TypeError):
        kinds = sorted({pid.rsplit("-", 2)[0] for pid in df["problem_id"]})
    rank = {k: i for i, k in enumerate(kinds)}

    def order(pid: str) -> tuple[int, int, int]:
        kind, scene, pair = pid.rsplit("-", 2)
        return int(scene), rank.get(kind, len(rank)), int(pair)

    keys = [order(pid) for pid in df["problem_id"].tolist()]
    df = df.iloc[sorted(range(len(keys)), key=keys.__getitem__)].reset_index(drop=True)
    return df if columns is None else df[columns]
