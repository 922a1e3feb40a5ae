"""Every example's `--help` (issue 27): a description and a help text for every option, each
ending in a full sentence, as a user reads them in the terminal."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted(p for p in (Path(__file__).resolve().parents[1] / "examples").glob("*.py")
                  if not p.name.startswith("_"))  # _name.py: a module examples share, not an example


def parse_help(text: str) -> tuple[str, dict[str, str]]:
    """(description, {option: help text}) of an argparse `--help` output."""
    head, _, options = text.partition("\noptions:\n")
    if not options:  # Python < 3.10 says "optional arguments:"
        head, _, options = text.partition("\noptional arguments:\n")
    paragraphs = head.strip().split("\n\n")
    description = " ".join(" ".join(paragraphs[1:]).split()) if len(paragraphs) > 1 else ""
    entries: dict[str, str] = {}
    name = None
    for line in options.splitlines():
        if re.match(r"^  -", line):  # a new option: "  --name ARG   help" or the help on the next lines
            invocation, _, rest = line.strip().partition("  ")
            name = invocation.split(",")[-1].split()[0]
            entries[name] = rest.strip()
        elif name is not None and line.strip():
            entries[name] = f"{entries[name]} {line.strip()}".strip()
    return description, entries


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_help_describes_the_example_and_every_option_in_full_sentences(script: Path, tmp_path: Path):
    proc = subprocess.run([sys.executable, str(script), "--help"], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    description, options = parse_help(proc.stdout)
    assert description.endswith("."), f"{script.name}: description cut mid-sentence: {description!r}"
    options.pop("--help", None)
    assert options, f"{script.name}: no options parsed from\n{proc.stdout}"
    for name, text in options.items():
        assert text, f"{script.name}: {name} has no help text"
        assert text.endswith("."), f"{script.name}: {name}'s help does not end in a full sentence: {text!r}"
        assert text[0].isupper() or text.startswith("--"), f"{script.name}: {name}'s help: {text!r}"
