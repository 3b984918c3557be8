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
    """Whether ``name`` is a module, or an attribute reached from its longest module."""
    parts = name.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for attr in parts[cut:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_references_resolve(path):
    text = path.read_text(encoding="utf-8")
    stale = sorted({m.rstrip(".") for m in DOTTED.findall(text) if not resolves(m.rstrip("."))})
    missing = sorted({p for p in PATH.findall(text) if not (ROOT / p).exists()})
    assert not stale and not missing, f"stale names {stale}, missing files {missing}"


def test_the_check_can_fail():
    assert resolves("armik.solve.distributed") and resolves("armik.Arm.solve")
    assert not resolves("armik.planar") and not resolves("armik.kernel.check")
