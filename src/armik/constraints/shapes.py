"""Obstacles in the arm's base frame (m): frozen, hashable shapes that convert to coal.

Each shape validates its values when built and raises ``CollisionError`` (an
``OptionError``, so a ``ValueError``) naming the bad value and the fix. Poses are given as
a 4x4 matrix, a ``pinocchio.SE3`` or a position (x, y, z) and kept as 16 floats, so that
shapes (and the ``Options`` holding them) hash and compare by value.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import coal
import numpy as np
import pinocchio as pin

from armik.errors import CollisionError, OptionError
from armik.tolerances import MAX_LENGTH, ROTATION_TOL

_IDENTITY = tuple(np.eye(4).ravel().tolist())


def _pose(shape: str, value: object) -> tuple[float, ...]:
    """A pose as 16 floats (row-major 4x4); raises ``CollisionError`` naming ``shape``."""
    fix = "give a 4x4 homogeneous matrix, a pinocchio.SE3 or a position (x, y, z) in m"
    if value is None:
        return _IDENTITY
    if isinstance(value, pin.SE3):
        value = value.homogeneous
    try:
        if isinstance(value, (str, bytes)) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        raise CollisionError(f"{shape} pose {value!r} is not a pose: {fix}", value=value) from None
    if arr.shape == (3,):
        T = np.eye(4)
        T[:3, 3] = arr
        arr = T
    if arr.shape != (4, 4):
        raise CollisionError(f"{shape} pose has shape {arr.shape}: {fix}", value=value)
    if not np.isfinite(arr).all() or np.abs(arr[:3, 3]).max() > MAX_LENGTH:
        raise CollisionError(
            f"{shape} pose must be finite and within {MAX_LENGTH:g} m, got {arr.tolist()}: {fix}",
            value=value,
        )
    R = arr[:3, :3]
    off = float(np.abs(R.T @ R - np.eye(3)).max())
    if off > ROTATION_TOL or np.linalg.det(R) < 0 or arr[3].tolist() != [0.0, 0.0, 0.0, 1.0]:
        raise CollisionError(
            f"{shape} pose's rotation is not a rotation (R^T R off the identity by {off:.2g}, "
            f"det {np.linalg.det(R):.3g}, last row {arr[3].tolist()}): {fix}",
            value=value,
        )
    return tuple(arr.ravel().tolist())


def _length(
    shape: str, name: str, value: object, zero: bool = False, unit: str = "a number of metres"
) -> float:
    """A length in m, > 0 (>= 0 with ``zero``) and finite; else ``CollisionError`` naming
    it as ``unit``."""
    try:
        if isinstance(value, (str, bytes, bool, np.bool_)):
            raise TypeError
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        out = math.nan
    if not (math.isfinite(out) and (out >= 0 if zero else out > 0) and out <= MAX_LENGTH):
        bound = ">= 0" if zero else "> 0"
        raise CollisionError(
            f"{shape} {name} must be {unit} {bound} and at most {MAX_LENGTH:g}, got {value!r}",
            value=value,
        )
    return out


def _vector(shape: str, name: str, value: object) -> tuple[float, float, float]:
    try:
        if isinstance(value, (str, bytes)) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        arr = np.array([np.nan])
    if arr.shape != (3,) or not np.isfinite(arr).all() or np.abs(arr).max() > MAX_LENGTH:
        raise CollisionError(
            f"{shape} {name} must be 3 finite numbers (x, y, z), got {value!r}", value=value
        )
    return tuple(float(v) for v in arr)  # type: ignore[return-value]


class Shape:
    """What every obstacle offers: its coal geometry and its placement in the base frame."""

    pose: tuple[float, ...] = _IDENTITY

    @property
    def T(self) -> np.ndarray:
        """The placement of the shape's own frame in the arm's base frame, 4x4 (m)."""
        return np.array(self.pose).reshape(4, 4)

    def placement(self) -> pin.SE3:
        T = self.T
        return pin.SE3(T[:3, :3], T[:3, 3])

    def geometry(self) -> coal.CollisionGeometry:  # pragma: no cover - every shape has one
        raise NotImplementedError


@dataclass(frozen=True, init=False)
class Box(Shape):
    """A box of full side lengths ``size`` (m) centred at ``pose``'s origin, its sides
    along ``pose``'s axes."""

    size: tuple[float, float, float]
    pose: tuple[float, ...]

    def __init__(self, size, pose=None) -> None:
        try:
            sides = list(size)
        except TypeError:
            sides = [size]
        if isinstance(size, (str, bytes, set, frozenset, Mapping)) or len(sides) != 3:
            raise CollisionError(
                f"Box size must be 3 full side lengths (x, y, z) in m, in that order (a list, a "
                f"tuple or an array), got {size!r}",
                value=size,
            )
        dims = tuple(_length("Box", "size", v) for v in sides)
        object.__setattr__(self, "size", dims)
        object.__setattr__(self, "pose", _pose("Box", pose))

    def geometry(self) -> coal.CollisionGeometry:
        return coal.Box(*self.size)


@dataclass(frozen=True, init=False)
class Sphere(Shape):
    """A sphere of ``radius`` (m) around ``center`` (x, y, z, m)."""

    radius: float
    center: tuple[float, float, float]

    def __init__(self, radius, center=(0.0, 0.0, 0.0)) -> None:
        object.__setattr__(self, "radius", _length("Sphere", "radius", radius))
        object.__setattr__(self, "center", _vector("Sphere", "center", center))

    @property
    def pose(self) -> tuple[float, ...]:  # type: ignore[override]
        return _pose("Sphere", self.center)

    def geometry(self) -> coal.CollisionGeometry:
        return coal.Sphere(self.radius)


@dataclass(frozen=True, init=False)
class Capsule(Shape):
    """A capsule: the points within ``radius`` (m) of the segment of ``length`` (m) along
    ``pose``'s z axis, centred at its origin."""

    radius: float
    length: float
    pose: tuple[float, ...]

    def __init__(self, radius, length, pose=None) -> None:
        object.__setattr__(self, "radius", _length("Capsule", "radius", radius))
        object.__setattr__(self, "length", _length("Capsule", "length", length, zero=True))
        object.__setattr__(self, "pose", _pose("Capsule", pose))

    def geometry(self) -> coal.CollisionGeometry:
        return coal.Capsule(self.radius, self.length)


@dataclass(frozen=True, init=False)
class Cylinder(Shape):
    """A cylinder of ``radius`` and ``length`` (m) along ``pose``'s z axis, centred at its
    origin."""

    radius: float
    length: float
    pose: tuple[float, ...]

    def __init__(self, radius, length, pose=None) -> None:
        object.__setattr__(self, "radius", _length("Cylinder", "radius", radius))
        object.__setattr__(self, "length", _length("Cylinder", "length", length))
        object.__setattr__(self, "pose", _pose("Cylinder", pose))

    def geometry(self) -> coal.CollisionGeometry:
        return coal.Cylinder(self.radius, self.length)


@dataclass(frozen=True, init=False)
class HalfSpace(Shape):
    """The solid ``normal . x <= offset`` (x in the base frame, m; ``normal`` is
    normalised, ``offset`` is then in m along it). A table top at z = 0:
    ``HalfSpace((0, 0, 1), 0)``."""

    normal: tuple[float, float, float]
    offset: float

    def __init__(self, normal, offset=0.0) -> None:
        n = np.array(_vector("HalfSpace", "normal", normal))
        norm = float(np.linalg.norm(n))
        if norm < 1e-9:
            raise CollisionError(
                f"HalfSpace normal must not be zero, got {normal!r}: give the direction out "
                "of the solid, e.g. (0, 0, 1) for a table top",
                value=normal,
            )
        try:
            if isinstance(offset, (str, bytes, bool, np.bool_)):
                raise TypeError
            d = float(offset)
        except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
            d = math.nan
        if not math.isfinite(d) or abs(d) > MAX_LENGTH:
            raise CollisionError(
                f"HalfSpace offset must be a finite number of metres, got {offset!r}",
                value=offset,
            )
        object.__setattr__(self, "normal", tuple((n / norm).tolist()))
        object.__setattr__(self, "offset", d / norm)

    def geometry(self) -> coal.CollisionGeometry:
        return coal.Halfspace(np.array(self.normal), self.offset)


@dataclass(frozen=True, init=False)
class Mesh(Shape):
    """The convex hull of the mesh file at ``path`` (STL, OBJ, DAE, ... as coal's loader
    reads them), scaled by ``scale`` and placed at ``pose``: the file as it was when the
    ``Mesh`` was made. Its vertices are read then and kept (``vertices``, m, scaled; they
    go with a pickled ``Mesh`` to worker processes), so the file written again later changes
    nothing of this ``Mesh``: make ``armik.Mesh(path)`` again for the file as it is then.
    ``digest``, the vertices' SHA-256, tells two versions of one file apart."""

    path: str
    pose: tuple[float, ...]
    scale: float
    digest: str = field(repr=False)
    vertices: np.ndarray = field(repr=False, compare=False)  # (m, 3), read-only

    def __init__(self, path, pose=None, scale=1.0) -> None:
        if not isinstance(path, (str, Path)) or not Path(path).is_file():
            raise CollisionError(
                f"Mesh path {str(path)!r} is not an existing file: give the path of a mesh "
                "file (STL, OBJ, DAE)",
                value=path,
            )
        object.__setattr__(self, "path", str(Path(path).resolve()))
        object.__setattr__(self, "pose", _pose("Mesh", pose))
        object.__setattr__(self, "scale", _length("Mesh", "scale", scale, unit="a factor"))
        vertices = self._read()  # a file coal cannot read, or no solid, refused here
        vertices.setflags(write=False)
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "digest", hashlib.sha256(vertices.tobytes()).hexdigest())

    def _read(self) -> np.ndarray:
        """The file's vertices, scaled; ``CollisionError`` where coal cannot read them or
        they are no solid (``solid``)."""
        try:
            bvh = coal.MeshLoader().load(self.path, np.full(3, self.scale))
        except Exception as exc:  # coal's loader raises its own types
            raise CollisionError(
                f"Mesh {self.path!r} could not be read ({exc}): give a mesh file coal reads "
                "(STL, OBJ, DAE)",
                value=self.path,
            ) from None
        solid(bvh, f"Mesh {self.path!r}", "give a mesh of a solid (a Box for a plate)")
        return np.array(bvh.vertices(), dtype=float).reshape(-1, 3)

    def geometry(self) -> coal.CollisionGeometry:
        bvh = coal.BVHModelOBBRSS()  # the kept vertices: their hull is the mesh's
        bvh.beginModel(0, len(self.vertices))
        bvh.addVertices(np.array(self.vertices))
        bvh.endModel()
        return convex_hull(bvh)


# the thinnest spread of a mesh's vertices, over their widest, that counts as a solid: coal's
# convex hull (qhull) ends the process on a flat mesh, already below about 3e-8
FLAT = 1e-6


def solid(bvh: coal.BVHModelBase, what: str, fix: str) -> None:
    """Refuse the mesh ``bvh`` (``what``: how the error names it, ``fix``: the way out) unless
    its vertices span a solid: 4 or more, not all in one plane (its convex hull, what
    distances are measured to, has a volume; coal refuses fewer than 4 points and crashes
    on a flat set). Raises ``CollisionError``."""
    points = np.asarray(bvh.vertices(), dtype=float).reshape(-1, 3)
    n = len(points)
    if n >= 4:
        centred = points - points.mean(axis=0)
        axes = np.linalg.svd(centred, full_matrices=False)[2]  # widest spread first
        spread = np.ptp(centred @ axes.T, axis=0)
        if spread[2] > FLAT * spread[0]:
            return
        lying = "on one point" if spread[0] == 0 else "on one line"
        lying = lying if spread[1] <= FLAT * spread[0] else "in one plane"
        given = f"{n} vertices, all {lying}"
    else:
        given = f"{n} vert{'ex' if n == 1 else 'ices'}"
    raise CollisionError(
        f"{what} has {given}: a collision mesh needs 4 or more vertices not all in one plane "
        f"(a solid: armik measures distances to its convex hull); {fix}",
        value=what,
    )


def convex_hull(bvh: coal.BVHModelBase) -> coal.ConvexBase:
    """The convex hull of a triangle mesh (a solid: ``solid``): distances to it cost a
    hundredth of the mesh's (docs/collisions.md)."""
    bvh.buildConvexHull(True, "Qt")
    return bvh.convex


SHAPES = (Box, Sphere, Capsule, Cylinder, HalfSpace, Mesh)


def check_obstacles(value: object) -> tuple[Shape, ...]:
    """``obstacles`` as a tuple of shapes; raises ``CollisionError`` otherwise."""
    if value is None:
        return ()
    if isinstance(value, Shape):
        return (value,)
    names = ", ".join(f"armik.{s.__name__}" for s in SHAPES)
    try:
        if isinstance(value, (str, bytes, Mapping)):  # a mapping's items are its keys
            raise TypeError
        items = tuple(cast("Iterable[Any]", value))  # not iterable: TypeError, caught below
    except TypeError:
        raise CollisionError(
            f"obstacles must be a list of shapes ({names}), got {value!r}", value=value
        ) from None
    for i, item in enumerate(items):
        if not isinstance(item, Shape):
            plain = (
                " (a mapping is a shape's plain form, what an obstacles file holds: read it "
                "with armik.constraints.shapes_file.as_shapes)"
                if isinstance(item, Mapping)
                else ""
            )
            raise CollisionError(
                f"obstacles[{i}] is {item!r}, not a shape{plain}: give {names}", value=item
            )
    return items


def flag(value: object) -> bool:
    """``self_collision`` as a bool: True or False (numpy's too), else ``OptionError``."""
    if not isinstance(value, (bool, np.bool_)):
        raise OptionError(
            f"self_collision must be True or False, got {value!r}",
            option="self_collision",
            value=value,
        )
    return bool(value)


def margin_of(value: object) -> float:
    """``margin`` as a distance in [0, MAX_LENGTH] m, else ``OptionError`` naming it."""
    try:
        if isinstance(value, (str, bytes, bool, np.bool_)):
            raise TypeError
        margin = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
        margin = float("nan")
    if not 0.0 <= margin <= MAX_LENGTH:
        raise OptionError(
            f"margin must be a distance in [0, {MAX_LENGTH:g}] m, got {value!r}",
            option="margin",
            value=value,
        )
    return margin
