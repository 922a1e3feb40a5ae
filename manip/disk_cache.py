"""Results computed once per robot geometry (sphere covers, self-pair proofs and maps), kept on disk.

Each file is named by a digest of everything it depends on, so a file is either right or
absent. Reads look in the user's folder (`$MANIP_CACHE_DIR`, else `$XDG_CACHE_HOME/manip`, else
`~/.cache/manip`; `MANIP_CACHE_DIR=off` disables it), then in the prebuilt folder shipped with
manip (`manip/_prebuilt/geometry/`: the shipped robots' files, made by `python -m manip.prebuild`;
`MANIP_PREBUILT=off` ignores it).
Writes go to the user's folder, atomically (a temporary file renamed into place), so processes
may share it.
"""

from __future__ import annotations

import logging
import os
import threading
from collections.abc import Callable
from pathlib import Path

logger = logging.getLogger(__name__)

#: Files made ahead of time by `python -m manip.prebuild` (read only): kernels/ (`manip.jit`) and
#: geometry/ (the shipped robots' files of this cache).
PREBUILT_ROOT = Path(__file__).resolve().parent / "_prebuilt"
PREBUILT_GEOMETRY = PREBUILT_ROOT / "geometry"


def prebuilt_enabled() -> bool:
    """False when `MANIP_PREBUILT` is off / 0 / none / false / no: the prebuilt files are ignored."""
    return os.environ.get("MANIP_PREBUILT", "on").strip().lower() not in ("off", "0", "none", "false", "no")


class DiskCache:
    """A folder of computed files, with a read-only prebuilt folder behind it.

    Args:
        folder: where files are read first and written (None: nothing is written).
        prebuilt: a second folder to read from (None: none).
    """

    def __init__(self, folder: Path | None, prebuilt: Path | None = PREBUILT_GEOMETRY):
        self.folder = folder
        self.prebuilt = prebuilt

    def find(self, name: str) -> Path | None:
        """The file called `name` in the user's folder, else in the prebuilt one, else None."""
        for folder in (self.folder, self.prebuilt):
            if folder is not None and (folder / name).is_file():
                return folder / name
        return None

    def write(self, name: str, save: Callable[[Path], None]) -> None:
        """Write the file `name` with `save(path)` (to a temporary path, then renamed into place).

        A folder that cannot be written is logged at DEBUG and skipped: the result is only
        recomputed next time.
        """
        if self.folder is None:
            return
        file = self.folder / name
        tmp = file.with_name(f"{file.stem}.{os.getpid()}-{threading.get_ident()}.tmp{file.suffix}")
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            save(tmp)
            os.replace(tmp, file)
        except OSError as exc:
            logger.debug("%s not cached (%s)", name, exc)
            tmp.unlink(missing_ok=True)


def user_folder() -> Path | None:
    """$MANIP_CACHE_DIR (off/none/0/empty: None), else $XDG_CACHE_HOME/manip, else ~/.cache/manip."""
    env = os.environ.get("MANIP_CACHE_DIR")
    if env is not None:
        return None if env.lower() in ("", "0", "off", "none") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "manip"


def default_cache() -> DiskCache:
    """The user's folder (`user_folder`) backed by the prebuilt folder (unless `MANIP_PREBUILT=off`)."""
    return DiskCache(user_folder(), PREBUILT_GEOMETRY if prebuilt_enabled() else None)
