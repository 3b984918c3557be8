"""The order conftest.py gives the suite: the tour first, the long tests next, every test
once."""

from __future__ import annotations

import ast
from pathlib import Path

from . import conftest

ROOT = Path(__file__).parents[1]


def test_each_long_test_named_is_still_a_test():
    """Each entry names a test file that is there and, past its ``::``, the start of the
    name of a test function in it."""
    missing = []
    for start in conftest.LONG:
        path, _, name = start.partition("::")
        file = ROOT / path
        tests = [
            node.name
            for node in ast.parse(file.read_text(encoding="utf-8")).body
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_")
        ] if file.is_file() else []  # fmt: skip
        if not any(test.startswith(name) for test in tests):
            missing.append(start)
    assert not missing, f"conftest.LONG names no test: {missing}"


def test_the_long_tests_come_first_after_the_tour_and_none_twice():
    class Item:
        def __init__(self, nodeid: str) -> None:
            self.nodeid, self.name = nodeid, nodeid.rpartition("::")[2]

    names = [
        "tests/a.py::test_a",
        "tests/view/test_cli_view.py::test_one",
        "tests/test_types.py::test_mypy_reports_no_error",
        f"tests/kernel/test_compile.py::{conftest.TOUR}",
        "tests/view/test_cli_view.py::test_two",
        "tests/z.py::test_z",
    ]
    items = [Item(n) for n in names]
    conftest.pytest_collection_modifyitems(None, None, items)
    assert [i.nodeid for i in items] == [
        f"tests/kernel/test_compile.py::{conftest.TOUR}",
        "tests/test_types.py::test_mypy_reports_no_error",
        "tests/view/test_cli_view.py::test_one",
        "tests/view/test_cli_view.py::test_two",
        "tests/a.py::test_a",
        "tests/z.py::test_z",
    ]
