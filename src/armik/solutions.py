"""``Solutions``: what ``Arm.solve_all`` returns, its results best first, read as a list.

A closed form's answers to one target are verified together in the compiled call that
solved them (``armik.solvers.closed_form.sixr_judged``) and kept as one record of N rows;
building N ``IKResult`` objects would cost more than solving. ``Solutions`` hands out the
record's rows as ``IKResult`` objects, each built on its first access and kept, so a
caller pays only for the results it reads. Every other route gives its results built
already (``Solutions(results)``).

It reads as the list ``solve_all`` returned before: ``len``, indexing, slicing (a list),
iteration, ``in``, ``==`` against a list or another ``Solutions`` (the results, in
order), ``+`` with a list (a list), pickling, and the list's methods that change it
(``append``, ``sort``, ...), after which it holds its results as a list. It is no
``list`` subclass: ``isinstance(x, list)`` is False (``list(x)`` gives one).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, MutableSequence
from typing import Any, SupportsIndex, overload

from armik.result import IKResult


class Solutions(MutableSequence[IKResult]):
    """``solve_all``'s results, best first; see the module."""

    __slots__ = ("_built", "_make")

    def __init__(self, results: Iterable[IKResult] = ()) -> None:
        self._built: list[Any] = list(results)
        self._make: Callable[[int], IKResult] | None = None  # builds result i

    @classmethod
    def _lazy(cls, n: int, make: Callable[[int], IKResult]) -> Solutions:
        """N results, result i built by ``make(i)`` on its first access."""
        self = _new(cls)
        self._built = [None] * n
        self._make = make
        return self

    def _at(self, i: int) -> IKResult:
        r = self._built[i]
        if r is None:
            r = self._built[i] = self._make(i)  # type: ignore[misc]
        return r  # type: ignore[no-any-return]

    def _results(self) -> list[IKResult]:
        """Every result built, as the list this holds from now on."""
        if self._make is not None:
            for i in range(len(self._built)):
                self._at(i)
            self._make = None
        return self._built

    def __len__(self) -> int:
        return len(self._built)

    @overload
    def __getitem__(self, index: SupportsIndex) -> IKResult: ...

    @overload
    def __getitem__(self, index: slice) -> list[IKResult]: ...

    def __getitem__(self, index):
        if self._make is None:
            return self._built[index]
        if isinstance(index, slice):
            return [self._at(i) for i in range(*index.indices(len(self._built)))]
        i = range(len(self._built))[index]  # negative indices, IndexError as a list's
        return self._at(i)

    def __iter__(self) -> Iterator[IKResult]:
        if self._make is None:
            return iter(self._built)
        return (self._at(i) for i in range(len(self._built)))

    def __setitem__(self, index, value) -> None:  # type: ignore[no-untyped-def]
        self._results()[index] = value

    def __delitem__(self, index) -> None:  # type: ignore[no-untyped-def]
        del self._results()[index]

    def insert(self, index: int, value: IKResult) -> None:
        self._results().insert(index, value)

    def sort(self, *, key: Callable[[IKResult], Any] | None = None, reverse: bool = False) -> None:
        self._results().sort(key=key, reverse=reverse)

    def copy(self) -> list[IKResult]:
        return list(self)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, (Solutions, list)):
            return len(self) == len(other) and all(a == b for a, b in zip(self, other))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # mutable, as a list

    def __add__(self, other: Iterable[IKResult]) -> list[IKResult]:
        if isinstance(other, (Solutions, list)):
            return [*self, *other]
        return NotImplemented

    def __radd__(self, other: Iterable[IKResult]) -> list[IKResult]:
        if isinstance(other, list):
            return [*other, *self]
        return NotImplemented

    def __repr__(self) -> str:
        return repr(list(self))

    def __reduce__(self) -> tuple:
        return Solutions, (list(self),)


_new = object.__new__
