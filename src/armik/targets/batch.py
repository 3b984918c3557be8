"""Many targets at once: N poses (or N positions) as arrays, in the arm's base frame.

``parse_targets`` reads, without a Python call per target where it can:

- an (N, 4, 4) array of homogeneous transforms ``T_base_target``;
- an (N, 7) array of rows ``x y z qx qy qz qw`` (quaternions normalised if not unit);
- an (N, 3) array of positions (position-only targets);
- a sequence of anything ``Arm.solve`` accepts (``pinocchio.SE3``, 4x4, ``(position,
  quaternion)``, ...), read one by one with ``armik.targets.parse_target``. Either every
  element carries an orientation or none does;
- a spatialmath ``SE3`` holding N poses;
- a list or tuple of objects of a class with a registered spelling
  (``armik.targets.pose.register_spelling``), each read by it.

Every target is checked as ``parse_target`` checks one (finite, its position within
``MAX_POSITION``, rotation orthonormal with determinant +1, last row (0, 0, 0, 1),
quaternion not zero) and an error names the index of the first bad target. Rotations within
``ROTATION_TOL`` of orthonormal are snapped onto the nearest rotation. To keep memory flat
for millions of targets, a ``TargetBatch`` read from an array may share memory with it
(positions and rotations as views): do not modify the array while it is being solved.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from armik.errors import InputError, TargetError
from armik.targets.aim import Aim
from armik.targets.pose import SPELLINGS, Target, parse_target, spelling_of
from armik.tolerances import LAST_ROW_TOL, MAX_POSITION, ROTATION_TOL

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


@dataclass(frozen=True, eq=False)
class TargetBatch:
    """N desired tip poses in the base frame (m). ``rotations`` is None for positions;
    ``aim``, ``along``: every target's (``Target``'s), or None."""

    positions: np.ndarray  # (N, 3)
    rotations: np.ndarray | None = None  # (N, 3, 3)
    aim: Aim | None = None
    along: tuple[float, float, float] | None = None

    def __len__(self) -> int:
        return len(self.positions)

    @property
    def position_only(self) -> bool:
        return self.rotations is None

    def matrices(self) -> np.ndarray:
        """(N, 4, 4) homogeneous transforms ``T_base_target`` (identity rotation for
        position targets)."""
        n = len(self)
        T = np.zeros((n, 4, 4))
        T[:, :3, :3] = np.eye(3) if self.rotations is None else self.rotations
        T[:, :3, 3] = self.positions
        T[:, 3, 3] = 1.0
        return T

    def target(self, i: int) -> Target:
        """Target ``i`` as the ``Target`` that ``Arm.solve`` reads."""
        # Contiguous copies: rows of a view are strided, and compiled code specialises on that.
        R = None if self.rotations is None else np.ascontiguousarray(self.rotations[i])
        return Target(np.ascontiguousarray(self.positions[i]), R, aim=self.aim, along=self.along)

    def __getitem__(self, index: slice | np.ndarray) -> TargetBatch:
        """A sub-batch (a slice or an index array: views where numpy gives views)."""
        if isinstance(index, (int, np.integer)):
            raise TypeError("index a TargetBatch with a slice or an array; .target(i) gives one")
        R = None if self.rotations is None else self.rotations[index]
        return TargetBatch(self.positions[index], R, self.aim, self.along)


def parse_targets(value: object, arm: ArmModel | None = None) -> TargetBatch:
    """Read many targets into a ``TargetBatch``; raises ``TargetError`` naming the index of
    the first bad target and what is wrong with it."""
    if isinstance(value, TargetBatch):
        return value
    if isinstance(value, (Target, str, bytes)) or np.isscalar(value):
        raise TargetError(
            f"expected many targets (an (N, 4, 4), (N, 7) or (N, 3) array, or a list of "
            f"targets), got {type(value).__name__}: use Arm.solve for one target"
        )
    if SPELLINGS and spelling_of(value) is not None:  # a class of the user's own
        raise TargetError(
            f"expected many targets, got one {type(value).__name__}: use Arm.solve for one "
            "target, or give a list of them"
        )
    if SPELLINGS and isinstance(value, (list, tuple)) and value and spelling_of(value[0]):
        return _from_sequence(value, arm)  # each read by its spelling (a tuple's too)
    if hasattr(value, "A") and hasattr(value, "__len__") and not isinstance(value, np.ndarray):
        # a spatialmath pose array (SE3 holding N poses): its matrices, one per pose
        A = value.A
        value = np.asarray(A if isinstance(A, list) else [A], dtype=float)
    arr = _numeric_array(value)
    if arr is not None:
        if arr.ndim == 3 and arr.shape[1:] == (4, 4):
            return _from_matrices(arr)
        if arr.ndim == 2 and arr.shape[1] == 7:
            return _from_rows7(arr)
        if arr.ndim == 2 and arr.shape[1] == 3:
            _finite_rows(arr, "position")
            if (np.abs(arr) > MAX_POSITION).any():
                _far(arr)
            return TargetBatch(arr)
        if arr.shape in ((4, 4), (7,), (3,), (2,)):
            raise TargetError(
                f"an array of shape {arr.shape} is one target: use Arm.solve, or give an "
                f"array of shape (N, {', '.join(map(str, arr.shape))}) for many"
            )
        if arr.ndim == 1 and arr.size == 0:
            return TargetBatch(np.zeros((0, 3)))
        if not (arr.ndim == 2 and arr.shape[1] == 2):  # (N, 2): planar, one by one below
            raise TargetError(
                f"cannot read targets from an array of shape {arr.shape}: give (N, 4, 4) "
                "transforms, (N, 7) rows x y z qx qy qz qw, (N, 3) positions, or a list of "
                "targets"
            )
    if not isinstance(value, (Sequence, np.ndarray)):
        raise TargetError(
            f"cannot read targets from {type(value).__name__}: give (N, 4, 4) transforms, "
            "(N, 7) rows x y z qx qy qz qw, (N, 3) positions, or a list of targets"
        )
    return _from_sequence(value, arm)


def _numeric_array(value: object) -> np.ndarray | None:
    """``value`` as a float array if it is one rectangular block of real numbers, else None
    (a ragged list, a list of objects). Complex input is refused, not truncated."""
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        return None
    if arr.dtype.kind == "c":
        raise TargetError("targets are complex numbers: give real coordinates (m) and rotations")
    if arr.dtype.kind not in "biuf":
        return None
    return arr.astype(float, copy=False)


def _finite_rows(arr: np.ndarray, what: str) -> np.ndarray:
    if np.isfinite(arr).all():  # the usual case, in one pass
        return arr
    bad = ~np.isfinite(arr).reshape(len(arr), int(np.prod(arr.shape[1:]))).all(axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise TargetError(
            f"target {i}: {what} contains NaN or inf: {arr[i].tolist()} "
            f"({int(bad.sum())} such target(s))"
        )
    return arr


def _far(p: np.ndarray) -> None:
    """The ``TargetError`` of positions ``p`` (N, 3) not all within ``MAX_POSITION`` of the
    base (``parse_target`` refuses one such), naming the first row beyond it."""
    rows = (np.abs(p) > MAX_POSITION).any(axis=1)
    i = int(np.flatnonzero(rows)[0])
    raise TargetError(
        f"target {i}: position {p[i].tolist()} is beyond {MAX_POSITION:g} m from the base "
        f"({int(rows.sum())} such target(s)): give positions in metres (no arm reaches this "
        "far, and the error arithmetic would overflow)"
    )


def _from_matrices(T: np.ndarray) -> TargetBatch:
    _finite_rows(T, "4x4 transform")
    last = np.abs(T[:, 3, :] - _LAST_ROW) > LAST_ROW_TOL
    if last.any():
        i = int(np.flatnonzero(last.any(axis=1))[0])
        raise TargetError(
            f"target {i}: the last row of a 4x4 target must be (0, 0, 0, 1), got {T[i, 3].tolist()}"
        )
    if (np.abs(T[:, :3, 3]) > MAX_POSITION).any():
        _far(T[:, :3, 3])
    return TargetBatch(T[:, :3, 3], _rotations(T[:, :3, :3]))


_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])


def _rotations(R: np.ndarray) -> np.ndarray:
    """Check N rotation matrices (orthonormal, det +1) and snap the near ones."""
    err = _orthonormality_error(R)
    bad = err > ROTATION_TOL
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise TargetError(
            f"target {i}: rotation is not orthonormal (|R^T R - I| = {err[i]:.2g}): give "
            "rotation matrices, or quaternions"
        )
    a = R  # the determinant by cofactors: ten times cheaper than numpy.linalg.det here
    det = (
        a[:, 0, 0] * (a[:, 1, 1] * a[:, 2, 2] - a[:, 1, 2] * a[:, 2, 1])
        - a[:, 0, 1] * (a[:, 1, 0] * a[:, 2, 2] - a[:, 1, 2] * a[:, 2, 0])
        + a[:, 0, 2] * (a[:, 1, 0] * a[:, 2, 1] - a[:, 1, 1] * a[:, 2, 0])
    )
    flipped = det < 0
    if flipped.any():
        i = int(np.flatnonzero(flipped)[0])
        raise TargetError(
            f"target {i}: rotation has determinant -1 (a reflection, not a rotation): "
            "flip the sign of one axis"
        )
    off = err > 1e-14
    if off.any():  # the nearest rotation, as parse_target does for one
        R = R.copy()
        U, _, Vt = np.linalg.svd(R[off])
        R[off] = U @ Vt
    return R


def _orthonormality_error(R: np.ndarray) -> np.ndarray:
    """max |R^T R - I| per matrix, from the six distinct dot products of the columns."""
    c = (R[:, :, 0], R[:, :, 1], R[:, :, 2])
    err = np.zeros(len(R))
    for i in range(3):
        for j in range(i, 3):
            d = np.einsum("ni,ni->n", c[i], c[j])
            if i == j:
                d -= 1.0
            np.maximum(err, np.abs(d), out=err)
    return err


def _from_rows7(rows: np.ndarray) -> TargetBatch:
    _finite_rows(rows, "row x y z qx qy qz qw")
    quat = rows[:, 3:]
    # Scale by the largest component first: squares of components near 1e154 would overflow.
    scale = np.abs(quat).max(axis=1)
    zero = ~(scale > 0)
    scaled = quat / np.where(zero, 1.0, scale)[:, None]
    norm = np.sqrt((scaled * scaled).sum(axis=1)) * scale
    zero |= norm < 1e-12
    if zero.any():
        i = int(np.flatnonzero(zero)[0])
        raise TargetError(
            f"target {i}: quaternion {quat[i].tolist()} has zero norm: give unit quaternions "
            "(x, y, z, w), e.g. (0, 0, 0, 1) for no rotation"
        )
    x, y, z, w = (scaled / np.linalg.norm(scaled, axis=1)[:, None]).T
    R = np.empty((len(rows), 3, 3))
    R[:, 0, 0] = 1 - 2 * (y * y + z * z)
    R[:, 0, 1] = 2 * (x * y - z * w)
    R[:, 0, 2] = 2 * (x * z + y * w)
    R[:, 1, 0] = 2 * (x * y + z * w)
    R[:, 1, 1] = 1 - 2 * (x * x + z * z)
    R[:, 1, 2] = 2 * (y * z - x * w)
    R[:, 2, 0] = 2 * (x * z - y * w)
    R[:, 2, 1] = 2 * (y * z + x * w)
    R[:, 2, 2] = 1 - 2 * (x * x + y * y)
    if (np.abs(rows[:, :3]) > MAX_POSITION).any():
        _far(rows[:, :3])
    return TargetBatch(rows[:, :3], R)


def _from_sequence(values: Sequence | np.ndarray, arm: ArmModel | None) -> TargetBatch:
    n = len(values)
    if n == 2 and _looks_like_one_pose(values):
        raise TargetError(
            "this is one (position, orientation) target: use Arm.solve, or give a list "
            "of such pairs for many"
        )
    positions = np.empty((n, 3))
    rotations = np.empty((n, 3, 3))
    has_rotation: bool | None = None
    for i, value in enumerate(values):
        try:
            t = parse_target(value, arm)
        except InputError as exc:
            raise TargetError(f"target {i}: {exc}") from None
        if has_rotation is None:
            has_rotation = t.rotation is not None
        elif has_rotation != (t.rotation is not None):
            kinds = ("a position", "a full pose") if has_rotation else ("a full pose", "a position")
            raise TargetError(
                f"target {i} is {kinds[0]} but target 0 is {kinds[1]}: give every target "
                "with an orientation, or every target as a position"
            )
        positions[i] = t.position
        if t.rotation is not None:
            rotations[i] = t.rotation
    return TargetBatch(positions, rotations if has_rotation else None)


def _looks_like_one_pose(values: Sequence | np.ndarray) -> bool:
    shapes = []
    for v in values:
        arr = _numeric_array(v) if not hasattr(v, "as_matrix") else np.zeros((3, 3))
        if arr is None:
            return False
        shapes.append(arr.shape)
    return shapes[0] == (3,) and shapes[1] in ((4,), (3, 3))
