"""``frozen(cls, **fields)``: the one way armik builds its frozen dataclasses on hot paths.

A frozen dataclass's generated ``__init__`` sets each field through ``object.__setattr__``
(about 0.1 us a field); a solve builds several such objects, so the inner paths build them
here instead. The caller gives every field, already of its type (what ``__post_init__``
would make of it); anything else goes through the class itself.
"""

from __future__ import annotations

from typing import TypeVar

T = TypeVar("T")
_new = object.__new__


def frozen(cls: type[T], **fields: object) -> T:
    """The object ``cls(**fields)`` builds, without the generated ``__init__``."""
    self = _new(cls)
    self.__dict__.update(fields)
    return self
