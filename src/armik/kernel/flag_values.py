"""numba's compile flags compared in one dict merge: the same values, 8 % less compile time.

numba keys the implementations it has typed for a call (``typing.templates``'s
``_get_impl``) by the compile flags, and hashing or comparing flags builds a dict of all
of their ~50 options, one Python property call each (``TargetConfig.values``). Typing
armik's kernels does that about three times per call it resolves: 300 000 times in each
half of ``armik compile --all``, 8 % of its CPU time (measured with cProfile and paired
runs, 2026-12-07). ``install`` gives ``TargetConfig`` a ``values`` that builds the same dict
(same keys, order and values) from the class's defaults and the values set on the object,
in one merge done in C. It replaces numba's function only while that is still the one
this module was written against, and ``tests/kernel/test_flag_values.py`` holds the two
equal.
"""

from __future__ import annotations

from typing import Any

from numba.core import targetconfig

_NUMBAS = targetconfig.TargetConfig.values
_DEFAULTS: dict[type, dict[str, Any]] = {}  # per flags class: its options' defaults


def values(self: targetconfig.TargetConfig) -> dict[str, Any]:
    """Every option of ``self`` with its value: what numba's ``values`` returns."""
    cls = type(self)
    defaults = _DEFAULTS.get(cls)
    if defaults is None:
        defaults = _DEFAULTS[cls] = {k: o.default for k, o in cls.options.items()}
    return {**defaults, **self._values}  # a set value keeps its option's place


def numbas(self: targetconfig.TargetConfig) -> dict[str, Any]:
    """numba's own ``values`` (the tests compare with it)."""
    return _NUMBAS(self)  # type: ignore[no-any-return]


def install() -> None:
    """Put ``values`` in place of numba's, once, if numba's is the one this reproduces (a
    property per option reading ``_values`` with the option's default)."""
    config = targetconfig.TargetConfig
    if config.values is values:
        return
    if getattr(config.values, "__qualname__", "") != "TargetConfig.values" or not hasattr(
        config, "__slots__"
    ):
        return  # a numba this was not written against: its own stays
    config.values = values  # type: ignore[method-assign]
