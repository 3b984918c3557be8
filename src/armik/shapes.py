"""Obstacle shapes in the arm's base frame: boxes and spheres.

The viewer draws them today (``Viewer.add_obstacles``); collision-aware solving will take
the same shapes. ``as_shapes`` also reads the plain form a JSON file holds::

    [{"type": "box", "size": [0.2, 0.2, 0.4], "position": [0.5, 0, 0.2]},
     {"type": "box", "size": [1, 1, 0.02], "position": [0, 0, -0.01],
      "quaternion": [0, 0, 0, 1]},
     {"type": "sphere", "radius": 0.1, "center": [0.3, 0.3, 0.5]}]
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armik.errors import InputError


@dataclass(frozen=True)
class Box:
    """A box of edge lengths ``size`` (m), centred at ``position`` (m, base frame), turned by
    the unit quaternion ``quaternion`` (x, y, z, w)."""

    size: tuple[float, float, float]
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quaternion: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", _vector(self.size, 3, "Box size", positive=True))
        object.__setattr__(self, "position", _vector(self.position, 3, "Box position"))
        q = _vector(self.quaternion, 4, "Box quaternion (x, y, z, w)")
        norm = math.sqrt(sum(v * v for v in q))
        if norm < 1e-9:
            raise InputError(f"Box quaternion {q} has zero length: give a unit (x, y, z, w)")
        object.__setattr__(self, "quaternion", tuple(v / norm for v in q))


@dataclass(frozen=True)
class Sphere:
    """A sphere of ``radius`` (m) centred at ``center`` (m, base frame)."""

    radius: float
    center: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        (r,) = _vector((self.radius,), 1, "Sphere radius", positive=True)
        object.__setattr__(self, "radius", r)
        object.__setattr__(self, "center", _vector(self.center, 3, "Sphere center"))


Shape = Box | Sphere


def as_shapes(items: Iterable[Shape | Mapping]) -> list[Shape]:
    """``items`` as shapes: each a ``Box``, a ``Sphere`` or its plain form (see the module
    docstring). Raises ``InputError`` naming the item and what it lacks."""
    if isinstance(items, (Box, Sphere, Mapping, str, bytes)):
        raise InputError(
            f"obstacles must be a list of shapes, got {type(items).__name__}: wrap one "
            "shape in a list, [armik.Box(...)]"
        )
    out: list[Shape] = []
    for i, item in enumerate(items):
        if isinstance(item, (Box, Sphere)):
            out.append(item)
        elif isinstance(item, Mapping):
            out.append(_from_mapping(i, item))
        else:
            raise InputError(
                f"obstacle {i} is a {type(item).__name__}: give an armik.Box, an "
                'armik.Sphere or a mapping such as {"type": "sphere", "radius": 0.1, '
                '"center": [x, y, z]}'
            )
    return out


def read_shapes(path: str | Path) -> list[Shape]:
    """The shapes of a JSON file holding a list of plain shapes. Raises ``InputError``."""
    p = Path(path)
    try:
        data = json.loads(p.read_text())
    except OSError as exc:
        raise InputError(f"cannot read obstacles file {str(p)!r}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"obstacles file {str(p)!r} is not JSON: {exc}") from None
    if not isinstance(data, list):
        raise InputError(f"obstacles file {str(p)!r} must hold a JSON list of shapes")
    return as_shapes(data)


def _from_mapping(i: int, item: Mapping) -> Shape:
    kind = item.get("type")
    keys = {
        "box": {"type", "size", "position", "quaternion"},
        "sphere": {"type", "radius", "center"},
    }
    if kind not in keys:
        raise InputError(f"obstacle {i}: 'type' must be 'box' or 'sphere', got {kind!r}")
    unknown = sorted(set(item) - keys[kind])
    if unknown:
        raise InputError(
            f"obstacle {i} ({kind}): unknown keys {unknown}; a {kind} takes "
            f"{sorted(keys[kind] - {'type'})}"
        )
    fields = {k: v for k, v in item.items() if k != "type"}
    try:
        return Box(**fields) if kind == "box" else Sphere(**fields)
    except TypeError:
        need = "size" if kind == "box" else "radius"
        raise InputError(f"obstacle {i} ({kind}) needs {need!r}") from None


def _vector(value: object, n: int, what: str, positive: bool = False) -> tuple[float, ...]:
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        arr = np.array([])
    if arr.shape != (n,) or not np.all(np.isfinite(arr)) or (positive and np.any(arr <= 0)):
        sign = " > 0" if positive else ""
        raise InputError(f"{what} must be {n} finite number(s){sign} (m), got {value!r}")
    return tuple(float(v) for v in arr)
