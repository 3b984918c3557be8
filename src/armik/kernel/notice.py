"""A one-line notice on stderr while armik's compiled code is built for this machine.

numba compiles a kernel at its first call and keeps the machine code in its on-disk cache;
later processes load it in milliseconds. A first call that compiles can take seconds, so
armik says so, once per part and process: "armik: compiling the numeric solvers for this
machine (once; about 25 s on a quiet 2-core machine); `armik compile dls qp batch tasks`
builds it ahead of time" (``COMMANDS``: the parts of ``armik compile`` that build it). On a
terminal the line counts the seconds and ends with the time taken. A call served from the
cache says nothing; the FK check, which compiles with a solve, says nothing of its own,
nor does the conversion of joint values to Pinocchio's (an arm with continuous joints: its
first call of anything), which compiles in well under a second.

numba announces only real compilations ("numba:compile" events, not cache loads); the
first outermost one of an armik function in a burst names the part. How long it takes is
measured: each line's time is kept in ``compile-seconds.json`` in the user's cache
directory (``ARMIK_COMPILE_TIMES`` names another file), under its part and the function
that began it (``record_key``), and the next such notice on this machine (a new cache, an
upgrade) says it; a burst never measured here says ``PARTS``' figure from the project's
2-core machine, as such.
``ARMIK_COMPILE_NOTICE=0`` in the environment silences the notice. ``armik.compile``
(``armik compile``) builds every part ahead of time.
"""

from __future__ import annotations

import atexit
import contextlib
import json
import os
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

from numba.core import event
from numba.core.dispatcher import LiftedCode

ENVIRONMENT = "ARMIK_COMPILE_NOTICE"  # "0": no notice

# (module prefix, what it is, about how long its first call compiles (s): measured with
# benchmarks/compile_time.py on an empty cache of this project's 2-core machine, rounded up)
PARTS = (
    ("armik.kernel.measure", "the forward-kinematics check", 2),
    ("armik.kernel.coordinates", "the joint-value conversion", 1),
    ("armik.kernel.fk_many", "the batch forward kinematics", 3),
    ("armik.kernel.ladder", "the global path plan", 10),
    ("armik.kernel.task_rows", "the task solver's descent", 10),
    ("armik.servo", "the servo's tick", 35),
    ("armik.kernel", "the numeric solvers", 25),
    ("armik.solvers.closed_form.spherical_wrist", "the spherical-wrist closed form", 20),
    ("armik.solvers.closed_form.three_parallel", "the three-parallel-axes closed form", 15),
    ("armik.solvers.closed_form.spherical_general", "the general spherical-wrist closed form", 30),
    ("armik.solvers.closed_form.spherical_shoulder", "the spherical-shoulder closed form", 20),
    ("armik.solvers.closed_form.three_parallel_general", "the general 3-parallel closed form", 30),
    # both searches' compiled code is shared (search_zeros calls search_1d, search_q1, _q4)
    ("armik.solvers.closed_form.search_zeros", "the one-dimensional searches", 50),
    ("armik.solvers.closed_form.search_1d", "the one-dimensional searches", 50),
    ("armik.solvers.closed_form.search_q1", "the one-dimensional searches", 50),
    ("armik.solvers.closed_form.search_q4", "the one-dimensional searches", 50),
    ("armik.solvers.closed_form.swept_7r", "the swept 7R closed form", 10),
    ("armik.solvers.closed_form.srs_kernel", "the SRS 7R closed form", 10),
    ("armik.solvers.closed_form.general_6r", "the general 6R search", 15),
    ("armik.solvers.closed_form.elimination", "the 6R elimination", 15),
    ("armik.solvers.closed_form.elimination_roots", "the 6R elimination", 15),
    ("armik.solvers.closed_form.planar2r_kernel", "the planar 2-link closed form", 3),
    ("armik.solvers.closed_form", "the 6R closed forms' shared code", 5),
    ("armik.constraints", "the collision checks' bounds", 3),
    ("armik", "armik's compiled code", 5),
)
_CHECK = PARTS[0][1]  # the forward-kinematics check
_CONVERSION = PARTS[1][1]  # joint values to Pinocchio's: said by no line of its own
# what each part's line tells to run to build it ahead of time: ``armik compile``'s parts
# (``armik.precompile.PARTS``) whose calls compile it; where none is named, every part
_NUMERIC = "dls qp batch tasks"  # a solve, a batch, a tip-only task list lower to its entries
COMMANDS = {
    "the batch forward kinematics": "fk_batch",
    "the global path plan": "path",
    "the task solver's descent": "tasks",
    "the servo's tick": "servo",
    "the numeric solvers": _NUMERIC,
    "the spherical-wrist closed form": "spherical",
    "the three-parallel-axes closed form": "three_parallel",
    "the general spherical-wrist closed form": "spherical_general",
    "the spherical-shoulder closed form": "spherical_shoulder",
    "the general 3-parallel closed form": "three_parallel_general",
    "the one-dimensional searches": "search_1d",
    "the swept 7R closed form": "swept",
    "the SRS 7R closed form": "srs",
    "the general 6R search": "general_6r",
    "the 6R elimination": "elimination_6r",
    "the planar 2-link closed form": "planar2r",
    "the collision checks' bounds": "collisions",
}


def command(what: str) -> str:
    """The command that builds part ``what`` ahead of time: ``armik compile`` with the
    parts whose calls compile it (every part where ``COMMANDS`` names none)."""
    parts = COMMANDS.get(what)
    return f"armik compile {parts}" if parts else "armik compile"


BURST_GAP = 1.0  # s: compilations this close together are one wait, told in one line


def part_of(module: str) -> tuple[str, float]:
    """(what, about how many seconds) of the part a compiled function's module belongs to."""
    for prefix, what, seconds in PARTS:
        if module == prefix or module.startswith(prefix + "."):
            return what, seconds
    return "armik's compiled code", 5.0


class _Notice(event.Listener):
    """Tells when armik functions compile: one line per burst of outermost compilations
    (a first call compiles several functions in a row, the FK check among them), named
    after the first."""

    def __init__(self, stream=None) -> None:
        self.stream = stream
        self.depth = 0  # nested compilations (callees) inside the outermost one
        self.holds = 0  # ``held`` blocks open: the line stays open through them
        self.line: _Line | None = None
        self.closing: threading.Timer | None = None
        self.lock = threading.Lock()

    def on_start(self, ev: event.Event) -> None:
        self.depth += 1
        if self.depth > 1 or os.environ.get(ENVIRONMENT, "1") == "0":
            return
        dispatcher = ev.data["dispatcher"]
        if isinstance(dispatcher, LiftedCode):
            return  # an objmode block, lifted again in each process at its first run: fast
        func = getattr(dispatcher, "py_func", None)
        module = getattr(func, "__module__", "") or ""
        if not module.startswith("armik"):
            return
        what, seconds = part_of(module)
        if what == _CONVERSION:  # under a second: within another part's line or none
            return
        key = record_key(what, f"{module}.{getattr(func, '__qualname__', '')}")
        with self.lock:
            if self.closing is not None:
                self.closing.cancel()
                self.closing = None
            # the FK check compiles within the solves' bursts: it goes on under their line
            if self.line is not None and what not in (self.line.what, _CHECK):
                record(self.line.key, self.line.close())
                self.line = None
            if self.line is None:
                stream = self.stream or sys.stderr
                self.line = _Line(what, seconds, stream, measured().get(key), key)

    def on_end(self, ev: event.Event) -> None:
        self.depth -= 1
        if self.depth == 0:
            self._close_soon()

    def _close_soon(self) -> None:
        """Close the line after ``BURST_GAP`` unless a compilation or a hold comes first."""
        with self.lock:
            if self.line is not None:
                self.line.ended = time.perf_counter()  # the burst's time so far
            if self.line is not None and self.closing is None and not self.holds:
                self.closing = threading.Timer(BURST_GAP, self._close)
                self.closing.daemon = True
                self.closing.start()

    @contextlib.contextmanager
    def held(self) -> Iterator[None]:
        """A block that is part of the burst whatever its pauses (waiting for the compile
        helper between compilations): the line stays open through it, and is said once."""
        with self.lock:
            self.holds += 1
            if self.closing is not None:
                self.closing.cancel()
                self.closing = None
        try:
            yield
        finally:
            with self.lock:
                self.holds -= 1
            if self.depth == 0:
                self._close_soon()

    def _close(self) -> None:
        with self.lock:
            if self.line is not None:
                record(self.line.key, self.line.close())
                self.line = None
            self.closing = None


class _Line:
    """The notice's line: written at once; on a terminal, redrawn with the seconds so far."""

    def __init__(
        self, what: str, seconds: float, stream, here: float | None = None, key: str = ""
    ) -> None:
        self.what = what
        self.key = key or what  # what its time is kept under
        if here is not None:  # measured on this machine
            took = f"it took {here:.0f} s here last time"
        else:
            took = f"about {seconds:g} s on a quiet 2-core machine"
        ahead = f"`{command(what)}` builds it ahead of time"
        self.text = f"armik: compiling {what} for this machine (once; {took}); {ahead}"
        self.stream = stream
        self.t0 = time.perf_counter()
        self.ended = self.t0  # when its last compilation (or hold) ended
        self.live = _is_terminal(stream)
        self.done = threading.Event()
        self._write(self.text + ("" if self.live else "\n"))
        if self.live:
            threading.Thread(target=self._tick, name="armik-compile-notice", daemon=True).start()

    def _tick(self) -> None:
        while not self.done.wait(0.5):
            self._write(f"\r{self.text}: {time.perf_counter() - self.t0:.0f} s")

    def close(self) -> float:
        """End the line; returns the seconds of its burst (to its last compilation's end)."""
        self.done.set()
        took = max(self.ended, self.t0) - self.t0
        if self.live:
            self._write(f"\r{self.text}: done in {took:.1f} s\n")
        return took

    def _write(self, text: str) -> None:
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):  # a closed or broken stream: the notice is optional
            pass


TIMES = "compile-seconds.json"  # record_key -> seconds its last notice's line was open


_BACKGROUND: set[str] = set()  # the parts said to compile in the background


def in_background(module: str, name: str) -> None:
    """Say, once per part and process, that the part of ``module``'s function ``name``
    compiles in a helper process and that calls run as Python until it is done
    (``kernel.tier``)."""
    what, seconds = part_of(module)
    if os.environ.get(ENVIRONMENT, "1") == "0" or what in _BACKGROUND or what == _CONVERSION:
        return
    if what == _CHECK and _BACKGROUND:  # it compiles with the solve said before: one line
        return
    _BACKGROUND.add(what)
    here = measured().get(record_key(what, f"{module}.{name}"))  # the helper's, last time
    took = f"{here:.0f} s here last time" if here and here >= 1 else f"about {seconds:g} s"
    try:
        sys.stderr.write(
            f"armik: compiling {what} for this machine in the background (once; {took}); "
            f"until then they run as Python, slower; `{command(what)}` builds them ahead of "
            "time\n"
        )
    except (OSError, ValueError):
        pass


def record_key(what: str, first: str) -> str:
    """What a burst's time is kept under: its part and the function that began it. A part
    compiles more or less of itself as its cache is empty or partly filled (a weighted
    solve after a plain one compiles only its own entry); a burst that begins at the same
    function compiles the same functions, so its last time is the one to say."""
    return f"{what}, from {first}"


TIMES_ENVIRONMENT = "ARMIK_COMPILE_TIMES"  # the file, where not the user's cache directory


def times_path() -> Path:
    """Where the measured compile times are kept: ``ARMIK_COMPILE_TIMES`` when set, else
    the user's cache directory (one file per user and machine, whatever numba's cache)."""
    given = os.environ.get(TIMES_ENVIRONMENT)
    if given:
        return Path(given)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "armik" / TIMES


def measured() -> dict[str, float]:
    """The compile times measured on this machine, by part (empty when none or unreadable)."""
    try:
        got = json.loads(times_path().read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    if not isinstance(got, dict):
        return {}
    return {k: float(v) for k, v in got.items() if isinstance(v, (int, float))}


def record(what: str, seconds: float) -> None:
    """Keep ``seconds`` as the time of part ``what`` (the notice is optional: a file that
    cannot be written is left as it is)."""
    path = times_path()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        times = {**measured(), what: round(seconds, 1)}
        tmp = path.with_name(f"{path.name}.{os.getpid()}")
        tmp.write_text(json.dumps(times, indent=1, sort_keys=True), encoding="utf-8")
        os.replace(tmp, path)
    except OSError:
        pass


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


NOTICE = _Notice()
event.register("numba:compile", NOTICE)
atexit.register(NOTICE._close)  # a line still open at exit (its timer never ran): kept too
