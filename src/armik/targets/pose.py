"""Turning user input into one Target type.

Accepted: a ``pinocchio.SE3``; a spatialmath ``SE3`` holding one pose; a 4x4 homogeneous
matrix; a 3-vector (position only); ``(position, quaternion)`` with the quaternion in
(x, y, z, w) order as in Pinocchio and scipy (a non-unit quaternion is normalised), a
``pinocchio.Quaternion`` or ``pinocchio.AngleAxis``;
``(position, 3x3 rotation matrix)``; ``(position, scipy Rotation)``; ``(position,
spatialmath SO3, UnitQuaternion or Quaternion)`` (a quaternion by its parts, scalar
first as spatialmath holds it); a 7-vector
(x, y, z, qx, qy, qz, qw); and on a planar arm a 2-vector (x, y) in the arm's plane (see
``armik.model.geometry.Plane``). Every target is expressed in the arm's base frame, in metres.
A class of the user's own is read by the function registered for it
(``register_spelling``), consulted only when one is registered.

Several poses in one object (an (N, 4, 4) array, a spatialmath ``SE3`` of length N, a
scipy ``Rotation`` of N rotations) are refused with a pointer to ``Arm.solve_batch``:
solving the first pose only would be a silent answer to another question. Complex numbers
are refused, never cast.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from armik.errors import TargetError
from armik.frozen import frozen
from armik.model.arm_model import model_of
from armik.targets.aim import Aim
from armik.tolerances import LAST_ROW_TOL, MAX_POSITION, ROTATION_TOL


@dataclass(frozen=True, eq=False)
class Target:
    """A desired tip pose in the base frame. ``rotation`` is None for a position target;
    ``aim``: a tip axis within a cone in place of the whole rotation (``armik.targets.aim``);
    ``along``: the tip axis (unit, tip frame) of an ``armik.Axis`` lowered to a pose, whose
    direction is all its rotation says (``armik.verify.distances``). None: none."""

    position: np.ndarray
    rotation: np.ndarray | None = None
    planar_xy: np.ndarray | None = None  # a 2-vector target's point, in plane coordinates
    aim: Aim | None = None
    along: tuple[float, float, float] | None = None

    @property
    def planar(self) -> bool:
        return self.planar_xy is not None

    @property
    def position_only(self) -> bool:
        return self.rotation is None

    def se3(self) -> pin.SE3:
        """The pose as ``T_base_target`` (identity rotation for a position target)."""
        R = np.eye(3) if self.rotation is None else self.rotation
        return pin.SE3(R, self.position)

    def aimed(self, aim: Aim | None) -> Target:
        """This target with ``aim`` (a copy, built without the frozen ``__init__``)."""
        return frozen(Target, **{**self.__dict__, "aim": aim})


def parsed(value: object, arm: object = None) -> Target:
    """``value`` as a ``Target``: itself where it was parsed already (the stages below the
    door pass the parsed target on), else ``parse_target``'s."""
    return value if type(value) is Target else parse_target(value, arm)


def parse_target(value: object, arm: object = None) -> Target:
    """Parse any accepted form into a ``Target``; raises ``TargetError`` naming the problem.
    ``arm`` (an ``Arm`` or its model) places a 2-vector on a planar arm's plane."""
    return _read(value, arm)


def parse_by_tip(targets: Mapping[str, object], arms: Mapping[str, object]) -> dict[str, Target]:
    """A several-tip target (tip -> one target in any form ``parse_target`` reads) parsed in
    one call, each tip's value on its own chain ``arms[tip]`` (a 2-vector on that chain's
    plane), a ``Target`` checked as its parts; a ``TargetError`` names the tip."""
    out = {}
    for tip, value in targets.items():
        try:
            out[tip] = _read(value, arms[tip])
        except TargetError as exc:
            raise TargetError(f"the target of tip {tip!r}: {exc}") from None
    return out


def _read(value: object, arm: object) -> Target:
    """``parse_target``'s reading of one value, which ``parse_by_tip`` shares."""
    if isinstance(value, Target):
        return checked(value)
    if isinstance(value, pin.SE3):
        return _se3(value)
    if SPELLINGS:  # an empty dict is false: the common forms pay nothing for the hook
        spelled = _spelled(value, arm)
        if spelled is not None:
            return spelled
    if _is_spatialmath(value):
        n = len(value)  # type: ignore[arg-type]
        if n != 1:
            raise TargetError(_several(f"a spatialmath {type(value).__name__} of {n} poses"))
        value = value.A  # type: ignore[attr-defined]
    if (
        isinstance(value, (tuple, list))
        and value
        and all(isinstance(v, pin.SE3) or _is_spatialmath(v) for v in value)
    ):
        raise TargetError(_several(f"a {type(value).__name__} of {len(value)} poses"))
    if isinstance(value, (tuple, list)) and len(value) == 2 and not np.isscalar(value[0]):
        position, rotation = value
        return _pose(_rotation(rotation), _vector(position, 3, "target position"))
    try:
        arr = _array(value, "target")
    except TargetError:
        _not_a_pose(value)  # a rotation alone, tasks among poses: said as such
        raise
    if (arr.ndim == 3 and arr.shape[1:] == (4, 4)) or (arr.ndim == 2 and arr.shape[1] in (3, 7)):
        raise TargetError(_several(f"an array of shape {arr.shape}"))
    if arr.shape == (4, 4):
        return _from_matrix(arr)
    if arr.shape == (3,):
        return Target(_position(arr))
    if arr.shape == (7,):
        return _pose(_rotation_from_quat(arr[3:]), arr[:3])
    if arr.shape == (2,):
        return _planar(_finite(arr, "target (x, y)"), arm)
    raise TargetError(
        f"cannot read a target of shape {arr.shape}: give a pinocchio.SE3, a 4x4 matrix, "
        "a position (x, y, z), (position, quaternion xyzw), or (x, y) on a planar arm"
    )


def checked(t: Target) -> Target:
    """A ``Target`` built by hand (``armik.Target(position, rotation)``) with its parts
    checked and copied as ``parse_target`` checks a position and a rotation (a 3-vector
    within ``MAX_POSITION``, a 3x3 rotation snapped within ``ROTATION_TOL``); its plane
    point, aim and axis kept. ``TargetError`` naming the part that is not."""
    p = _vector(t.position, 3, "target position")
    if t.rotation is None:
        out = _target(_position(p), None)
    else:
        R = _array(t.rotation, "target rotation")
        if R.shape != (3, 3):
            raise TargetError(
                f"the rotation of a Target has shape {R.shape}: give a 3x3 rotation matrix, "
                "or build the target with armik.parse_target((position, rotation))"
            )
        out = _pose(R, p)
    kept = {"planar_xy": t.planar_xy, "aim": t.aim, "along": t.along}
    plain = all(v is None for v in kept.values())
    return out if plain else frozen(Target, **{**out.__dict__, **kept})


Spelling = Callable[[Any], object]  # the user's object -> a form ``parse_target`` reads

SPELLINGS: dict[type, Spelling] = {}
# what the parser reads itself: no spelling may take these (or a class they derive from)
_BUILT_IN = (Target, pin.SE3, np.ndarray, list, tuple, dict, str, bytes, int, float)


def register_spelling(kind: type, to_target: Spelling) -> None:
    """Accept objects of class ``kind`` (and its subclasses) as targets wherever a target
    is read: ``to_target(value)`` gives a ``Target`` or any form ``parse_target`` reads (a
    ``pinocchio.SE3``, a 4x4, ``(position, quaternion)``, a 3-vector, ...), which is then
    checked as that form. ``solve``, ``solve_all``, several tips, and a sequence of them in
    ``solve_batch`` and ``solve_path`` all read it (``armik.targets.batch`` parses a
    sequence one by one). ``unregister_spelling(kind)`` removes it. ``TargetError`` for a
    ``kind`` that is not a class, a class the parser reads itself, or one registered already."""
    if not isinstance(kind, type):
        raise TargetError(f"a target spelling is registered for a class, got {kind!r}")
    builtin = next((b for b in _BUILT_IN if issubclass(b, kind)), None)
    if builtin is not None:
        raise TargetError(
            f"class {kind.__name__} is a form the target parser reads itself "
            f"({builtin.__name__}): register a class of your own"
        )
    if kind in SPELLINGS:
        raise TargetError(
            f"class {kind.__name__} has a target spelling already: "
            f"unregister_spelling({kind.__name__}) first"
        )
    if not callable(to_target):
        raise TargetError(
            f"the spelling of {kind.__name__} must be a function of one of its objects "
            f"giving a target, got {to_target!r}"
        )
    SPELLINGS[kind] = to_target


def unregister_spelling(kind: type) -> None:
    """Stop accepting objects of class ``kind`` as targets; ``TargetError`` if it has no
    spelling."""
    if SPELLINGS.pop(kind, None) is None:
        raise TargetError(
            f"class {getattr(kind, '__name__', kind)!r} has no target spelling; registered: "
            f"{[k.__name__ for k in SPELLINGS] or 'none'}"
        )


def spelling_of(value: object) -> Spelling | None:
    """The registered spelling of ``value``'s class (or of a class it derives from)."""
    kind = type(value)
    if kind in SPELLINGS:
        return SPELLINGS[kind]
    return next((f for k, f in SPELLINGS.items() if isinstance(value, k)), None)


def _spelled(value: object, arm: object) -> Target | None:
    """``value`` read by its class' registered spelling, checked as the form it gives;
    None where its class has none."""
    to_target = spelling_of(value)
    if to_target is None:
        return None
    name = type(value).__name__
    try:
        given = to_target(value)
    except TargetError:
        raise
    except Exception as exc:
        raise TargetError(f"the target spelling of {name} failed on {value!r}: {exc!r}") from exc
    if spelling_of(given) is not None:
        raise TargetError(
            f"the target spelling of {name} gave {type(given).__name__}, another spelled "
            "class: give a Target, a pinocchio.SE3, a 4x4, (position, quaternion) or a position"
        )
    if isinstance(given, Target):  # built by the user: checked as its parts
        return checked(given)
    try:
        return _read(given, arm)
    except TargetError as exc:
        raise TargetError(f"the target spelling of {name} gave {given!r}: {exc}") from None


def _not_a_pose(value: object) -> None:
    """A ``TargetError`` saying what ``value`` is where it is a rotation without a position
    or a list of tasks (``armik.Pose``, ...) read where poses are (a batch's row among
    poses); else nothing (the caller's error stands)."""
    if isinstance(value, (pin.Quaternion, pin.AngleAxis)) or (
        type(value).__module__.startswith("scipy.spatial") and hasattr(value, "as_matrix")
    ):
        raise TargetError(
            f"target {_one_line(value)} is a rotation without a position: give (position, "
            "rotation), e.g. ((x, y, z), rotation)"
        ) from None
    listed = isinstance(value, (list, tuple))
    items: tuple[Any, ...] | list[Any] = value if isinstance(value, (list, tuple)) else (value,)
    if items and all(type(v).__module__.startswith("armik.problem.tasks") for v in items):
        what = "a list of tasks" if listed else "a task"
        raise TargetError(
            f"target {_one_line(value)} is {what} where a pose is read: give every target "
            "of a batch or a path as tasks, or every one as a pose or a position"
        ) from None


def _several(what: str) -> str:
    return (
        f"the target is {what}: a target is one pose; give one, or for several solve them "
        "with Arm.solve_batch(targets) or stream them with a servo's track(targets)"
    )


def _is_spatialmath(value: object) -> bool:
    return type(value).__module__.startswith("spatialmath") and hasattr(value, "A")


def _array(value: object, what: str) -> np.ndarray:
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise TargetError(f"{what} {_one_line(value)} is not numeric") from None
    kind = raw.dtype.kind
    if kind == "f":
        return raw
    if kind == "c":
        raise TargetError(
            f"{what} {_one_line(value)} has complex numbers: give real numbers (m, rad)"
        )
    try:
        return raw.astype(float)
    except (TypeError, ValueError):
        raise TargetError(f"{what} {_one_line(value)} is not numeric") from None
    except OverflowError:  # an int beyond a float's range
        raise TargetError(f"{what} {_one_line(value)} has a value too large for a float") from None


def _one_line(value: object) -> str:
    """``repr(value)`` on one line (Eigen's objects print theirs over several)."""
    return " ".join(repr(value).split())


def _finite(arr: np.ndarray, what: str) -> np.ndarray:
    # A sum on plain floats is finite iff every element is, unless finite huge values
    # overflow it: then numpy decides (a few us more, never on real targets).
    if not math.isfinite(sum(arr.ravel().tolist())) and not np.isfinite(arr).all():
        raise TargetError(f"{what} contains NaN or inf: {arr.tolist()}")
    return arr.copy()


def _position(arr: np.ndarray) -> np.ndarray:
    """A copy of the 3-vector ``arr``; raises ``TargetError`` if it is not finite or beyond
    ``MAX_POSITION`` (plain floats: half the cost of numpy at this size)."""
    x, y, z = arr.tolist()
    if abs(x) <= MAX_POSITION and abs(y) <= MAX_POSITION and abs(z) <= MAX_POSITION:
        return np.array((x, y, z))
    _finite(arr, "target position")  # NaN fails every comparison above
    raise TargetError(
        f"target position {arr.tolist()} is beyond {MAX_POSITION:g} m from the base: give "
        "it in metres (no arm reaches this far, and the error arithmetic would overflow)"
    )


def _vector(value: object, n: int, what: str) -> np.ndarray:
    arr = _array(value, what)
    if arr.shape != (n,):
        raise TargetError(f"{what} must have {n} numbers, got shape {arr.shape}")
    return _finite(arr, what)


def _rotation(value: object) -> np.ndarray:
    """The rotation of ``(position, rotation)``: a quaternion (x, y, z, w), a 3x3 matrix,
    a scipy ``Rotation`` holding one rotation, a ``pin.Quaternion`` or ``pin.AngleAxis``, a
    spatialmath ``SO3``, ``UnitQuaternion`` or ``Quaternion`` holding one (read by its
    scalar and vector parts: its array is (w, x, y, z))."""
    module = type(value).__module__
    if module.startswith("scipy.spatial") and hasattr(value, "as_matrix"):
        rotation: Any = value  # a scipy Rotation (scipy has no type information)
        if not getattr(rotation, "single", True):
            raise TargetError(_several(f"a scipy Rotation of {len(rotation)} rotations"))
        return np.asarray(rotation.as_matrix(), float)
    if module.startswith("spatialmath") and hasattr(value, "A"):
        return _spatialmath_rotation(value)
    if isinstance(value, pin.Quaternion):  # its coeffs() are (x, y, z, w)
        return _rotation_from_quat(value.coeffs())
    if isinstance(value, pin.AngleAxis):
        return _rotation_from_quat(pin.Quaternion(value).coeffs())
    arr = _array(value, "target rotation")
    if arr.shape == (3, 3):
        return arr
    if arr.shape == (4,):
        return _rotation_from_quat(arr)
    two = (
        "; two positions are several targets: Arm.solve_batch(targets)" if arr.shape == (3,) else ""
    )
    raise TargetError(
        f"the rotation of (position, rotation) has shape {arr.shape}: give a quaternion "
        "of 4 numbers (x, y, z, w), a 3x3 rotation matrix or a scipy Rotation" + two
    )


def _spatialmath_rotation(value: Any) -> np.ndarray:
    """The rotation of a spatialmath object holding one: a quaternion by its scalar ``s``
    and vector ``v`` (its array, and numpy's reading of it, is (w, x, y, z), not the
    (x, y, z, w) a quaternion is read in here), else its array (an ``SO3``'s 3x3; other
    shapes are refused by ``_rotation``)."""
    n = len(value)
    name = type(value).__name__
    if n != 1:
        raise TargetError(_several(f"a spatialmath {name} of {n} rotations"))
    if hasattr(value, "s") and hasattr(value, "v"):  # (Unit)Quaternion: scalar first
        x, y, z = _vector(value.v, 3, f"the vector part of spatialmath {name}").tolist()
        return _rotation_from_quat((x, y, z, float(value.s)))
    return _rotation(_array(value.A, "target rotation"))


def _rotation_from_quat(quat: object) -> np.ndarray:
    x, y, z, w = _vector(quat, 4, "quaternion (x, y, z, w)").tolist()
    scale = max(abs(x), abs(y), abs(z), abs(w))  # divide first: squares above 1e154 overflow
    if scale < 1e-12:
        raise TargetError(
            f"quaternion {[x, y, z, w]} has zero norm: give a unit quaternion "
            "(x, y, z, w), e.g. (0, 0, 0, 1) for no rotation"
        )
    x, y, z, w = x / scale, y / scale, z / scale, w / scale
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def _from_matrix(M: np.ndarray) -> Target:
    last = M[3].tolist()
    if not all(abs(x - y) <= LAST_ROW_TOL for x, y in zip(last, (0.0, 0.0, 0.0, 1.0))):
        _finite(M, "4x4 target")
        raise TargetError(f"the last row of a 4x4 target must be (0, 0, 0, 1), got {last}")
    return _pose(M[:3, :3], M[:3, 3])  # checks the rest


def _se3(T: pin.SE3) -> Target:
    """``_pose(T.rotation, T.translation)``, on the plain floats of one fresh copy of the
    matrix: a finite position within ``MAX_POSITION`` and a rotation orthonormal to 1e-14
    with determinant +1 (every pose Pinocchio computes) give the same ``Target`` without
    ``_pose``'s copies; anything else goes through ``_pose``."""
    H = T.homogeneous  # a new C-ordered array (T.rotation would be a view into T)
    (a, b, c, x), (d, e, f, y), (g, h, i, z), _ = H.tolist()
    if (
        abs(x) <= MAX_POSITION
        and abs(y) <= MAX_POSITION
        and abs(z) <= MAX_POSITION
        and math.isfinite(a + b + c + d + e + f + g + h + i)
        and _orthonormality_error(a, b, c, d, e, f, g, h, i) <= 1e-14
        and _determinant(a, b, c, d, e, f, g, h, i) > 0
    ):
        return _target(np.array((x, y, z)), np.array(H[:3, :3]))
    return _pose(T.rotation, T.translation)


# |R^T R - I| and det(R) of R = [[a, b, c], [d, e, f], [g, h, i]] on plain floats: a fifth
# of the numpy cost for a 3x3. (kernel.single.plain_pose computes the same in compiled code.)
def _orthonormality_error(
    a: float, b: float, c: float, d: float, e: float, f: float, g: float, h: float, i: float
) -> float:
    return max(
        abs(a * a + d * d + g * g - 1.0),
        abs(b * b + e * e + h * h - 1.0),
        abs(c * c + f * f + i * i - 1.0),
        abs(a * b + d * e + g * h),
        abs(a * c + d * f + g * i),
        abs(b * c + e * f + h * i),
    )


def _determinant(
    a: float, b: float, c: float, d: float, e: float, f: float, g: float, h: float, i: float
) -> float:
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def is_rotation(R: np.ndarray) -> bool:
    """Whether a finite 3x3 ``R`` is a rotation as the parser takes one: orthonormal within
    ``ROTATION_TOL``, not a reflection."""
    v = R.ravel().tolist()
    return _orthonormality_error(*v) <= ROTATION_TOL and _determinant(*v) > 0


def _target(p: np.ndarray, R: np.ndarray | None) -> Target:
    """``Target(p, R)`` without the frozen ``__init__``'s setattr per field."""
    return frozen(Target, position=p, rotation=R, planar_xy=None, aim=None, along=None)


def _pose(R: np.ndarray, p: np.ndarray) -> Target:
    p = _position(np.asarray(p, float))
    R = np.array(R, dtype=float)  # a copy: the target must not change with the caller's array
    a, b, c, d, e, f, g, h, i = R.ravel().tolist()
    if not math.isfinite(a + b + c + d + e + f + g + h + i):
        _finite(R, "target rotation")  # NaN or inf; else huge entries, far from a rotation
    err = _orthonormality_error(a, b, c, d, e, f, g, h, i)
    if not err <= ROTATION_TOL:
        raise TargetError(
            f"target rotation is not orthonormal (|R^T R - I| = {err:.2g}): "
            "give a rotation matrix, or a quaternion"
        )
    if _determinant(a, b, c, d, e, f, g, h, i) < 0:
        raise TargetError(
            "target rotation has determinant -1 (a reflection, not a rotation): "
            "flip the sign of one axis"
        )
    if err > 1e-14:
        # Snap to the nearest rotation so that verification measures the arm, not rounding.
        U, _, Vt = np.linalg.svd(R)
        R = U @ Vt
    return _target(p, R)


def _not_planar(arm: Any) -> str:
    """Why ``arm`` takes no 2-vector: the planar reading is of revolute joints about
    parallel axes, without a mimic or prismatic joint even where the motion stays in a
    plane."""
    reading = "which the planar reading (revolute joints about parallel axes) does not take"
    if arm is not None and arm.mimics:
        names = ", ".join(repr(m.name) for m in arm.mimics)
        return f"has the mimic joint(s) {names}, {reading}"
    if arm is not None and any(arm.prismatic):
        name = next(n for n, p in zip(arm.joint_names, arm.prismatic) if p)
        return f"has the prismatic joint {name!r}, {reading}"
    return "is not planar (its joint axes are not parallel)"


def _planar(xy: np.ndarray, arm: object) -> Target:
    arm = None if arm is None else model_of(arm)  # armik.parse_target takes an Arm too
    plane = None if arm is None else arm.plane
    if plane is None:
        name = "this arm" if arm is None else f"arm {arm.name!r}"
        raise TargetError(
            f"a 2-vector target needs a planar arm, and {name} {_not_planar(arm)}: "
            "give a position (x, y, z) or a full pose"
        )
    p, uv = plane.from_base(xy)  # base (x, y) across the plane; the kernel's coordinates
    return Target(_position(p), None, planar_xy=uv)
