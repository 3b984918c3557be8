"""Every Python block of docs/*.md runs, as the README's do (tests/test_readme.py, the same
helper: tests/doc_blocks.py): the blocks of one page in order, in one namespace, in a
scratch folder, with no network. A block that cannot run here (a cluster's address, a file
the user has) is marked on the line just before it with ``<!-- not-run: the reason -->``,
and the reason must be given."""

from __future__ import annotations

import re
import socket
from pathlib import Path

import pytest

from tests.doc_blocks import blocks, run

DOCS = Path(__file__).resolve().parents[1] / "docs"
ALL_PAGES = sorted(DOCS.glob("*.md"))
PAGES = [p for p in ALL_PAGES if blocks(p.read_text(), p.name)]
needs_docs = pytest.mark.skipif(not ALL_PAGES, reason="docs/ is not part of this tree (an sdist)")


@needs_docs
def test_every_page_with_code_is_found():
    assert {p.name for p in PAGES} >= {"batch.md", "tolerances.md", "preferences.md"}


@needs_docs
@pytest.mark.parametrize("page", ALL_PAGES, ids=lambda p: p.name)
def test_no_python_escapes_the_test(page):
    """Python is fenced as ```python (other spellings would not be run), and every
    not-run marker sits on the line just before a Python block's fence."""
    text = page.read_text()
    other = re.findall(r"^```(py|python3|pycon|ipython)\b", text, flags=re.M)
    assert not other, f"{page.name}: fence Python blocks as ```python, not {other}"
    marked = sum(block.not_run is not None for block in blocks(text, page.name))
    assert text.count("<!-- not-run:") == marked, (
        f"{page.name}: a <!-- not-run: ... --> marker is not on the line before a ```python fence"
    )


def test_a_not_run_marker_needs_a_reason():
    text = "<!-- not-run: needs a cluster -->\n```python\nx = 1\n```\n"
    assert [b.not_run for b in blocks(text)] == ["needs a cluster"]
    with pytest.raises(ValueError, match="must say why"):
        blocks(text.replace("needs a cluster", " "))


_connect = socket.socket.connect


def _no_network(self, address):
    if self.family in (socket.AF_INET, socket.AF_INET6):
        raise OSError(f"a docs block tried to connect to {address}: nothing may download")
    return _connect(self, address)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_blocks_of_a_page_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setattr(socket.socket, "connect", _no_network)
    namespace: dict = {"__name__": "__docs__"}
    ran = 0
    for block in blocks(page.read_text(), page.name):
        if block.not_run is None:
            printed = run(block.code, str(page), namespace, block.line)
            ran += 1
            # numpy 2 prints a scalar in a list as np.str_('converged'): print .tolist()
            shown = _NUMPY_SCALAR.search(printed)
            assert not shown, f"{page.name}:{block.line}: prints {shown.group(0)}...)"
    assert ran, f"{page.name}: every block is marked not-run"


_NUMPY_SCALAR = re.compile(r"np\.\w+\(")


_NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def _same_numbers(shown: str, printed: str) -> bool:
    """The same words, the same counts, and the same measures to 1 % (a value at rounding's
    level, below 1e-12, matches any other there)."""
    if _NUMBER.sub("#", shown) != _NUMBER.sub("#", printed):
        return False
    for a, b in zip(_NUMBER.findall(shown), _NUMBER.findall(printed)):
        if a.lstrip("+-").isdigit() and a != b:  # a count: exact
            return False
        x, y = float(a), float(b)
        if abs(x) < 1e-12 and abs(y) < 1e-12:
            continue
        if abs(x - y) > 0.01 * max(abs(x), abs(y)):
            return False
    return True


@needs_docs
def test_servo_sample_output_is_what_the_command_prints(capsys):
    """servo.md's `$ armik servo ...` session, line for line but the tick's times."""
    from armik.tools.cli import main

    text = (DOCS / "servo.md").read_text()
    session = re.search(r"```\n\$ armik (servo [^\n]*)\n(.*?)```", text, flags=re.S)
    assert session, "servo.md has no '$ armik servo' session"
    assert main(session.group(1).split()) in (0, None)
    printed = capsys.readouterr().out.splitlines()
    shown = session.group(2).splitlines()
    assert len(printed) == len(shown), printed
    for want, got in zip(shown, printed):
        if want.startswith("tick:"):  # a time on this machine
            assert got.startswith("tick:")
            continue
        assert _same_numbers(want, got), f"servo.md shows\n  {want}\narmik servo prints\n  {got}"
