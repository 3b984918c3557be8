"""numba types an int or bool literal passed by compiled code to a compiled function as that
very value (``Literal[int](3)``, ``Literal[bool](False)``), and compiles the callee once for
each value and once more for a variable: ``sixr.onto_limits`` called with False and True
compiled twice, ``line_split.split_at`` with 3, 5 and with variables twice. Read from the
source: a compiled callee takes at each argument either one literal or none."""

from __future__ import annotations

import ast
import functools
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).parents[2] / "src" / "armik"
# compiled once per literal on purpose: quartic's degree, folded into the root finder; the
# cubic and quadratic that pass 3 and 2 are called from Python only (by the tests)
FOLDED = {"armik.solvers.closed_form.roots._solve"}


def _compiled(fn: ast.FunctionDef) -> str | None:
    """The njit decorator's text, or None."""
    for d in fn.decorator_list:
        text = ast.unparse(d)
        if text == "njit" or text.startswith("njit("):
            return text
    return None


def _name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _literal(node: ast.expr) -> object:
    """An int or bool literal's value (-1 too: Python folds it), else None."""
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        value = _literal(node.operand)
        return None if value is None or isinstance(value, bool) else -value  # type: ignore[operator]
    if isinstance(node, ast.Constant) and type(node.value) in (int, bool):
        return node.value
    return None


class _Module:
    def __init__(self, path: Path) -> None:
        self.name = _name(path)
        self.tree = ast.parse(path.read_text(encoding="utf-8"))
        self.functions = {
            n.name: n for n in self.tree.body if isinstance(n, ast.FunctionDef) and _compiled(n)
        }
        self.constants: dict[str, object] = {}  # NAME = 3 (numba freezes it: a literal)
        self.imported: dict[str, str] = {}  # a local name: the dotted name it stands for
        for node in self.tree.body:
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target = node.targets[0]
                if isinstance(target, ast.Name) and _literal(node.value) is not None:
                    self.constants[target.id] = _literal(node.value)
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("armik"):
                for alias in node.names:
                    self.imported[alias.asname or alias.name] = f"{node.module}.{alias.name}"


@functools.cache
def _module(name: str) -> _Module | None:
    """The package's module ``name`` read (a package by its __init__), or None."""
    parts = name.split(".")[1:]
    for path in (
        PACKAGE.joinpath(*parts).with_suffix(".py"),
        PACKAGE.joinpath(*parts, "__init__.py"),
    ):
        if path.is_file():
            return _Module(path)
    return None


def _resolve(dotted: str) -> tuple[_Module, str] | None:
    module, _, attr = dotted.rpartition(".")
    found = _module(module) if module.startswith("armik") else None
    return (found, attr) if found is not None else None


def _callee(call: ast.Call, here: _Module) -> str | None:
    """The dotted name of the compiled function ``call`` calls, else None."""
    f = call.func
    dotted = None
    if isinstance(f, ast.Name):
        dotted = f"{here.name}.{f.id}" if f.id in here.functions else here.imported.get(f.id)
    elif isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name):
        if f.value.id in here.imported:
            dotted = f"{here.imported[f.value.id]}.{f.attr}"
    found = _resolve(dotted) if dotted else None
    if found is None or found[1] not in found[0].functions:
        return None
    return dotted


def _argument(node: ast.expr, here: _Module) -> str:
    """How numba types ``node`` as an argument: 'literal 3' or 'a variable'."""
    value = _literal(node)
    if value is None and isinstance(node, ast.Name):
        if node.id in here.constants:
            value = here.constants[node.id]
        elif node.id in here.imported:
            found = _resolve(here.imported[node.id])
            if found is not None:
                value = found[0].constants.get(found[1])
    return "a variable" if value is None else f"literal {value!r}"


def _arguments_of_compiled_calls() -> dict[tuple[str, str], dict[str, list[str]]]:
    """Per compiled callee and argument (its position or keyword), how each call site of
    compiled code passes it, and where."""
    seen: dict[tuple[str, str], dict[str, list[str]]] = defaultdict(lambda: defaultdict(list))
    compiled = [p for p in sorted(PACKAGE.rglob("*.py")) if "njit" in p.read_text(encoding="utf-8")]
    for path in compiled:
        here = _module(_name(path))
        assert here is not None
        for caller in here.functions.values():
            for call in ast.walk(caller):
                if not isinstance(call, ast.Call):
                    continue
                callee = _callee(call, here)
                if callee is None:
                    continue
                site = f"{here.name}.{caller.name} line {call.lineno}"
                given = [(str(i), a) for i, a in enumerate(call.args)]
                given += [(k.arg or "**", k.value) for k in call.keywords]
                for slot, node in given:
                    seen[(callee, slot)][_argument(node, here)].append(site)
    return seen


def _inlined(dotted: str) -> bool:
    """Whether the function is inlined where it is called (typed there, never compiled)."""
    found = _resolve(dotted)
    assert found is not None
    return "inline" in (_compiled(found[0].functions[found[1]]) or "")


def test_a_compiled_function_takes_one_literal_or_none_at_each_argument():
    mixed = []
    for (callee, slot), ways in _arguments_of_compiled_calls().items():
        literal = any(w.startswith("literal") for w in ways)
        if len(ways) > 1 and literal and callee not in FOLDED and not _inlined(callee):
            mixed.append(f"{callee} argument {slot}: {dict(ways)}")
    assert mixed == [], "a typed constant (np.int64(3), np.bool_(False)) compiles once:\n" + (
        "\n".join(mixed)
    )


def test_the_reading_finds_literal_arguments():
    # the check sees the calls it is about: the closed forms' typed constants and a literal
    seen = _arguments_of_compiled_calls()
    split = seen[("armik.solvers.closed_form.line_split.split_at", "6")]
    assert set(split) == {"a variable"}
    assert any(w.startswith("literal") for ways in seen.values() for w in ways)
