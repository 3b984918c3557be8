"""The habits a contributor relies on, checked where CI runs the tests: ruff's lint and
format over the code, and the layout (no import cycle among modules or packages, no module
over 500 lines, a README under 300 lines), read from the source."""

from __future__ import annotations

import ast
import functools
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
SRC = ROOT / "src"
CODE = ["src", "tests", "examples", "benchmarks"]
MAX_LINES = 500
README_MAX = 300


def _ruff(*args: str) -> subprocess.CompletedProcess:
    ruff = shutil.which("ruff") or str(Path(sys.executable).parent / "ruff")
    if not Path(ruff).exists():
        pytest.fail("ruff is not installed: the test extra installs it (pip install '.[test]')")
    return subprocess.run([ruff, *args, *CODE], cwd=ROOT, capture_output=True, text=True)


def test_ruff_lint():
    proc = _ruff("check", "--no-cache")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_format():
    proc = _ruff("format", "--check", "--no-cache")
    assert proc.returncode == 0, proc.stdout + proc.stderr + "\nfix: ruff format src tests ..."


def _modules() -> dict[str, Path]:
    mods = {}
    for path in sorted((SRC / "armik").rglob("*.py")):
        parts = path.relative_to(SRC).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        mods[name] = path
    return mods


def _imports(path: Path, name: str, mods: dict) -> set[str]:
    """The armik modules ``path`` imports at module level, its type-only imports (the
    TYPE_CHECKING blocks) included: a type names what a module stands on as well."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()

    def visit(nodes) -> None:
        for node in nodes:
            if isinstance(node, ast.Import):
                found.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(up + ([base] if base else []))
                found.add(base)
                found.update(f"{base}.{a.name}" for a in node.names)
            elif isinstance(node, (ast.If, ast.Try)):
                visit(node.body)
                visit(getattr(node, "orelse", []))

    visit(tree.body)
    return {m for m in found if m in mods and m != name}


@functools.cache  # parsed once for both cycle checks, which only read it
def _graph() -> dict[str, set[str]]:
    mods = _modules()
    return {name: _imports(path, name, mods) for name, path in mods.items()}


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph``, or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def walk(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in state and (found := walk(nxt)):
                return found
        state[node] = 2
        stack.pop()
        return None

    for node in sorted(graph):
        if node not in state and (found := walk(node)):
            return found
    return None


def _package(module: str, graph: dict) -> str:
    """The unit a module belongs to: itself for a package or a module at the top of
    ``armik`` (the vocabulary: ``status``, ``batch_result``, ...), else its package."""
    is_package = any(other.startswith(module + ".") for other in graph)
    return module if is_package or module.count(".") == 1 else module.rpartition(".")[0]


def test_no_module_imports_itself_in_a_circle():
    graph = _graph()
    # a package's __init__ importing its own modules is the usual re-export, not a cycle
    edges = {
        m: {n for n in deps if not n.startswith(m + ".") and not m.startswith(n + ".")}
        for m, deps in graph.items()
    }
    assert _cycle(edges) is None, " -> ".join(_cycle(edges) or [])


def test_no_package_imports_a_package_that_imports_it():
    graph = _graph()
    packages: dict[str, set[str]] = {}
    for module, deps in graph.items():
        mine = _package(module, graph)
        for dep in deps:
            other = _package(dep, graph)
            if (
                other != mine
                and not other.startswith(mine + ".")
                and not mine.startswith(other + ".")
            ):
                packages.setdefault(mine, set()).add(other)
    assert _cycle(packages) is None, " -> ".join(_cycle(packages) or [])


def test_modules_and_readme_stay_short():
    long = {
        str(p.relative_to(ROOT)): n
        for p in _modules().values()
        if (n := p.read_text(encoding="utf-8").count("\n") + 1) > MAX_LINES
    }
    assert not long, f"modules over {MAX_LINES} lines: {long}"
    readme = (ROOT / "README.md").read_text(encoding="utf-8").count("\n") + 1
    assert readme <= README_MAX, f"README.md has {readme} lines (at most {README_MAX})"


def test_the_cycle_check_can_fail():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


def test_type_only_imports_count_as_imports(tmp_path):
    """A module that names another's type under TYPE_CHECKING stands on it: a circle through
    such an import is a circle."""
    path = tmp_path / "m.py"
    path.write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from armik.arm import Arm\n"
    )
    assert _imports(path, "armik.m", _modules()) == {"armik.arm"}


def test_the_kernel_takes_plain_arrays():
    """``kernel/`` reads no arm model and no Pinocchio model: the model is read into arrays
    below it (``model/chain_arrays.py``, ``model/frame_chains.py``)."""
    graph, kernel = _graph(), "armik.kernel"
    above = {
        m: sorted(d for d in deps if d.startswith(("armik.model", "armik.solve")))
        for m, deps in graph.items()
        if m.startswith(kernel + ".")
    }
    assert not {m: d for m, d in above.items() if d}
    for path in (SRC / "armik" / "kernel").glob("*.py"):
        assert "import pinocchio" not in path.read_text(encoding="utf-8"), path.name
