"""docs/problem-model.md's protocols of a task and a constraint are the code's: each method
the page writes out exists on ``Task`` and ``Constraint`` with the parameters it names."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import pytest

from armik.constraints.base import Constraint
from armik.problem.tasks.base import Task

PAGE = (Path(__file__).resolve().parents[1] / "docs" / "problem-model.md").read_text()


def _block(cls_name: str) -> str:
    found = re.search(rf"```text\nclass {cls_name}\(.*?```", PAGE, re.S)
    assert found, f"no class {cls_name} block"
    return found.group(0)


@pytest.mark.parametrize(("cls", "name"), [(Task, "Task"), (Constraint, "Constraint")])
def test_the_written_protocol_is_the_codes(cls, name):
    block = _block(name)
    methods = re.findall(r"def (\w+)\(self(?:, )?([^)]*)\)", block)
    assert methods
    for method, params in methods:
        assert hasattr(cls, method), f"{name}.{method} is not in the code"
        written = [p.split(":")[0].strip() for p in params.split(",") if p.strip()]
        actual = list(inspect.signature(getattr(cls, method)).parameters)[1:]
        assert written == actual, (method, written, actual)
    for attribute in re.findall(r"^    (\w+): ", block, re.M):
        assert hasattr(cls, attribute), f"{name}.{attribute} is not in the code"
