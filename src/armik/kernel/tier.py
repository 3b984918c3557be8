"""First calls answered at once: run as Python while a helper process compiles them.

numba compiles a function at its first call with new argument types, and a solver takes
10-25 s to compile on a 2-core machine; the cache then serves every later process. Run as
Python instead (``as_python``), the same kernels answer a first solve in milliseconds
(a Panda dls solve in 2-10 ms). So when an armik function is called from Python with
argument types neither compiled in this process nor in numba's cache, this module:

- sends the function and its types to a helper process (started at the first such call),
  which compiles them into the cache, one after the other;
- runs this call, and every call of the same function and types until the helper is done,
  as Python;
- at the first call after the helper is done, loads the compiled code from the cache (a
  fraction of a second), which every later call runs, as if it had compiled here.

The helper ends once it has compiled all it was sent (a later first call starts another).
It runs in a session of its own: a program that ends or is interrupted (Ctrl-C) before it
is done leaves it to finish, so the next process finds the cache filled. Helpers of
several processes take turns on a lock file beside the cache and skip what another has
compiled meanwhile: one compiles at a time. A call over large arrays (a batch of many
targets: more than ``LARGEST`` values in one argument) compiles here first, as before: it
would run longer as Python than the compile takes. The hook sits where numba asks a
function to compile for a call from Python (``Dispatcher._compile_for_args``), so a call
of compiled code (the hot path) never passes through it.

Python runs instead of waiting only where a helper may start (two CPUs, an interpreter
to start it with: ``helper_allowed``); ``ARMIK_FIRST_CALLS=compile`` in the environment
turns it off (the tests do, so that their timing is the compiled code's), and so does a
``compiling()`` block (``armik compile``, the benchmarks); ``ARMIK_FIRST_CALLS=python``
runs every call not in the cache as Python and starts no helper (the tests of the Python
runs).
"""

from __future__ import annotations

import contextlib
import os
import pickle
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
from numba.core import types as numba_types
from numba.core.dispatcher import Dispatcher
from numba.np import numpy_support

from armik.kernel import notice
from armik.kernel.as_python import is_armik, run

# "compile": compile at the first call, as numba does; "python": run as Python, no helper
ENVIRONMENT = "ARMIK_FIRST_CALLS"
HELPER = "ARMIK_COMPILE_HELPER"  # "0": no helper process, "1": one even on one CPU
LARGEST = 65536  # values in one array argument: a call over more compiles first
DONE = "armik-compiled"  # the helper's line for a job done (its other output is ignored)
LOCK = "armik-compile.lock"  # the helpers' turns, beside the cache

_COMPILE = Dispatcher._compile_for_args  # type: ignore[attr-defined]  # numba's, undocumented


class _State:
    """This process's jobs and helper (a forked process starts with none)."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.done = threading.Condition(self.lock)  # a job of the helper's is done
        self.jobs: dict[tuple, str] = {}  # (function, types) -> "compiling" | "done"
        self.functions: list[Dispatcher] = []  # the functions sent, in order
        self.helper: _Helper | None = None  # the helper at work, if any
        self.compiling = 0  # ``compiling()`` blocks open


_state = _State()
os.register_at_fork(after_in_child=lambda: globals().update(_state=_State()))


class _Helper:
    """A helper process: compiles (module, name, types) jobs in order into the cache, says
    which are done, and ends when its input does (``_read`` closes it when all are done)."""

    def __init__(self) -> None:
        root = str(Path(__file__).resolve().parents[2])  # numba's cache is keyed on the sources
        code = f"import sys; sys.path.insert(0, {root!r}); import armik.kernel.tier as t; t.serve()"
        self.process = subprocess.Popen(
            [sys.executable, "-c", code],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            env={**os.environ, ENVIRONMENT: "compile", notice.ENVIRONMENT: "0"},
            start_new_session=True,  # Ctrl-C on the program leaves it to finish
        )
        self.sent: list[tuple] = []  # the keys of its jobs, by number
        threading.Thread(target=self._read, name="armik-compile-helper", daemon=True).start()

    def send(self, key: tuple, dispatcher: Dispatcher, types: tuple) -> bool:
        f = dispatcher.py_func
        job = (len(self.sent), f.__module__, f.__qualname__, types)
        try:
            pickle.dump(job, self.process.stdin)  # type: ignore[arg-type]
            self.process.stdin.flush()  # type: ignore[union-attr]
        except (OSError, ValueError, pickle.PicklingError, TypeError, AttributeError):
            return False
        self.sent.append(key)
        return True

    def _read(self) -> None:
        state = _state
        for line in self.process.stdout or ():
            words = line.split()
            if len(words) != 2 or words[0] != DONE.encode():
                continue  # numba's own output (NUMBA_DEBUG_CACHE=1, ...)
            with state.done:
                state.jobs[self.sent[int(words[1])]] = "done"
                if all(state.jobs[k] == "done" for k in self.sent) and state.helper is self:
                    state.helper = None  # a new job starts a new helper
                    self.process.stdin.close()  # type: ignore[union-attr]  # it ends
                state.done.notify_all()
        with state.done:  # it ended (or failed): what it did not do, numba's call does
            for key in self.sent:
                state.jobs[key] = "done"
            if state.helper is self:
                state.helper = None
            state.done.notify_all()


def _compile_for_args(self: Dispatcher, *args: Any, **kws: Any) -> Callable:
    """numba's ``_compile_for_args``, with first calls of armik functions run as Python."""
    setting = os.environ.get(ENVIRONMENT)
    if kws or setting == "compile" or _state.compiling or not is_armik(self):
        return _COMPILE(self, *args, **kws)
    try:
        types = tuple(_type_of(self, a) for a in args)
    except Exception:  # numba's own call reports it
        return _COMPILE(self, *args, **kws)
    key, state = (self, types), _state
    with state.lock:
        known = state.jobs.get(key)
        if known is None and not _large(args) and not cached(self, types):
            if setting == "python":  # Python only, never compiled (the tests')
                return run(self)
            if _send(state, key, self, types):
                known = "sent"
    if known == "sent":
        notice.in_background(self.py_func.__module__, self.py_func.__qualname__)
    if known in ("sent", "compiling"):
        return run(self)
    return _COMPILE(self, *args, **kws)


def _send(state: _State, key: tuple, dispatcher: Dispatcher, types: tuple) -> bool:
    """Send a job to the helper, starting one if none is at work (under ``state.lock``)."""
    if state.helper is None:
        if not helper_allowed():
            return False
        try:
            state.helper = _Helper()
        except OSError:
            return False
    if not state.helper.send(key, dispatcher, types):
        return False
    state.jobs[key] = "compiling"
    state.functions.append(dispatcher)
    return True


@contextlib.contextmanager
def compiling() -> Iterator[None]:
    """A block (or, as a decorator, a function) whose first calls compile in this process,
    as numba does: ``armik compile``, and the benchmarks, which time compiled code."""
    with _state.lock:
        _state.compiling += 1
    try:
        yield
    finally:
        with _state.lock:
            _state.compiling -= 1


def wait(timeout: float | None = None) -> bool:
    """Wait until the helper has compiled every function sent to it so far (a program that
    wants compiled speed from here on, a test); False if ``timeout`` s passed first."""
    state = _state
    with state.done:
        return state.done.wait_for(lambda: "compiling" not in state.jobs.values(), timeout)


def ran_as_python() -> list[Dispatcher]:
    """The functions this process sent to a helper, in order."""
    with _state.lock:
        return list(_state.functions)


def python_first() -> bool:
    """Whether first calls run as Python while the helper compiles (see the module)."""
    setting = os.environ.get(ENVIRONMENT)
    if setting == "compile" or _state.compiling:
        return False
    return setting == "python" or helper_allowed()


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


def cached(dispatcher: Dispatcher, types: tuple) -> bool:
    """Whether numba's cache holds ``dispatcher`` for ``types``: its entry's header only,
    not the code (numba's own key, through attributes numba does not document: anything
    unexpected counts as cached, so that numba's own call goes on)."""
    try:
        cache = dispatcher._cache  # type: ignore[attr-defined]
        key = cache._index_key(types, dispatcher.targetctx.codegen())  # type: ignore[attr-defined]
        return bool(cache._cache_file.holds(key))  # ``compiled_cache.Entries``
    except Exception:
        return True


@contextlib.contextmanager
def _turn() -> Iterator[None]:
    """This helper's turn among the helpers of every process on this cache (a lock file
    where numba's cache is, else where the compile times are kept; no turns where the
    platform has no ``fcntl`` or the file cannot be opened)."""
    try:
        import fcntl

        folder = Path(os.environ.get("NUMBA_CACHE_DIR") or notice.times_path().parent)
        folder.mkdir(parents=True, exist_ok=True)
        file = open(folder / LOCK, "a")  # noqa: SIM115  # held across the yield
    except (ImportError, OSError):
        yield
        return
    with file:
        fcntl.flock(file, fcntl.LOCK_EX)
        yield  # closing the file gives the turn back


def serve() -> None:
    """The helper process: each job read from stdin compiled into the cache (in its turn,
    unless another helper has meanwhile), ``DONE`` and its number written when done. It
    goes on after its reader is gone, and ends with its input."""
    import importlib

    while True:
        try:
            number, module, qualname, types = pickle.load(sys.stdin.buffer)
        except EOFError:
            return
        try:
            target: Any = importlib.import_module(module)
            for part in qualname.split("."):
                target = getattr(target, part)
            with _turn():
                if not cached(target, types):
                    t0 = time.perf_counter()
                    target.compile(types)
                    what = notice.part_of(module)[0]
                    key = notice.record_key(what, f"{module}.{qualname}")
                    notice.record(key, time.perf_counter() - t0)
        except Exception:
            pass  # the process that asked compiles it itself
        try:
            print(DONE, number, flush=True)
        except (BrokenPipeError, OSError):
            pass


def install() -> None:
    """Put the hook where numba compiles for a call from Python (once)."""
    Dispatcher._compile_for_args = _compile_for_args  # type: ignore[attr-defined]
