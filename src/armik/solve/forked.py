"""A batch's chunks on forked worker processes, for work that holds the GIL.

Threads solve a batch side by side only while its compiled kernels run: a collision check
(coal, called from Python) and a solver run target by target hold the GIL, and on two
threads such a batch runs no faster than on one, or slower as the threads wait for each
other (docs/batch.md). A forked child starts with the parent's memory: the arm, its
compiled code and its collision checker, shared page by page until written, so it starts in
milliseconds and loads nothing. The parent works too; every process takes the next chunk
from a shared counter, a child sends each chunk's rows back through a pipe, and the parent
puts them in place and reports them.

Fork is used only where it is safe: on Linux, and when the calling process runs one
thread. A fork copies only the thread that calls it, so a lock some other thread held
would stay locked in the child for ever; with other threads alive, the batch runs on
threads instead (``usable``).
"""

from __future__ import annotations

import multiprocessing
import pickle
import sys
import threading
from collections.abc import Callable, Sequence
from multiprocessing.connection import Connection, wait
from typing import TypeVar, cast

from armik.errors import ArmikError

T = TypeVar("T")  # what a chunk's work returns and collect takes


def usable() -> bool:
    """Whether chunks may go to forked processes here: Linux (macOS can fork, but its
    system libraries, Accelerate among them, are not safe to use in a forked child) and
    this process runs one thread."""
    return sys.platform.startswith("linux") and threading.active_count() == 1


def run(
    work: Callable[[int], T],
    starts: Sequence[int],
    workers: int,
    collect: Callable[[int, T], None],
) -> None:
    """``collect(start, work(start))`` in this process for every ``start``, the work shared
    with ``workers - 1`` forked children; ``collect`` runs in this process only, in the
    order the chunks finish. An exception of ``work`` in a child is raised here."""
    ctx = multiprocessing.get_context("fork")
    taken = ctx.Value("q", 0)  # the next chunk to take, shared by every process
    children = []
    done = False
    try:
        for _ in range(workers - 1):
            receive, send = ctx.Pipe(duplex=False)
            child = ctx.Process(
                target=_child, args=(work, starts, taken, send), daemon=True, name="armik"
            )
            child.start()
            send.close()  # the child's end: the pipe reads as closed when the child ends
            children.append((child, receive))
        open_ = {receive: child for child, receive in children}
        while (k := _take(taken, len(starts))) is not None:
            collect(starts[k], work(starts[k]))
            _receive(open_, collect, block=False)
        while open_:
            _receive(open_, collect, block=True)
        done = True
    finally:  # an error here or Ctrl-C: no child outlives the call
        for child, receive in children:
            receive.close()
            if done:  # it said it is done and is ending: multiprocessing reaps it later
                continue  # (joining its exit cost 5-6 ms a batch, a tenth of 1000 targets')
            if child.is_alive():
                child.terminate()
            child.join()


def _take(taken, n: int) -> int | None:
    """The index of the next chunk nobody has taken, or None when all are taken."""
    with taken.get_lock():
        k = taken.value
        if k >= n:
            return None
        taken.value = k + 1
    return k


def _child(work, starts, taken, send) -> None:
    try:
        while (k := _take(taken, len(starts))) is not None:
            send.send((starts[k], work(starts[k])))
        send.send(_DONE)
    except BaseException as error:  # noqa: BLE001 - every failure goes to the parent
        try:
            pickle.loads(pickle.dumps(error))  # it must come back whole, or as its text
            send.send(_Failed(error))
        except Exception:
            send.send(_Failed(ArmikError(f"a batch worker process failed: {error!r}")))
    finally:
        send.close()


_DONE = "done"


class _Failed:
    def __init__(self, error: BaseException) -> None:
        self.error = error


def _receive(open_: dict, collect, block: bool) -> None:
    """Collect what the children have sent (with ``block``, wait for at least one message
    or end); a child that ended or failed is closed and removed from ``open_``."""
    for ready in wait(list(open_), timeout=None if block else 0):
        receive = cast(Connection, ready)  # a key of open_: a pipe's receiving end
        child = open_[receive]
        try:
            message = receive.recv()
        except EOFError:  # ended without a word: killed, or out of memory
            child.join()
            raise ArmikError(
                f"a batch worker process ended unexpectedly (exit code {child.exitcode}); "
                "run the batch with workers=1 to see the error"
            ) from None
        if message == _DONE:
            del open_[receive]
        elif isinstance(message, _Failed):
            raise message.error
        else:
            collect(*message)
