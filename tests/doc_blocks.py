"""The Python blocks of a Markdown page, and running them: shared by the README's test
(tests/test_readme.py) and the docs' (tests/test_docs_code.py).

A block that cannot run in the tests (a cluster's address, a file the user has) is marked
on the line just before its fence with ``<!-- not-run: the reason -->``; a marker without
a reason is an error."""

from __future__ import annotations

import contextlib
import io
import re
from dataclasses import dataclass

_BLOCK = re.compile(
    r"(?:^<!-- not-run:(?P<why>[^>]*)-->[ \t]*\n)?^```python[ \t]*\n(?P<code>.*?)^```",
    flags=re.S | re.M,
)


@dataclass(frozen=True)
class Block:
    code: str
    line: int  # the line of the page the code starts on, counted from 1
    not_run: str | None  # the reason it is not run, or None: it runs


def blocks(text: str, where: str = "page") -> list[Block]:
    """Every Python block of ``text``, in order; ``where`` names the page in errors."""
    found = []
    for match in _BLOCK.finditer(text):
        line = text.count("\n", 0, match.start("code")) + 1
        why = match["why"]
        if why is not None and not why.strip():
            raise ValueError(f"{where}:{line}: a not-run block must say why")
        found.append(Block(match["code"], line, None if why is None else why.strip()))
    return found


def python_blocks(text: str) -> list[str]:
    """The code of each Python block of ``text`` that runs, in order."""
    return [block.code for block in blocks(text) if block.not_run is None]


def run(code: str, where: str, namespace: dict | None = None, line: int = 1) -> str:
    """Run ``code`` in ``namespace`` (a fresh one by default) and return what it printed.
    ``where`` and ``line`` place a traceback at the page's line."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(
            compile("\n" * (line - 1) + code, where, "exec"), {} if namespace is None else namespace
        )
    return out.getvalue()
