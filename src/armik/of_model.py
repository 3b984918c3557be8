"""A facade's read-only attribute that reads its model: ``Arm.name`` is
``Arm.kinematics.name``, so the facade keeps no copy of what the model holds."""

from __future__ import annotations

from typing import Any, Generic, Protocol, TypeVar, overload

T = TypeVar("T")


class HasModel(Protocol):
    kinematics: Any


class OfModel(Generic[T]):
    """A read-only attribute of the owner's model (its ``kinematics``), of type ``T``."""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, obj: None, owner: type | None = None) -> OfModel[T]: ...
    @overload
    def __get__(self, obj: HasModel, owner: type | None = None) -> T: ...
    def __get__(self, obj: HasModel | None, owner: type | None = None) -> T | OfModel[T]:
        return self if obj is None else getattr(obj.kinematics, self.name)
