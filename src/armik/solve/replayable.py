"""Keyword options that can be read more than once: a one-shot iterator given as an option
(``constraints=iter([c])``, a generator of obstacles, ``constraints={tip: iter([...])}``)
gives its items to the first reader only, and a later one would read none (a constraint
dropped unseen: an answer that violates it a success). A facade that reads the options in
several places (``armik.Arms``: the robot's request, each chain's solve, the checks between
the chains) takes them replayable first."""

from __future__ import annotations

from collections.abc import Iterator, Mapping


def replayable(options: dict) -> dict:
    """``options`` with each one-shot iterator, given as an option or by tip in a mapping
    (``constraints={tip: ...}``), as the tuple of its items; ``options`` itself where none
    is one."""
    if not any(isinstance(v, (Iterator, Mapping)) for v in options.values()):
        return options  # the common call: lists, arrays, numbers
    out = {}
    for name, value in options.items():
        if isinstance(value, Iterator):
            value = tuple(value)
        elif isinstance(value, Mapping) and any(isinstance(v, Iterator) for v in value.values()):
            value = {k: tuple(v) if isinstance(v, Iterator) else v for k, v in value.items()}
        out[name] = value
    return out
