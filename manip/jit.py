"""Compiled kernels: numba's JIT, with kernels compiled ahead of time and shipped with manip.

`kernel` is `numba.njit(nogil=True)` with a cache that looks in two places, in order:

1. numba's own on-disk cache (`__pycache__` beside the source, or numba's user-wide folder),
   keyed to this machine's CPU: what this environment compiled before;
2. the prebuilt kernels (`manip/_prebuilt/kernels/`), compiled ahead of time for the generic
   CPU of an architecture (x86-64: SSE2 only, so they run on every x86-64 CPU) by
   `python -m manip.prebuild` (the wheel is built with them; `make setup` builds them in a
   checkout). They are used only when numba's version, Python's version, the architecture
   and the source of every kernel module are exactly those they were built from
   (`manifest.json`); anything else compiles as before. One folder can serve several Pythons
   (numba names its files by Python version): `python -m manip.prebuild --add`, run by each
   other interpreter, adds its kernels and its environment to the manifest (`make wheel` does
   for Python 3.11-3.13). `MANIP_PREBUILT=off` ignores them.

As with numba's own cache, a kernel is keyed by its module's source: a kernel must read no
global of a module that defines no kernel (such a value is frozen into the compiled code).

A kernel found in neither is compiled by numba (1-8 s each, once: numba caches it) and one
log line (WARNING, once per process) says so. Nothing here changes numba's configuration or
the environment: other numba code in the process is unaffected.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import sys
import threading
from pathlib import Path

import numba
import numpy as np
from numba.core.caching import FunctionCache, IndexDataCacheFile

from manip.disk_cache import PREBUILT_ROOT, prebuilt_enabled

logger = logging.getLogger(__name__)

#: Folder of the prebuilt kernels and of their manifest.
PREBUILT_KERNELS = PREBUILT_ROOT / "kernels"
#: Set by `manip.prebuild` in the process that compiles the prebuilt kernels: compiled
#: kernels are also written there, keyed for the generic CPU.
BUILD_ENV = "MANIP_PREBUILD_KERNELS"
#: The CPU the prebuilt kernels are compiled for (numba's NUMBA_CPU_NAME).
PORTABLE_CPU = "generic"

_KERNEL_FILES: set[Path] = set()  # source files that define kernels
_COMPILED: set[str] = set()  # kernels compiled by this process
_lock = threading.Lock()
_prebuilt_valid: bool | None = None
_warned = False


def kernel(fn=None, **options):
    """Decorator: `numba.njit(nogil=True, **options)` with manip's two-level cache (module docstring);
    `nogil=False` for a kernel that calls back into Python (`numba.objmode`)."""

    def wrap(f):
        dispatcher = numba.njit(**{"nogil": True, **options})(f)
        _KERNEL_FILES.add(Path(f.__code__.co_filename).resolve())
        # numba's `enable_caching` installs a FunctionCache; ours extends it
        dispatcher._cache = KernelCache(dispatcher.py_func)
        return dispatcher

    return wrap if fn is None else wrap(fn)


def kernel_array(a, dtype=np.float64) -> np.ndarray:
    """`a` as a C-contiguous, writable array of `dtype` (a copy only when needed).

    Kernels are compiled (and prebuilt) for writable arrays; a read-only one, such as a
    returned trajectory's `positions`, would make numba compile a second version of the
    kernel (1-8 s of CPU each in a fresh environment). Pass kernels' array arguments that
    may come from a caller through this.
    """
    out = np.ascontiguousarray(a, dtype=dtype)
    return out if out.flags.writeable else out.copy()


def kernel_files() -> list[Path]:
    """The source files that define kernels (those imported so far)."""
    return sorted(_KERNEL_FILES)


def compiled_names() -> list[str]:
    """Qualified names of the kernels this process compiled (not loaded from a cache)."""
    return sorted(_COMPILED)


def source_digest(files) -> dict[str, str]:
    """{file name relative to the manip package: sha256 of its bytes} for `files`."""
    root = Path(__file__).resolve().parent
    return {str(Path(f).resolve().relative_to(root)): hashlib.sha256(Path(f).read_bytes()).hexdigest()
            for f in sorted(files)}


def environment() -> dict[str, str]:
    """What the prebuilt kernels depend on besides their source."""
    from numba.core.registry import cpu_target

    triple = cpu_target.target_context.codegen().magic_tuple()[0]
    return {"numba": numba.__version__, "python": f"{sys.version_info[0]}.{sys.version_info[1]}", "triple": triple}


def manifest_environments(manifest: dict) -> list[dict]:
    """The environments (`environment()`) whose kernels a prebuilt manifest lists: the one that
    built the folder, then each added by `python -m manip.prebuild --add` (another Python)."""
    envs = manifest.get("environments")
    return list(envs) if isinstance(envs, list) else [manifest.get("environment")]


def read_manifest(folder: Path) -> dict | None:
    """The prebuilt kernels' `manifest.json` in `folder`, or None (missing or unreadable)."""
    try:
        return json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError):
        return None


def _manifest_matches() -> bool:
    """True when the prebuilt kernels were built from this source, numba, Python and architecture."""
    global _prebuilt_valid
    with _lock:
        if _prebuilt_valid is None:
            _prebuilt_valid = False
            if not prebuilt_enabled():
                return False
            manifest = read_manifest(PREBUILT_KERNELS)
            if manifest is not None:
                root = Path(__file__).resolve().parent
                try:
                    sources = source_digest(root / name for name in manifest.get("sources", {}))
                except OSError:
                    sources = None
                env = environment()
                _prebuilt_valid = sources == manifest.get("sources") and env in manifest_environments(manifest)
                if not _prebuilt_valid:
                    logger.info("prebuilt kernels in %s were built for %s, this is %s%s: compiling instead",
                                PREBUILT_KERNELS, manifest_environments(manifest), env,
                                "" if sources == manifest.get("sources") else " (the kernels' source changed)")
        return _prebuilt_valid


def _warn_compiling(name: str) -> None:
    global _warned
    if not _warned:
        _warned = True
        logger.warning("compiling manip's kernels for this machine (%s first): about 20-40 s of CPU once, "
                       "cached afterwards (prebuilt kernels: `python -m manip.prebuild`)", name)


class KernelCache(FunctionCache):
    """numba's FunctionCache, falling back to the prebuilt kernels (keyed for `PORTABLE_CPU`)."""

    def __init__(self, py_func):
        super().__init__(py_func)
        self._prebuilt = IndexDataCacheFile(cache_path=str(PREBUILT_KERNELS), filename_base=self._impl.filename_base,
                                            source_stamp="manifest")
        self._building = bool(os.environ.get(BUILD_ENV))

    def _portable_key(self, sig, codegen):
        key = self._index_key(sig, codegen)
        return key[0], (key[1][0], PORTABLE_CPU, ""), key[2]

    def _load_overload(self, sig, target_context):
        data = None if self._building else super()._load_overload(sig, target_context)
        if data is None and not self._building and _manifest_matches():
            payload = self._prebuilt.load(self._portable_key(sig, target_context.codegen()))
            if payload is not None:
                data = self._impl.rebuild(target_context, payload)
        if data is None and not self._building:
            _warn_compiling(self._py_func.__qualname__)
        return data

    def _save_overload(self, sig, data):
        _COMPILED.add(f"{self._py_func.__module__}.{self._py_func.__qualname__}")
        super()._save_overload(sig, data)
        if self._building and self._impl.check_cachable(data):
            if data.codegen.magic_tuple()[1] != PORTABLE_CPU:
                raise RuntimeError(f"prebuilt kernels must be compiled with NUMBA_CPU_NAME={PORTABLE_CPU}")
            PREBUILT_KERNELS.mkdir(parents=True, exist_ok=True)
            self._prebuilt.save(self._portable_key(sig, data.codegen), self._impl.reduce(data))
