"""Obstacles in their plain form: the mappings a JSON or YAML file holds (``--obstacles
FILE`` of ``armik solve``, ``batch`` and ``view``), read into the shapes of
``armik.constraints.shapes``::

    [{"type": "box", "size": [0.2, 0.2, 0.4], "position": [0.5, 0, 0.2]},
     {"type": "box", "size": [1, 1, 0.02], "position": [0, 0, -0.01],
      "quaternion": [0, 0, 0, 1]},
     {"type": "sphere", "radius": 0.1, "center": [0.3, 0.3, 0.5]},
     {"type": "cylinder", "radius": 0.05, "length": 0.5, "pose": [[1, 0, 0, 0.4], ...]},
     {"type": "halfspace", "normal": [0, 0, 1], "offset": 0}]

A pose is ``pose`` (a 4x4) or ``position`` (m) with an optional unit ``quaternion``
(x, y, z, w); all in the arm's base frame.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np
import pinocchio as pin

from armik.constraints.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Shape, Sphere
from armik.errors import CollisionError

_POSED = {"pose", "position", "quaternion"}
KEYS = {
    "box": ({"size"}, _POSED, Box),
    "sphere": ({"radius"}, {"center"}, Sphere),
    "capsule": ({"radius", "length"}, _POSED, Capsule),
    "cylinder": ({"radius", "length"}, _POSED, Cylinder),
    "halfspace": ({"normal"}, {"offset"}, HalfSpace),
    "mesh": ({"path"}, _POSED | {"scale"}, Mesh),
}


def as_shapes(items: Iterable[Shape | Mapping], folder: Path | None = None) -> list[Shape]:
    """``items`` as shapes: each a shape (``armik.Box``, ...) or its plain form (see the
    module); a mesh's relative path read from ``folder`` where it names a file there (the
    obstacles file's own folder, as a URDF's meshes are), else as given. Raises
    ``CollisionError`` naming the item and what is wrong with it."""
    if isinstance(items, (Shape, Mapping, str, bytes)):
        raise CollisionError(
            f"obstacles must be a list of shapes, got {type(items).__name__}: wrap one "
            "shape in a list, [armik.Box(...)]",
            value=items,
        )
    out: list[Shape] = []
    for i, item in enumerate(items):
        if isinstance(item, Shape):
            out.append(item)
        elif isinstance(item, Mapping):
            out.append(_from_mapping(i, _beside(item, folder) if folder else item))
        else:
            raise CollisionError(
                f"obstacle {i} is a {type(item).__name__}: give a shape (armik.Box, "
                'armik.Sphere, ...) or a mapping such as {"type": "sphere", "radius": 0.1, '
                '"center": [x, y, z]}',
                value=item,
            )
    return out


def read_shapes(path: str | Path) -> list[Shape]:
    """The shapes of a file holding a list of plain shapes: JSON, or YAML (``.yaml``,
    ``.yml``) when PyYAML is installed. Raises ``CollisionError`` naming the file."""
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise CollisionError(
            f"cannot read obstacles file {str(p)!r}: {exc.strerror}", value=str(p)
        ) from None
    if p.suffix.lower() in (".yaml", ".yml"):
        data = _yaml(p, text)
    else:
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise CollisionError(
                f"obstacles file {str(p)!r} is not JSON: {exc}", value=str(p)
            ) from None
    if not isinstance(data, list):
        raise CollisionError(f"obstacles file {str(p)!r} must hold a list of shapes", value=str(p))
    return as_shapes(data, p.parent)


def _beside(item: Mapping, folder: Path) -> Mapping:
    """``item`` with a mesh's relative ``path`` read from ``folder`` when a file is there."""
    path = item.get("path")
    if item.get("type") != "mesh" or not isinstance(path, str) or Path(path).is_absolute():
        return item
    there = folder / path
    return {**item, "path": str(there)} if there.is_file() else item


def _yaml(p: Path, text: str):
    try:
        import yaml  # optional: only for .yaml files
    except ImportError:
        raise CollisionError(
            f"obstacles file {str(p)!r} is YAML, which needs PyYAML (pip install pyyaml); "
            "or write the same list as JSON",
            value=str(p),
        ) from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        first = str(exc).splitlines()[0]
        raise CollisionError(
            f"obstacles file {str(p)!r} is not YAML: {first}", value=str(p)
        ) from None


def _from_mapping(i: int, item: Mapping) -> Shape:
    kind = item.get("type")
    if not isinstance(kind, str) or kind not in KEYS:  # (a list or a mapping: unhashable)
        raise CollisionError(
            f"obstacle {i}: 'type' must be one of {', '.join(map(repr, KEYS))}, got {kind!r}",
            value=kind,
        )
    needed, optional, cls = KEYS[kind]
    given = set(item) - {"type"}
    unknown = sorted(given - needed - optional, key=str)  # (YAML keys may be numbers)
    if unknown:
        raise CollisionError(
            f"obstacle {i} ({kind}): unknown keys {unknown}; a {kind} takes "
            f"{sorted(needed | optional)}",
            value=unknown,
        )
    missing = sorted(needed - given)
    if missing:
        raise CollisionError(f"obstacle {i} ({kind}) needs {missing[0]!r}", value=kind)
    fields = {k: item[k] for k in given if k not in _POSED}
    if optional is _POSED or "pose" in optional:
        fields["pose"] = _pose(i, kind, item)
    return cls(**fields)


def _pose(i: int, kind: str, item: Mapping):
    if "pose" in item:
        if "position" in item or "quaternion" in item:
            raise CollisionError(
                f"obstacle {i} ({kind}): give 'pose' or 'position' (and 'quaternion'), not both",
                value=item,
            )
        return item["pose"]
    if "position" not in item:
        return None if "quaternion" not in item else _placed(i, kind, (0, 0, 0), item)
    return _placed(i, kind, item["position"], item)


def _placed(i: int, kind: str, position, item: Mapping) -> np.ndarray:
    q = item.get("quaternion", (0.0, 0.0, 0.0, 1.0))
    try:
        quat = np.array(q, dtype=float).reshape(4)
        p = np.array(position, dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        raise CollisionError(
            f"obstacle {i} ({kind}): position must be 3 numbers and quaternion 4 (x, y, z, w)",
            value=item,
        ) from None
    if np.isfinite(quat).all() and np.abs(quat).max() > 1e150:  # its squares overflow: the
        quat = quat / np.abs(quat).max()  # quaternion scaled first (inf made it the identity)
    norm = float(np.linalg.norm(quat))
    if not np.isfinite(quat).all() or norm < 1e-9:
        raise CollisionError(
            f"obstacle {i} ({kind}): quaternion {q} has zero length or is not finite: give "
            "a unit (x, y, z, w)",
            value=q,
        )
    x, y, z, w = quat / norm
    T = np.eye(4)
    T[:3, :3] = pin.Quaternion(w, x, y, z).toRotationMatrix()
    T[:3, 3] = p
    return T
