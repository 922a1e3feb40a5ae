"""Dataset generation: seeded scenes, planned and verified trajectories, Parquet files.

    python -m manip.datagen --scenes 100 --problems-per-scene 10 --out data/ [--workers K] [--ray-address ADDR]

`generate(out, ...)` is the same from Python; `read_dataset(out)` (or
`pandas.read_parquet(out)`) reads a dataset back, one row per problem (columns in
`manip.datagen.dataset`). Needs the datagen extra (pyarrow, pandas, tqdm).
"""

from __future__ import annotations

from manip.datagen.dataset import read_dataset
from manip.datagen.generate import Summary, generate

__all__ = ["Summary", "generate", "read_dataset"]
