"""An armik callee's LLVM module left to its callers to optimise: less CPU to compile.

numba optimises every compiled function's module whole (LLVM's module passes) once its
callees are linked into it, and links that module into each caller, whose module is then
optimised whole again: a callee's code went through the module passes once for each
compiled function above it. A function compiled with ``no_cpython_wrapper`` is never
called from Python, only linked into its callers (its own entry point is never run), so
its module keeps numba's per-function optimisation only, and the callers' module passes
optimise it, once for each function called from Python. The passes keep IEEE arithmetic
(no armik function is compiled with ``fastmath``): the answers are the same bits.

Only while an armik function is the innermost one compiling (numba's "numba:compile"
events, under its global lock); any other numba code compiles as it would without armik.
"""

from __future__ import annotations

from numba.core import codegen, event


class _Compiling(event.Listener):
    """The dispatchers compiling, innermost last."""

    def __init__(self) -> None:
        self.stack: list[object] = []

    def on_start(self, ev: event.Event) -> None:
        self.stack.append(ev.data.get("dispatcher") if isinstance(ev.data, dict) else None)

    def on_end(self, ev: event.Event) -> None:
        if self.stack:
            self.stack.pop()


COMPILING = _Compiling()
event.register("numba:compile", COMPILING)

_WHOLE = codegen.CPUCodeLibrary._optimize_final_module


def linked_only(dispatcher: object) -> bool:
    """Whether ``dispatcher`` is an armik function never called from Python."""
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
    if not (module == "armik" or module.startswith("armik.")):
        return False
    return bool(getattr(dispatcher, "targetoptions", {}).get("no_cpython_wrapper", False))


def _optimize_final_module(self) -> None:
    if COMPILING.stack and linked_only(COMPILING.stack[-1]):
        return  # its callers' module passes optimise it
    _WHOLE(self)


def install() -> None:
    codegen.CPUCodeLibrary._optimize_final_module = _optimize_final_module  # type: ignore[method-assign]
