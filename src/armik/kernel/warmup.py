"""A cold first solve compiled on two cores: the step in a helper process, the rest here.

The first numeric solve on a machine compiles the kernel into numba's on-disk cache: the
pose error and its Jacobian (``error._evaluate``), the step (``step.dls`` or ``step.qp``),
the restarts (``restarts._pick``), then the entry that holds the descent and calls them.
The step and the pose error do not depend on each other. When the step is not in the cache
and a second CPU is free, ``prepare`` starts a helper process that compiles the step (then
the verification's ``check.placement_check``) into the cache, while this process compiles the
pose error and the restarts; the entry then loads the step from the cache instead of
compiling it. The functions, their types and their machine code are the ones a single
process would build (the same cache entries); only the wall time changes
(``benchmarks/compile_time.py``). PyTorch's ``torch.compile`` likewise compiles in worker
processes.

``prepare(kind)`` runs once per process and step, before the first call of an entry with
that step; ``start(kind)`` starts the helper earlier, for a program with other work to do
first. It starts no helper when the step is in the cache already, when this process
has compiled its share already (a qp solve after a dls one), when only one CPU is usable,
or when Python is embedded in an application (``sys.executable`` is no interpreter);
``ARMIK_COMPILE_HELPER=0`` in the environment turns the helper off, ``=1`` starts it even
on one CPU. A helper that cannot start or fails costs nothing but its CPU: this process
then compiles the step itself, as it would without it.
"""

from __future__ import annotations

import subprocess
import sys
import threading
from pathlib import Path

import numpy as np

from armik.kernel import error, restarts, step
from armik.kernel import measure as check
from armik.kernel.chain import Flat
from armik.kernel.descent import _add_solution, _near_known_minimum
from armik.kernel.notice import NOTICE
from armik.kernel.problem import STEP_DLS, STEP_QP, _workspace, unpack
from armik.kernel.single import plain_pose, plain_seed
from armik.kernel.tier import cached, helper_allowed, python_first

HELPER_TIMEOUT = 300.0  # s: a helper still silent after this is stopped
STEPS = {STEP_DLS: step.dls, STEP_QP: step.qp}

PREPARED: set[int] = set()  # the steps prepared in this process: a hot caller checks it first
_started: dict[int, subprocess.Popen] = {}  # helpers ``start`` began, for ``prepare``
_lock = threading.Lock()


def start(kind: int) -> None:
    """Start the helper of step ``kind`` now, when ``prepare`` would, and compile nothing in
    this process: ``prepare(kind)`` later does this process's share and waits for it. For
    a program that does other work first (``armik demo``'s 2-link arm), so that the step
    compiles meanwhile and no notice names the numeric solvers before they are used."""
    with _lock:
        if kind in PREPARED or kind in _started or python_first() or not _needs_helper(kind):
            return
        helper = _start_helper(kind)
        if helper is not None:
            _started[kind] = helper


def prepare(kind: int) -> None:
    """Make sure the kernel parts of step ``kind`` (``problem.STEP_DLS`` or ``STEP_QP``)
    are compiled or loaded in this process, the step by a helper process when the cache
    lacks it (see the module). Cheap after the first call."""
    if kind in PREPARED:
        return
    with _lock:
        if kind in PREPARED:
            return
        try:
            if not python_first():  # else a first call runs as Python (``tier``)
                _prepare(kind)
        finally:
            PREPARED.add(kind)


def _needs_helper(kind: int) -> bool:
    """Whether a helper would shorten the first call of step ``kind`` (see the module)."""
    step_types, share = _parts()
    return not (
        not helper_allowed()
        or all(types in dispatcher.overloads for dispatcher, types in share)  # nothing to share
        or cached(STEPS[kind], step_types)
    )  # else the entry compiles or loads everything in order, as always


def _prepare(kind: int) -> None:
    helper = _started.pop(kind, None)
    if helper is None:
        if not _needs_helper(kind):
            return
        helper = _start_helper(kind)
        if helper is None:
            return
    with NOTICE.held():  # one notice line over the share, the wait and the entry after
        for dispatcher, types in _parts()[1]:  # this process's share while the helper works
            dispatcher.compile(types)
        _wait_for(helper, "step")
    # it goes on with the verification in the background: reap it when it ends
    threading.Thread(target=helper.communicate, daemon=True).start()


def _parts() -> tuple[tuple, list]:
    """(the step's argument types, [(compiled function, argument types)] for the other
    parts an entry calls): the numba types the entries pass them. They depend on no arm,
    only on dtypes, dimensions and layouts, which small samples carry
    (tests/kernel/test_warmup.py checks them against what the entries compile)."""
    from numba import typeof

    ch = Flat(np.zeros(1), np.zeros(3, dtype=np.int64), np.zeros((1, 1)))
    sf, si = np.zeros(32), np.zeros(32, dtype=np.int64)  # longer than pack_settings makes
    st = unpack.py_func(sf, si)
    ws = _workspace.py_func(1, 1, 1)
    H = np.eye(4)
    R_t, p_t = check.split_pose.py_func(H)
    q, Q = np.zeros(1), np.zeros((1, 1))
    count = np.int64(0)  # descent.ZERO and what follows from it

    def types(*args):
        return tuple(map(typeof, args))

    share = [
        (error._evaluate, types(ch, st, R_t, p_t, ws, count)),
        (restarts._pick, types(ch, st, R_t, p_t, ws, count, q)),
        (plain_pose, types(H)),
        (plain_seed, types(q, q, q)),
        (unpack, types(sf, si)),
        (_workspace, types(count, count, count)),
        (check.split_pose, types(H)),
        (_add_solution, types(ch, q, q, q, Q, count)),
        (_near_known_minimum, types(ch, q, Q, count)),
    ]
    return types(ch, st, ws, count, q, 1.0), share


def _start_helper(kind: int) -> subprocess.Popen | None:
    # The helper must import these very source files: numba's cache is keyed on them.
    root = str(Path(__file__).resolve().parents[2])
    code = (
        f"import sys; sys.path.insert(0, {root!r}); "
        f"from armik.kernel.warmup import helper; helper({kind})"
    )
    try:
        return subprocess.Popen(
            [sys.executable, "-c", code],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
    except OSError:
        return None


def _wait_for(helper: subprocess.Popen, line: str) -> None:
    """Read the helper's output until ``line`` (it compiled that part), its end, or the
    timeout."""
    timer = threading.Timer(HELPER_TIMEOUT, helper.kill)
    timer.daemon = True
    timer.start()
    try:
        for got in helper.stdout or ():  # a pipe (stdout=PIPE): never None
            if got.strip() == line:
                return
    finally:
        timer.cancel()


def helper(kind: int) -> None:
    """The helper process: the step of ``kind`` into the cache, then the verification."""
    STEPS[kind].compile(_parts()[0])
    print("step", flush=True)
    q = np.zeros(1)
    R_w = np.asfortranarray(np.eye(3))  # as Pinocchio's rotation views are laid out
    check.placement_check(np.zeros(21), R_w, np.zeros(3), np.eye(4), q)  # the plan's types
    print("check", flush=True)
