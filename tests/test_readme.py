"""The README's code and commands stay true."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

README = (Path(__file__).parents[1] / "README.md").read_text()


def test_python_use_block_runs():
    blocks = re.findall(r"```python\n(.*?)```", README, flags=re.S)
    assert blocks, "README has no python block"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], "README.md", "exec"), {})
    assert "elbow-up" in out.getvalue() and "True converged dls" in out.getvalue()


def test_two_commands_between_markers():
    for marker, words in (("demo-command", "armik demo"), ("test-command", "pytest")):
        block = re.search(rf"<!-- {marker} -->\n```\n(.*?)\n```\n<!-- /{marker} -->", README)
        assert block and words in block.group(1) and "pip install" in block.group(1)
