"""Each step a test of the suite asks of a new closed-form family, task or constraint is in
CONTRIBUTING's recipe for it: a contributor who follows the recipe finds the suite green."""

from __future__ import annotations

from pathlib import Path

import pytest

from armik.precompile import _HALVES, PARTS
from armik.tools.cli.commands import PART_NAMES

ROOT = Path(__file__).resolve().parents[2]
TEXT = (ROOT / "CONTRIBUTING.md").read_text(encoding="utf-8")


def _recipe(title: str) -> str:
    """The recipe that starts with the bold ``title`` and runs to the next one."""
    start = TEXT.index(f"**{title}.**")
    end = TEXT.find("\n**", start + 1)
    return TEXT[start : end if end > 0 else None]


def test_the_compile_parts_a_family_adds_are_named_where_the_tests_read_them():
    # a part outside the halves or the parser's list fails tests/kernel/test_compile.py
    # or tests/tools/test_cli.py
    assert sorted(n for half in _HALVES for n in half) == sorted(PARTS)
    assert PART_NAMES == tuple(PARTS)
    family = _recipe("A closed-form family")
    for step in ("`_HALVES`", "`PART_NAMES`", "make_golden.py", "tests/test_contributing.py"):
        assert step in family, step
    assert "complete=False" in family  # a search's misses are no proof
    assert "`SEARCHES`" in family  # armik info's words for a search


@pytest.mark.parametrize(
    ("title", "steps"),
    [
        ("A task", ("`problem/__init__.py`", "tests/test_contributing.py")),
        ("A constraint", ("tests/test_contributing.py",)),
        ("A score", ("`_NAMED`", "`tools/cli/flags.py`")),
    ],
)
def test_a_new_file_is_named_in_the_layout_and_exported(title, steps):
    recipe = _recipe(title)
    for step in steps:
        assert step in recipe, step


def test_the_set_up_names_every_check_ci_runs_on_a_new_module():
    set_up = TEXT[TEXT.index("## Set up") : TEXT.index("## Package layout")]
    for check in ("tests/test_house.py", "tests/test_types.py"):
        assert check in set_up, check
