"""Every Python block of docs/*.md runs, as the README's do (tests/test_readme.py): the
blocks of one page in order, in one namespace, in a scratch folder. A block that cannot
run here (a cluster's address, a file the user has) is marked just before it with
``<!-- not-run: the reason -->``, and the reason must be given."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
BLOCK = re.compile(r"(<!-- not-run:(?P<why>[^>]*)-->\s*\n)?```python\n(?P<code>.*?)```", re.S)
PAGES = sorted(p for p in DOCS.glob("*.md") if "```python" in p.read_text())


def blocks(page: Path) -> list[tuple[str, str | None]]:
    """(code, reason not run or None) of each Python block of ``page``, in order."""
    return [(m["code"], m["why"]) for m in BLOCK.finditer(page.read_text())]


def test_every_page_with_code_is_found():
    assert {p.name for p in PAGES} >= {"batch.md", "tolerances.md", "preferences.md"}


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_blocks_of_a_page_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    namespace: dict = {}
    ran = 0
    for code, why in blocks(page):
        if why is not None:
            assert why.strip(), f"{page.name}: a not-run block must say why"
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exec(compile(code, f"{page.name} block", "exec"), namespace)
        ran += 1
    assert ran, f"{page.name}: every block is marked not-run"
