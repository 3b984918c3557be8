"""Every dotted ``armik.x.y`` name in the documentation and the docstrings names something
that exists, and every ``src/armik/...py`` path a file that exists: a module that moves
takes its references with it."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
TEXTS = [
    ROOT / "README.md",
    ROOT / "CONTRIBUTING.md",
    *sorted((ROOT / "docs").glob("*.md")),
    *sorted((ROOT / "src" / "armik").rglob("*.py")),
]
DOTTED = re.compile(r"\barmik(?:\.[A-Za-z_][A-Za-z0-9_]*)+(?![\w/])")  # "armik.X/1": a format
PATH = re.compile(r"\bsrc/armik/[\w/]+\.py\b")


def resolves(name: str) -> bool:
    """Whether ``name`` is reached from ``armik`` part by part: an attribute where the
    object has it, else a module. An attribute first: importing ``armik.robots`` (the
    installed package's folder of URDFs, a namespace package) would bind the name to that
    folder in place of the function ``armik.robots``, for every later test in the process."""
    parts = name.split(".")
    obj = importlib.import_module(parts[0])
    for cut in range(1, len(parts)):
        if hasattr(obj, parts[cut]):
            obj = getattr(obj, parts[cut])
            continue
        try:
            obj = importlib.import_module(".".join(parts[: cut + 1]))
        except ImportError:
            return False
    return True


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_references_resolve(path):
    text = path.read_text(encoding="utf-8")
    stale = sorted({m.rstrip(".") for m in DOTTED.findall(text) if not resolves(m.rstrip("."))})
    missing = sorted({p for p in PATH.findall(text) if not (ROOT / p).exists()})
    assert not stale and not missing, f"stale names {stale}, missing files {missing}"


def test_the_check_can_fail():
    assert resolves("armik.solve.distributed") and resolves("armik.Arm.solve")
    assert not resolves("armik.planar") and not resolves("armik.kernel.check")
