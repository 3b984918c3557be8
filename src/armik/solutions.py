"""``Solutions``: what ``Arm.solve_all`` returns, its results best first, read as a list.

A closed form's answers to one target are verified together in the compiled call that
solved them (``armik.solvers.closed_form.sixr_judged``) and kept as one record of N rows;
building N ``IKResult`` objects costs about as much as solving. ``Solutions`` builds them
from the record on the first access of any (all in one pass) and keeps them, so a caller
that reads none, or only ``len``, does not pay for them. Every other route gives its
results built already (``Solutions(results)``).

It reads as the list ``solve_all`` returned before: ``len``, indexing, slicing (a list),
iteration, ``in``, ``==`` against a list or another ``Solutions`` (the results, in
order), ``+`` with a list (a list), pickling, and the list's methods that change it
(``append``, ``sort``, ...). It is no ``list`` subclass: ``isinstance(x, list)`` is False
(``list(x)`` gives one).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, MutableSequence
from typing import Any, SupportsIndex, overload

from armik.result import IKResult


class Solutions(MutableSequence[IKResult]):
    """``solve_all``'s results, best first; see the module."""

    __slots__ = ("_args", "_built", "_make", "_n")

    def __init__(self, results: Iterable[IKResult] = ()) -> None:
        self._built: list[IKResult] | None = list(results)
        self._make: Callable[..., list[IKResult]] | None = None
        self._args: tuple = ()
        self._n = 0

    @classmethod
    def _lazy(cls, n: int, make: Callable[..., list[IKResult]], args: tuple = ()) -> Solutions:
        """N results that ``make(*args)`` builds, all at once, on the first access of any:
        one pass over the record costs less than N passes."""
        self = _new(cls)
        self._built, self._make, self._args, self._n = None, make, args, n
        return self

    def _results(self) -> list[IKResult]:
        built = self._built
        if built is None:  # two threads at once may both build: equal results, one kept
            built = self._built = self._make(*self._args)  # type: ignore[misc]
        return built

    def __len__(self) -> int:
        return self._n if self._built is None else len(self._built)

    @overload
    def __getitem__(self, index: SupportsIndex) -> IKResult: ...

    @overload
    def __getitem__(self, index: slice) -> list[IKResult]: ...

    def __getitem__(self, index):
        return self._results()[index]

    def __iter__(self) -> Iterator[IKResult]:
        return iter(self._results())

    def __setitem__(self, index, value) -> None:  # type: ignore[no-untyped-def]
        self._results()[index] = value

    def __delitem__(self, index) -> None:  # type: ignore[no-untyped-def]
        del self._results()[index]

    def insert(self, index: int, value: IKResult) -> None:
        self._results().insert(index, value)

    def sort(self, *, key: Any = None, reverse: bool = False) -> None:
        self._results().sort(key=key, reverse=reverse)

    def copy(self) -> list[IKResult]:
        return list(self._results())

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Solutions):
            return self._results() == other._results()
        if isinstance(other, list):
            return self._results() == other
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # mutable, as a list

    def __add__(self, other: Iterable[IKResult]) -> list[IKResult]:
        if isinstance(other, (Solutions, list)):
            return [*self._results(), *other]
        return NotImplemented

    def __radd__(self, other: Iterable[IKResult]) -> list[IKResult]:
        if isinstance(other, list):
            return [*other, *self._results()]
        return NotImplemented

    def __repr__(self) -> str:
        return repr(self._results())

    def __reduce__(self) -> tuple:
        return Solutions, (self._results(),)


_new = object.__new__
