"""The solving thread's CPU time as the solve budgets count it.

A budget's ``timeout`` is CPU seconds of the solving thread at compiled speed. While a
kernel runs as Python instead (a first call, while a helper process compiles it:
``kernel.tier``), it takes ``as_python.SLOWER`` times longer; the kernel's own clock is
slowed alike, and so is this one: ``thread_time()`` is ``time.thread_time()`` less what
the Python runs of this thread took beyond their compiled time. Python code between
kernels counts at its own speed, as it always does. So a first call gets the work of a
compiled one (the same restarts, the same answer), only later.
"""

from __future__ import annotations

import threading
import time

_beyond = threading.local()  # .seconds: what this thread's Python runs took beyond compiled


def thread_time() -> float:
    """CPU seconds of the calling thread as budgets count them (see the module)."""
    return time.thread_time() - getattr(_beyond, "seconds", 0.0)


def slowed(seconds: float) -> None:
    """Count ``seconds`` of this thread's CPU time as not spent (a Python run's excess)."""
    _beyond.seconds = getattr(_beyond, "seconds", 0.0) + seconds
