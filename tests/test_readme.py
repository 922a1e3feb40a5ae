"""Every python code block of README.md runs as written, in order, in one process (issue 27).

The blocks run in one fresh interpreter, one namespace, headless, from a scratch folder. The
only line left out is `viewer.wait()`, which serves the web viewer until Ctrl-C.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
#: The one line the test leaves out: it serves forever.
SERVES_FOREVER = re.compile(r"^viewer\.wait\(\)\s*(#.*)?$", re.M)

RUNNER = """
import sys
blocks = {blocks!r}
namespace = {{"__name__": "__main__"}}
for k, (line, source) in enumerate(blocks):
    print(f"--- README block {{k}} (line {{line}})", flush=True)
    exec(compile(source, f"README.md block {{k}} (line {{line}})", "exec"), namespace)
print("--- all README blocks ran", flush=True)
"""


def python_blocks(text: str) -> list[tuple[int, str]]:
    """(first line number, source) of every ```python block of `text`, in order."""
    return [(text.count("\n", 0, m.start(1)) + 1, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)]


def test_the_readme_has_python_blocks_and_one_line_that_serves_forever():
    blocks = python_blocks(README.read_text())
    assert len(blocks) >= 5
    assert sum(len(SERVES_FOREVER.findall(src)) for _, src in blocks) == 1


def test_every_python_block_of_the_readme_runs_in_order_in_one_process(tmp_path):
    pytest.importorskip("viser", reason="the README's viewer block needs the viz extra")
    blocks = [(line, SERVES_FOREVER.sub("pass  # viewer.wait() serves until Ctrl-C", src))
              for line, src in python_blocks(README.read_text())]
    proc = subprocess.run([sys.executable, "-c", RUNNER.format(blocks=blocks)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=1800)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-5000:]
    assert "--- all README blocks ran" in proc.stdout
    # the blocks that plan print their statuses: every plan succeeded
    assert "['SUCCESS', 'SUCCESS', 'SUCCESS', 'SUCCESS']" in proc.stdout, proc.stdout[-3000:]
    assert "\nSUCCESS " in proc.stdout, proc.stdout[-3000:]
