"""armik's compiled functions as the plain Python they are written in.

Every kernel is a Python function that numba compiles. ``python_of(f)`` gives the function
itself, run by the interpreter, with every compiled function it calls (by a global name, an
attribute of an armik module, a closure or a function argument taken from those) replaced
by its own Python in turn: a whole solve runs without compiling anything. It is the same
code, so it computes the same answers (numba compiles without fast-math: the same IEEE
operations in the same order; only the math library's last bit may differ), only slower.
``kernel.tier`` runs first calls this way while a helper process compiles them.

The functions keep their own modules' globals, read through a view (``_Globals``) that
gives the Python form of each compiled value on first reading; nothing of the modules
themselves changes. The one function numba builds from LLVM directly (the solve budget's
CPU clock, ``clock.thread_cpu_ns``) has a Python twin here, whose clock runs ``SLOWER``
times slower, as the budgets' clock in Python (``cpu_time``) counts a Python run: so a time
budget buys the Python run the work it buys the compiled code.
"""

from __future__ import annotations

import builtins
import threading
import time
import types
from collections.abc import Callable
from typing import Any

import numpy as np
from numba.core.dispatcher import Dispatcher

from armik import cpu_time
from armik.kernel import clock

# How much slower a solve runs as Python than compiled, per iteration: 75-110 for dls and
# qp on the Panda (benchmarks/as_python.py, this project's 2-core machine)
SLOWER = 100


def _python_clock() -> int:
    """``clock.thread_cpu_ns`` for Python runs: the thread's CPU time over ``SLOWER``."""
    return time.thread_time_ns() // SLOWER


_TWINS: dict[Any, Callable] = {clock.thread_cpu_ns: _python_clock}
_FUNCTIONS: dict[Dispatcher, Callable] = {}  # its Python form, by compiled function
_MODULES: dict[str, _Globals] = {}  # module name -> the view of its globals


def is_armik(dispatcher: Dispatcher) -> bool:
    return getattr(dispatcher.py_func, "__module__", "").startswith("armik.")


def python_of(dispatcher: Dispatcher) -> Callable:
    """``dispatcher``'s function run as Python, with what it calls (see the module)."""
    known = _FUNCTIONS.get(dispatcher)
    if known is not None:
        return known
    twin = _TWINS.get(dispatcher)
    if twin is not None:
        return twin
    f = dispatcher.py_func
    module = __import__(f.__module__, fromlist=["_"])
    closure = f.__closure__
    if closure is not None:
        closure = tuple(types.CellType(_plain(c.cell_contents)) for c in closure)
    g = types.FunctionType(f.__code__, _globals_of(module), f.__name__, f.__defaults__, closure)
    g.__kwdefaults__ = f.__kwdefaults__
    g.__qualname__ = f.__qualname__
    _FUNCTIONS[dispatcher] = g
    return g


def run(dispatcher: Dispatcher) -> Callable:
    """A caller of ``python_of(dispatcher)`` as compiled code behaves: floating-point and
    unsigned wrap-around without warnings (the restarts' hash multiplies mod 2^64), and its
    CPU time counted by the budgets at compiled speed (``cpu_time``)."""
    f = python_of(dispatcher)

    def as_compiled(*args):
        outermost = not getattr(_running, "depth", 0)  # not a call back from an objmode block
        _running.depth = getattr(_running, "depth", 0) + 1
        started = time.thread_time()
        try:
            with np.errstate(all="ignore"):
                return f(*args)
        finally:
            _running.depth -= 1
            if outermost:
                cpu_time.slowed((time.thread_time() - started) * (1 - 1 / SLOWER))

    return as_compiled


_running = threading.local()  # .depth: Python runs under way in this thread


class _Globals(dict):
    """A module's globals as its functions see them when run as Python: read through, each
    compiled armik function and armik module given in its Python form."""

    def __init__(self, module: types.ModuleType) -> None:
        super().__init__(__builtins__=builtins.__dict__)
        self.module = module

    def __missing__(self, name: str) -> Any:
        if name in self.module.__dict__:
            value = _plain(self.module.__dict__[name])
        elif hasattr(builtins, name):  # kept here too: the next reading is a dict's
            value = getattr(builtins, name)
        else:
            raise KeyError(name)  # Python goes on to the builtins, and the NameError
        self[name] = value
        return value


def _globals_of(module: types.ModuleType) -> _Globals:
    view = _MODULES.get(module.__name__)
    if view is None:
        view = _MODULES[module.__name__] = _Globals(module)
    return view


class _Module:
    """An armik module's attributes as its functions' globals give them (``error._evaluate``
    read from another module's function)."""

    def __init__(self, module: types.ModuleType) -> None:
        self._globals = _globals_of(module)

    def __getattr__(self, name: str) -> Any:
        try:
            return self._globals[name]
        except KeyError:
            raise AttributeError(name) from None


_MODULE_VIEWS: dict[str, _Module] = {}


def _plain(value: Any) -> Any:
    if isinstance(value, Dispatcher):
        return python_of(value) if is_armik(value) or value in _TWINS else value
    if isinstance(value, types.ModuleType) and value.__name__.startswith("armik."):
        view = _MODULE_VIEWS.get(value.__name__)
        if view is None:
            view = _MODULE_VIEWS[value.__name__] = _Module(value)
        return view
    if type(value) is tuple and any(isinstance(v, Dispatcher) for v in value):
        return tuple(_plain(v) for v in value)
    return value
