"""One writer per dataset folder: a lock that a crashed run does not leave stuck.

A run holds an OS lock on `DIR/_lock` while it reads the folder's manifest and ids and
writes part files (`generate`). A second run on the same folder, from this process or
another, is refused at once with `DatasetBusyError` (`python -m manip.datagen` exits with
status 3): two writers would number their part files alike and plan the same problems twice.
The lock is the OS's (a POSIX record lock, `fcntl.lockf`; `msvcrt.locking` on Windows), so
it goes with the process that holds it, however that process ends (Ctrl-C, a crash, kill -9):
a later run is never refused by a run that is gone. The file itself stays (it names the
last holder); worker processes do not inherit the lock. Folders on a network file system
lock only where that file system supports POSIX locks (NFSv4 does).
"""

from __future__ import annotations

import datetime
import logging
import os
import socket
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from manip.errors import InvalidInputError, ManipError

log = logging.getLogger(__name__)

#: The lock file in a dataset folder (a leading "_": pyarrow and pandas skip it).
LOCK_FILE = "_lock"

# POSIX record locks belong to a process, not to a file descriptor: a second lock of the same
# file by this process would succeed, so folders locked here are also kept in a set.
_held: set[str] = set()
_held_guard = threading.Lock()


class DatasetBusyError(ManipError):
    """Another run (of this process or another) is writing the dataset folder."""


def _try_lock(fd: int) -> bool:
    """Lock the open file `fd` without waiting; False when another process holds it."""
    if sys.platform == "win32":  # pragma: no cover (not run on Linux)
        import msvcrt

        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True
    import fcntl

    try:
        fcntl.lockf(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # EAGAIN / EACCES: held by another process
        return False
    return True


def _busy(out: Path, holder: str) -> DatasetBusyError:
    return DatasetBusyError(
        f"{out} is being written by another manip.datagen run ({holder}); wait for it to end (then run the "
        f"same command to complete the dataset), or use another --out. The lock is the OS's on {out / LOCK_FILE}: "
        "it goes with that run, however the run ends")


@contextmanager
def writer_lock(out: str | Path) -> Iterator[Path]:
    """Hold the writer's lock of the dataset folder `out` (which must exist) for the block.

    Yields:
        The folder.

    Raises:
        DatasetBusyError: another run holds it (the message names it: process id, host, start).
        InvalidInputError: the lock file cannot be created in `out`.
    """
    out = Path(out)
    key = str(out.resolve())
    with _held_guard:
        if key in _held:
            raise _busy(out, f"in this process, pid {os.getpid()}")
        _held.add(key)
    fd = -1
    try:
        try:
            fd = os.open(out / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise InvalidInputError(f"cannot use {out} as the dataset folder: {exc.strerror or exc}") from exc
        if not _try_lock(fd):
            holder = os.pread(fd, 4096, 0).decode(errors="replace").strip() if hasattr(os, "pread") else ""
            raise _busy(out, holder or "its process id is not written yet")
        stamp = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
        text = f"pid {os.getpid()} on {socket.gethostname()}, started {stamp}\n".encode()
        os.ftruncate(fd, 0)
        os.lseek(fd, 0, os.SEEK_SET)
        os.write(fd, text)
        log.debug("locked %s", out / LOCK_FILE)
        yield out
    finally:
        if fd >= 0:
            os.close(fd)  # releases the lock
        with _held_guard:
            _held.discard(key)
