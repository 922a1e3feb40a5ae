"""Shared pieces of the benchmark scripts: the machine description and BENCHMARKS.md sections."""

from __future__ import annotations

import platform
import re
from pathlib import Path

HEADER = "# Benchmarks\n\nEach section is written by its benchmark script.\n"


def cpu_model() -> str:
    """The CPU's model name (from /proc/cpuinfo on Linux), else what `platform` knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def replace_section(path: Path, heading: str, section: str) -> None:
    """Replace the `heading` section of the markdown file at `path` (or append it).

    Args:
        path: BENCHMARKS.md (created with a header if missing).
        heading: the section's heading line, e.g. "## Kinematics".
        section: the new section, starting with `heading`.
    """
    text = path.read_text() if path.exists() else HEADER
    pattern = re.compile(r"^" + re.escape(heading) + r"\n.*?(?=^## |\Z)", re.S | re.M)
    if pattern.search(text):
        text = pattern.sub(lambda _: section.rstrip("\n") + "\n\n", text).rstrip("\n") + "\n"
    else:
        text = text.rstrip("\n") + "\n\n" + section.rstrip("\n") + "\n"
    path.write_text(text)
