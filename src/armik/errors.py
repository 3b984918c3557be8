"""One exception tree for everything armik raises.

Input errors also derive from ``ValueError`` so that generic callers can catch them.
An unreachable or unconverged target is never an exception: it is an ``IKResult``
with ``success=False``.
"""

from __future__ import annotations

import difflib
import os
import sys
import warnings
from collections.abc import Callable, Iterable

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


class ArmikError(Exception):
    """Base class of every error armik raises."""

    def __reduce__(self) -> tuple[Callable[..., ArmikError], tuple[object, ...]]:
        # pickled with its fields: the subclasses' fields are keyword-only, which
        # Exception's own pickling (``cls(*args)``) does not pass (a worker process or a
        # cluster sends its errors pickled)
        return (_rebuilt, (type(self), self.args, dict(self.__dict__)))


def _rebuilt(
    cls: type[ArmikError], args: tuple[object, ...], fields: dict[str, object]
) -> ArmikError:
    error = cls.__new__(cls, *args)
    error.args = args
    error.__dict__.update(fields)
    return error


class ArmikWarning(UserWarning):
    """Warnings armik emits (for example a seed clipped into the joint limits)."""


def warn(message: str) -> None:
    """An ``ArmikWarning`` said at the caller's line: the first frame outside armik, however
    deep the route that found it (a fixed ``stacklevel`` named one of armik's own lines on
    every route but the one it was counted on)."""
    frame, level = sys._getframe(0), 1
    while frame.f_back is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, ArmikWarning, stacklevel=level)


class InputError(ArmikError, ValueError):
    """A value passed by the caller is malformed; the message names it and the fix."""


class URDFError(InputError):
    """The robot description cannot be read or does not describe a usable arm."""

    def __init__(self, message: str, *, path: str | None = None) -> None:
        super().__init__(message)
        self.path = path


class FrameError(InputError):
    """An unknown frame, or a base and tip that do not form a chain."""

    def __init__(self, message: str, *, frame: str, candidates: Iterable[str] = ()) -> None:
        super().__init__(message)
        self.frame = frame
        self.candidates = tuple(candidates)


class JointError(InputError):
    """An unknown joint name, or a joint that cannot play the role asked of it."""

    def __init__(self, message: str, *, joint: str, candidates: Iterable[str] = ()) -> None:
        super().__init__(message)
        self.joint = joint
        self.candidates = tuple(candidates)


class TargetError(InputError):
    """A target pose that is not a finite, well-formed pose."""


class OptionError(InputError):
    """A solver option or seed configuration that is out of range or of the wrong shape."""

    def __init__(self, message: str, *, option: str, value: object = None) -> None:
        super().__init__(message)
        self.option = option
        self.value = value


class CollisionError(OptionError):
    """A bad obstacle (a negative size, a NaN pose, a mesh that does not exist), an arm with
    no collision geometry asked for collisions, an obstacle overlapping a link that never
    moves, or an SRDF that cannot be read."""

    def __init__(self, message: str, *, option: str = "obstacles", value: object = None) -> None:
        super().__init__(message, option=option, value=value)


class SolverError(InputError):
    """An unknown solver name, or a solver that does not apply to this arm or target."""

    def __init__(self, message: str, *, solver: str, candidates: Iterable[str] = ()) -> None:
        super().__init__(message)
        self.solver = solver
        self.candidates = tuple(candidates)


class ViewerError(ArmikError):
    """The viewer cannot start or draw: its optional dependency is missing, or its port is
    taken (``port`` then holds it)."""

    def __init__(self, message: str, *, port: int | None = None) -> None:
        super().__init__(message)
        self.port = port


def listing(names: Iterable[str], limit: int = 40) -> str:
    """A short comma-separated listing for error messages."""
    names = list(names)
    shown = ", ".join(repr(n) for n in names[:limit])
    if len(names) > limit:
        shown += f", ... ({len(names) - limit} more)"
    return shown


def closest(name: object, names: Iterable[str]) -> list[str]:
    """The names most like ``name`` (difflib's, at most 5, whatever their case): an error's
    suggestions ('UR5' finds 'ur5')."""
    by_lower: dict[str, str] = {}
    for n in names:
        by_lower.setdefault(n.lower(), n)
    found = difflib.get_close_matches(str(name).lower(), list(by_lower), n=5, cutoff=0.5)
    return [by_lower[f] for f in found]


def did_you_mean(name: object, names: Iterable[str]) -> str:
    """The words "did you mean 'x'? " naming the ``closest`` of ``names`` ("" if none)."""
    close = closest(name, names)
    return f"did you mean {listing(close)}? " if close else ""
