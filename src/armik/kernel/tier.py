"""First calls answered at once: run as Python while a helper process compiles them.

numba compiles a function at its first call with new argument types, and a solver takes
10-25 s to compile on a 2-core machine; the cache then serves every later process. Run as
Python instead (``as_python``), the same kernels answer a first solve in milliseconds
(a Panda dls solve in 2-10 ms). So when an armik function is called from Python with
argument types neither compiled in this process nor in numba's cache, this module:

- sends the function and its types to one helper process (started at the first such call),
  which compiles them into the cache, one after the other;
- runs this call, and every call of the same function and types until the helper is done,
  as Python;
- at the first call after the helper is done, loads the compiled code from the cache
  (milliseconds), which every later call runs, as if it had compiled here.

A helper still compiling when the program ends goes on until its queue is done, so the
next process finds the cache filled; it then ends. A call over large arrays (a batch of
many targets: more than ``LARGEST`` values in one argument) compiles here first, as
before: it would run longer as Python than the compile takes. The hook sits where numba
asks a function to compile for a call from Python (``Dispatcher._compile_for_args``), so a
call of compiled code (the hot path) never passes through it.

Python runs instead of waiting only where a helper may start (two CPUs, an interpreter
to start it with: ``warmup.helper_allowed``); ``ARMIK_FIRST_CALLS=compile`` in the
environment turns it off (the tests do, so that their timing is the compiled code's);
``ARMIK_FIRST_CALLS=python`` runs every call not in the cache as Python and starts no
helper (the tests of the Python runs).
"""

from __future__ import annotations

import contextlib
import os
import pickle
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
from numba.core import types as numba_types
from numba.core.dispatcher import Dispatcher
from numba.np import numpy_support

from armik.kernel.as_python import is_armik, run
from armik.kernel.notice import in_background

# "compile": compile at the first call, as numba does; "python": run as Python, no helper
ENVIRONMENT = "ARMIK_FIRST_CALLS"
HELPER = "ARMIK_COMPILE_HELPER"  # "0": no helper process, "1": one even on one CPU
LARGEST = 65536  # values in one array argument: a call over more compiles first

_COMPILE = Dispatcher._compile_for_args  # type: ignore[attr-defined]  # numba's, undocumented
_lock = threading.Lock()
_done = threading.Condition(_lock)  # a job of the helper's is done


class _Helper:
    """The helper process: compiles (module, name, types) jobs in order into the cache and
    says which are done."""

    def __init__(self) -> None:
        root = str(Path(__file__).resolve().parents[2])  # numba's cache is keyed on the sources
        code = f"import sys; sys.path.insert(0, {root!r}); import armik.kernel.tier as t; t.serve()"
        self.process = subprocess.Popen(
            [sys.executable, "-c", code],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            env={**os.environ, ENVIRONMENT: "compile"},
        )
        self.pid = os.getpid()  # the process it answers (not a fork of it)
        self.jobs: dict[tuple, str] = {}  # (id(function), types) -> "compiling" | "done"
        self.order: list[tuple] = []  # the jobs' keys by their numbers
        self.functions: list[Dispatcher] = []  # and their functions
        threading.Thread(target=self._read, name="armik-compile-helper", daemon=True).start()

    def send(self, key: tuple, dispatcher: Dispatcher, types: tuple) -> bool:
        f = dispatcher.py_func
        job = (len(self.order), f.__module__, f.__qualname__, types)
        try:
            pickle.dump(job, self.process.stdin)  # type: ignore[arg-type]
            self.process.stdin.flush()  # type: ignore[union-attr]
        except (OSError, pickle.PicklingError, TypeError, AttributeError):
            return False
        self.jobs[key] = "compiling"
        self.order.append(key)
        self.functions.append(dispatcher)
        return True

    def _read(self) -> None:
        for line in self.process.stdout or ():
            number = int(line.split()[0])
            with _done:
                self.jobs[self.order[number]] = "done"
                _done.notify_all()
        with _done:  # the helper ended (or failed): nothing more will be done by it
            for key, state in self.jobs.items():
                if state == "compiling":
                    self.jobs[key] = "done"  # numba's own compile takes over
            _done.notify_all()


_helper: _Helper | None = None


def _compile_for_args(self: Dispatcher, *args: Any, **kws: Any) -> Callable:
    """numba's ``_compile_for_args``, with first calls of armik functions run as Python."""
    if kws or not is_armik(self) or os.environ.get(ENVIRONMENT) == "compile":
        return _COMPILE(self, *args, **kws)
    try:
        types = tuple(_type_of(self, a) for a in args)
    except Exception:  # numba's own call reports it
        return _COMPILE(self, *args, **kws)
    key = (id(self), types)
    with _lock:
        helper = _helper if _helper is not None and _helper.pid == os.getpid() else None
        state = None if helper is None else helper.jobs.get(key)
    if state == "compiling":
        return run(self)
    if state == "done" or _large(args) or _cached(self, types):
        return _COMPILE(self, *args, **kws)
    if os.environ.get(ENVIRONMENT) == "python":  # Python only, never compiled (the tests')
        return run(self)
    if not _start(key, self, types):
        return _COMPILE(self, *args, **kws)
    in_background(self.py_func.__module__, self.py_func.__qualname__)
    return run(self)


def _start(key: tuple, dispatcher: Dispatcher, types: tuple) -> bool:
    global _helper
    with _lock:
        if _helper is None or _helper.pid != os.getpid():  # a forked process starts its own
            if not helper_allowed():
                return False
            try:
                _helper = _Helper()
            except OSError:
                return False
        return _helper.send(key, dispatcher, types)


@contextlib.contextmanager
def compiling() -> Iterator[None]:
    """A block whose first calls compile in this process, as numba does (``armik.compile``:
    what it calls is to be compiled, not run)."""
    before = os.environ.get(ENVIRONMENT)
    os.environ[ENVIRONMENT] = "compile"
    try:
        yield
    finally:
        if before is None:
            del os.environ[ENVIRONMENT]
        else:
            os.environ[ENVIRONMENT] = before


def wait(timeout: float | None = None) -> bool:
    """Wait until the helper has compiled every function sent to it so far (a program that
    wants compiled speed from here on, a test); False if ``timeout`` s passed first."""
    with _done:
        return _done.wait_for(
            lambda: _helper is None or "compiling" not in _helper.jobs.values(), timeout
        )


def ran_as_python() -> list[Dispatcher]:
    """The functions this process sent to its helper, in order."""
    with _lock:
        return [] if _helper is None else list(_helper.functions)


def python_first() -> bool:
    """Whether first calls run as Python while the helper compiles (see the module)."""
    setting = os.environ.get(ENVIRONMENT)
    return setting == "python" or (setting != "compile" and helper_allowed())


def helper_allowed() -> bool:
    """Whether a helper process may start: ``ARMIK_COMPILE_HELPER`` says so ("0" or "1"),
    else two CPUs are usable and ``sys.executable`` is an interpreter (not an application
    that embeds Python)."""
    setting = os.environ.get(HELPER)
    if setting in ("0", "1"):
        return setting == "1"
    if getattr(sys, "frozen", False) or not Path(sys.executable).name.lower().startswith("python"):
        return False
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cpus = os.cpu_count() or 1
    return cpus >= 2


def _type_of(dispatcher: Dispatcher, value: Any) -> Any:
    """numba's type of ``value``; an array's by numba's own rule without its first step,
    the check for a masked array, whose import of ``numpy.ma`` takes 50-70 ms, most of a
    target beyond reach's first solve."""
    if type(value) is np.ndarray:
        dtype = numpy_support.from_dtype(value.dtype)
        layout = numpy_support.map_layout(value)
        return numba_types.Array(dtype, value.ndim, layout, readonly=not value.flags.writeable)
    return dispatcher.typeof_pyval(value)


def _large(args: tuple) -> bool:
    return any(isinstance(a, np.ndarray) and a.size > LARGEST for a in args)


def _cached(dispatcher: Dispatcher, types: tuple) -> bool:
    """Whether numba's cache holds ``dispatcher`` for ``types``: its index only, not the
    code (numba's own lookup, through attributes numba does not document: anything
    unexpected counts as cached, so that numba's own call goes on)."""
    try:
        cache = dispatcher._cache  # type: ignore[attr-defined]
        key = cache._index_key(types, dispatcher.targetctx.codegen())  # type: ignore[attr-defined]
        return key in cache._cache_file._load_index()
    except Exception:
        return True


def serve() -> None:
    """The helper process: each job read from stdin compiled into the cache, its number
    written when done. It goes on after its reader is gone, and ends with its input."""
    import importlib

    number = 0
    while True:
        try:
            _, module, qualname, types = pickle.load(sys.stdin.buffer)
        except EOFError:
            return
        try:
            target = importlib.import_module(module)
            for part in qualname.split("."):
                target = getattr(target, part)
            target.compile(types)
        except Exception:
            pass  # the process that asked compiles it itself
        try:
            print(number, flush=True)
        except (BrokenPipeError, OSError):
            pass
        number += 1


def install() -> None:
    """Put the hook where numba compiles for a call from Python (once)."""
    Dispatcher._compile_for_args = _compile_for_args  # type: ignore[attr-defined]
