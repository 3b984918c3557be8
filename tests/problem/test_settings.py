"""What a solver reads (``SolverSettings``) apart from what the stages read (``Options``)."""

from __future__ import annotations

import ast
from dataclasses import fields
from pathlib import Path

from armik.options import Options
from armik.problem.settings import SolverSettings
from armik.request import with_seed

STAGE_FIELDS = {"obstacles", "self_collision", "margin", "hold", "swivel", "slide"}
SOLVERS = Path(__file__).resolve().parents[2] / "src" / "armik" / "solvers"


def test_a_solver_reads_no_stage_field():
    solver_fields = {f.name for f in fields(SolverSettings)}
    assert solver_fields.isdisjoint(STAGE_FIELDS)
    assert {f.name for f in fields(Options)} == solver_fields | STAGE_FIELDS


def test_no_solver_module_imports_the_stages_options():
    importing = []
    for path in SOLVERS.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module == "armik.options":
                importing.append(path.name)
            if isinstance(node, ast.Import) and any(a.name == "armik.options" for a in node.names):
                importing.append(path.name)
    assert importing == []


def test_settings_equal_by_class_and_every_field():
    a = Options.from_kwargs({"weights": (1, 1, 1, 0, 0, 1)})
    b = with_seed(with_seed(a, 5), 0)  # a copy through another seed and back
    assert a == b and hash(a) == hash(b) and {a: 1}[b] == 1
    assert a != Options.from_kwargs({"weights": (1, 1, 1, 0, 0, 1), "self_collision": True})
    assert a != Options.from_kwargs({"weights": (1, 1, 1, 0, 0, 2)})
    assert SolverSettings() != Options()  # another class, though every shared field agrees
