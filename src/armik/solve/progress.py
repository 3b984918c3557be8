"""Progress of a long call: a one-line bar on stderr, the caller's callback, or nothing."""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable

from armik.errors import OptionError

ProgressArg = bool | Callable[[int, int], None] | None


class Progress:
    """A one-line progress bar on stderr, redrawn at most every 0.1 s."""

    def __init__(self, label: str, total: int, stream=None) -> None:
        self.label, self.total = label, total
        self.stream = stream if stream is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.last = -math.inf

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        if now - self.last < 0.1 and done < total:
            return
        self.last = now
        frac = done / total if total else 1.0
        filled = int(30 * frac)
        rate = done / (now - self.t0) if now > self.t0 else 0.0
        self.stream.write(
            f"\r{self.label:<20} [{'#' * filled}{'.' * (30 - filled)}] {done}/{total} "
            f"({rate:,.0f}/s)"
        )
        self.stream.flush()

    def close(self) -> None:
        self.stream.write("\n")
        self.stream.flush()


class _Callback:
    def __init__(self, fn: Callable[[int, int], None] | None) -> None:
        self.fn = fn

    def __call__(self, done: int, total: int) -> None:
        if self.fn is not None:
            self.fn(done, total)

    def close(self) -> None:
        pass


def make_progress(progress: ProgressArg, total: int, label: str):
    """A progress reporter ``(done, total)`` with ``close()``: a bar (True, or None with
    stderr on a terminal), the caller's callable, or nothing."""
    found = reporter(progress, total, label)
    return _Callback(None) if found is None else found


def reporter(progress: ProgressArg, total: int, label: str) -> Progress | _Callback | None:
    """``make_progress``'s reporter, or None where nothing is reported (False, or None with
    stderr not on a terminal): a caller that checks for None calls nothing per step."""
    if progress is None:
        progress = sys.stderr.isatty()
    if progress is True:
        return Progress(label, total)
    if progress is False:
        return None
    if callable(progress):
        return _Callback(progress)
    raise OptionError(
        f"progress must be True, False, None or a callable (done, total), got {progress!r}",
        option="progress",
        value=progress,
    )
