"""What a module derives from an arm and keeps with it (a closed form's geometry, prepared
solves, collision checkers): declared once, typed, by the module that owns it. The
declaration itself is the key, so no two modules can choose the same one, and an arm
with other limits or locks starts without any (``ArmModel.with_limits``)."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import TYPE_CHECKING, Any, Generic, TypeVar

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel

T = TypeVar("T")
_MISSING: Any = object()


class Derived(Generic[T]):
    """``build(arm)``, built on an arm's first use and kept with that arm."""

    __slots__ = ("name", "_build")

    def __init__(self, name: str, build: Callable[[ArmModel], T]) -> None:
        self.name, self._build = name, build

    def __call__(self, arm: ArmModel) -> T:
        store = arm._derived
        value = store.get(self, _MISSING)
        if value is _MISSING:
            value = store[self] = self._build(arm)
        return value  # type: ignore[no-any-return]

    def __repr__(self) -> str:
        return f"Derived({self.name!r})"


class DerivedBy(Generic[T]):
    """``build(arm, key)``, built on an arm's first use with ``key`` and kept with it."""

    __slots__ = ("name", "_build")

    def __init__(self, name: str, build: Callable[[ArmModel, Any], T]) -> None:
        self.name, self._build = name, build

    def __call__(self, arm: ArmModel, key: Hashable) -> T:
        store = arm._derived
        value = store.get((self, key), _MISSING)
        if value is _MISSING:
            value = store[(self, key)] = self._build(arm, key)
        return value  # type: ignore[no-any-return]

    def __repr__(self) -> str:
        return f"DerivedBy({self.name!r})"
