"""The forward-kinematics check that every solver's answer passes through.

Errors are recomputed from the returned joints, never taken from a solver: Pinocchio
computes the tip placement (its forward kinematics is the source of truth), compiled code
(``armik.kernel.measure``) measures it against the target. Several answers of one target
(``measure_many``: ``solve_all``'s) are placed by armik's compiled FK instead, all in one
call with their errors and limits: it is Pinocchio's placement to 1e-12 on every arm the
tests load (tests/kernel/test_fk_checks.py, tests/model/test_fk_batch.py), errors of
1e-12 beside tolerances of 1e-6 or more. Position error:
|p_target - p_tip| (m). Orientation error: the geodesic angle |log3(R_tip^T R_target)|
(rad). Axes with zero weight (see ``Options.weights``) are not measured: the position error
is then taken in the tip frame on the weighted axes, the orientation error on the weighted
components of the rotation vector; for a position-only target the orientation error is
None (NaN in ``measure_batch``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from armik import reasons
from armik.frozen import frozen
from armik.kernel.measure import (
    fk_check_frame,
    fk_checks,
    pose_error,
    pose_errors,
    within_limits,
)
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.settings import SolverSettings
from armik.reasons import Cone
from armik.targets.aim import Aim, cone_words
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target
from armik.tolerances import LIMIT_TOL
from armik.verify.region import region_error, region_errors

_EYE = np.eye(3)  # read only by the kernel
_SAID = (False, False)  # no part left free: read without a call on the plain routes
_FLOAT = np.dtype(float)
_new = tuple.__new__  # an aim's ``Cone`` without a Python call (every aimed solve)


@dataclass(frozen=True)
class Measure:
    position_error: float
    orientation_error: float | None
    violations: list[str]
    tol_position: float
    tol_orientation: float
    region: bool = False  # the errors are the distances outside the target's bounds
    cone: Cone | None = None  # the aim's cone; the orientation error lies outside it
    # (position, rotation) left wholly free, not said (``SolverSettings.left_free``)
    free: tuple[bool, bool] = (False, False)

    @property
    def pose_ok(self) -> bool:
        ori_ok = self.orientation_error is None or self.orientation_error <= self.tol_orientation
        return self.position_error <= self.tol_position and ori_ok

    @property
    def ok(self) -> bool:
        return self.pose_ok and not self.violations

    def describe(self) -> str:
        pos = None if self.free[0] else self.position_error
        ori = None if self.free[1] else self.orientation_error
        if self.region:
            return reasons.region(pos, ori, self.tol_position, self.tol_orientation, self.cone)
        return reasons.measured(pos, ori, self.tol_position, self.tol_orientation)


class Measured(dict):
    """An arm's (weights (6,), weighted, orientation measured) under (``weights``,
    ``position_only``, a position target): what the check measures for those options and
    target kind, each built on its first lookup (``measured[key]``: a plain dict's lookup
    after that)."""

    def __missing__(self, key: tuple) -> tuple[np.ndarray, bool, bool]:
        weights, position_only_option, position_only_target = key
        w = SolverSettings(weights=weights, position_only=position_only_option).weight_vector(
            position_only_target
        )
        position_only = position_only_option or position_only_target
        measure_rot = not position_only and bool(w[3:].any())
        if len(self) > 256:
            self.clear()
        found = self[key] = (w, weights is not None, measure_rot)
        return found


MEASURED: Derived[Measured] = Derived("measured axes", lambda _: Measured())


def measures_of(arm: ArmModel, weights, position_only_option: bool, position_only_target: bool):
    """(weights (6,), weighted, orientation measured): what the check measures for these
    options (``weights``, ``position_only``) and target kind, kept per arm (``MEASURED``)."""
    return MEASURED(arm)[(weights, position_only_option, position_only_target)]


# (the compiled FK check's frame, orientation measured) under ``Measured``'s keys, per arm
FK_FRAMES: Derived[dict] = Derived("FK check frames", lambda _: {})


def measure(arm: ArmModel, q: np.ndarray, target: Target, opts: SolverSettings) -> Measure:
    """Measure ``q`` against ``target`` with Pinocchio FK and the joint limits."""
    model, data = arm.model, arm.data
    # Without continuous joints (one coordinate per joint) a float64 q is Pinocchio's
    # configuration itself (``to_pin`` would copy it).
    direct = type(q) is np.ndarray and q.dtype == _FLOAT and model.nq == arm.dof
    pin.forwardKinematics(model, data, q if direct else arm.to_pin(q))
    T = pin.updateFramePlacement(model, data, arm.tip_frame_id)
    measured = arm._derived.get(MEASURED)  # read as a dict, not through a call
    if measured is None:
        measured = MEASURED(arm)
    w, weighted, measure_rot = measured[(opts.weights, opts.position_only, target.rotation is None)]
    ch = arm.kernel_chain.chain
    aim = target.aim
    region = opts.bounds is not None or aim is not None
    if region:
        R_t = _EYE if target.rotation is None else target.rotation
        pos, ori = region_error(
            arm.T_base_world,
            T.rotation,
            T.translation,
            R_t,
            target.position,
            opts.region_bounds,
            w,
            *_aim_args(aim),
        )
        measure_rot = measure_rot or aim is not None  # an aim is measured, a position's too
    # C-ordered, writable float64 arrays: numba compiles anew for every other layout, and
    # Pinocchio's rotation is Fortran-ordered. ``T.homogeneous`` is a fresh C-ordered 4x4
    # whose top-left 3x3 block is the rotation: ``pose_error`` reads R_w[a, b] for a, b < 3
    # only. ``T.translation`` is a C-ordered view. The kernel only reads its arguments.
    else:
        pos, ori = pose_error(
            ch.base_R,
            ch.base_p,
            T.homogeneous,
            T.translation,
            _EYE if target.rotation is None else _c_float(target.rotation),
            _c_float(target.position),
            w,
            weighted,
            measure_rot,
        )
    violations = [] if arm._within(q.tolist()) else arm.limit_violations(q)
    return frozen(
        Measure,
        position_error=pos,
        orientation_error=ori if measure_rot else None,
        violations=violations,
        tol_position=opts.tol_position,
        tol_orientation=opts.tol_orientation,
        region=region,
        cone=None if aim is None else _new(Cone, (aim.within, aim.point is not None)),
        free=_SAID
        if opts.weights is None and opts.bounds is None
        else opts.left_free(target.rotation is None, aim is not None),
    )


def _aim_args(aim: Aim | None) -> tuple:
    """(cone, look-at point, direction) of a target's aim, as the region's measure takes
    them."""
    return (None, None, None) if aim is None else (aim.cone, aim.point, aim.toward)


def measure_many(
    arm: ArmModel, qs: list[np.ndarray], target: Target, opts: SolverSettings
) -> BatchMeasure:
    """The numbers of ``[measure(arm, q, target, opts) for q in qs]`` (two or more), as
    arrays, all in one compiled call: each answer placed by the compiled FK
    (``armik.kernel.measure.fk_checks``: Pinocchio's placement to 1e-12), its errors and
    limits; a region's errors from Pinocchio's placements, as ``measure`` measures them."""
    n = len(qs)
    if opts.bounds is not None or target.aim is not None:
        return _region_many(arm, qs, target, opts)
    key = (opts.weights, opts.position_only, target.rotation is None)
    frames = arm._derived.get(FK_FRAMES)  # read as a dict, not through a call
    found = None if frames is None else frames.get(key)
    if found is None:
        w, weighted, measure_rot = measures_of(arm, *key)
        frame = fk_check_frame(w, int(weighted) | (2 if measure_rot else 0), arm.lower, arm.upper)
        frames = FK_FRAMES(arm)
        if len(frames) > 256:
            frames.clear()
        found = frames[key] = (frame, measure_rot)
    frame, measure_rot = found
    Q = np.array(qs, dtype=float).reshape(n, arm.dof)  # C-ordered and writable
    H = np.eye(4)
    if target.rotation is not None:
        H[:3, :3] = target.rotation
    H[:3, 3] = target.position
    out = np.empty((n, 3))
    packed, kind, halton = arm.kernel_chain.flat
    fk_checks(packed, kind, halton, frame, H, Q, out)
    return BatchMeasure(
        out[:, 0],
        out[:, 1],  # NaN where the orientation is not measured
        out[:, 2] > 0.0,
        opts.tol_position,
        opts.tol_orientation,
        measure_rot,
        False,
        free=_SAID if opts.weights is None else opts.left_free(target.rotation is None, False),
    )


def _region_many(arm: ArmModel, qs: list[np.ndarray], target: Target, opts: SolverSettings):
    """``measure_many`` of a target with a region: Pinocchio's placements."""
    n = len(qs)
    direct = arm.model.nq == arm.dof
    rows = [q if direct and type(q) is np.ndarray and q.dtype == _FLOAT else arm.to_pin(q)
            for q in qs]  # fmt: skip
    R_w, p_w = _placements(arm, rows, [True] * n)
    R_t = np.empty((n, 3, 3))
    R_t[:] = _EYE if target.rotation is None else target.rotation
    p_t = np.empty((n, 3))
    p_t[:] = target.position
    position_only = target.rotation is None
    out, measure_rot = _errors(arm, R_w, p_w, R_t, p_t, opts, position_only, True, target.aim)
    within = np.array([arm._within(q.tolist()) for q in qs], dtype=np.bool_)
    return BatchMeasure(
        out[:, 0],
        out[:, 1] if measure_rot else np.full(n, math.nan),
        within,
        opts.tol_position,
        opts.tol_orientation,
        measure_rot,
        True,
        None if target.aim is None else cone_words(target.aim),
        opts.left_free(position_only, target.aim is not None),
    )


def _c_float(a: np.ndarray) -> np.ndarray:
    """``a`` itself when it is already a C-ordered, writable float64 array (a parsed
    target's arrays are), else such a copy."""
    if type(a) is np.ndarray and a.dtype == _FLOAT:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=float, order="C")


@dataclass(frozen=True)
class BatchMeasure:
    """The check of N answers as arrays: position_error (N,) m, orientation_error (N,) rad
    (NaN where not measured), within_limits (N,) bool, and the tolerances."""

    position_error: np.ndarray
    orientation_error: np.ndarray
    within_limits: np.ndarray
    tol_position: float
    tol_orientation: float
    rotation: bool = True  # the orientation is measured (else NaN throughout)
    region: bool = False  # the errors are the distances outside the target's region
    cone: Cone | None = None  # the aim's cone; the orientation error lies outside it
    # (position, rotation) left wholly free, not said (``SolverSettings.left_free``)
    free: tuple[bool, bool] = (False, False)

    @classmethod
    def of(cls, measures: list[Measure]) -> BatchMeasure:
        """The measures of one answer each, as arrays (at least one)."""
        first = measures[0]
        rotation = first.orientation_error is not None
        return cls(
            np.array([m.position_error for m in measures], dtype=float),
            np.array(
                [m.orientation_error if rotation else math.nan for m in measures], dtype=float
            ),
            np.array([not m.violations for m in measures], dtype=np.bool_),
            first.tol_position,
            first.tol_orientation,
            rotation,
            first.region,
            first.cone,
            first.free,
        )

    @property
    def pose_ok(self) -> np.ndarray:
        ori = self.orientation_error
        ori_ok = np.isnan(ori) | (ori <= self.tol_orientation)
        return (self.position_error <= self.tol_position) & ori_ok

    @property
    def ok(self) -> np.ndarray:
        """(N,) bool: within tolerance and within the limits: the only success there is."""
        return self.pose_ok & self.within_limits


def _placements(arm: ArmModel, rows, placed: list[bool]) -> tuple[np.ndarray, np.ndarray]:
    """(R_w (N, 3, 3), p_w (N, 3)): the tip placement of each of Pinocchio's
    configurations ``rows`` by Pinocchio's FK, NaN where ``placed`` is False."""
    model, data, fid = arm.model, arm.data, arm.tip_frame_id
    H_w = np.full((len(placed), 4, 4), np.nan)
    fk, place = pin.forwardKinematics, pin.updateFramePlacement
    for i, (qp, ok) in enumerate(zip(rows, placed)):
        if ok:
            fk(model, data, qp)
            H_w[i] = place(model, data, fid).homogeneous
    return np.ascontiguousarray(H_w[:, :3, :3]), np.ascontiguousarray(H_w[:, :3, 3])


def _errors(
    arm: ArmModel,
    R_w,
    p_w,
    R_t,
    p_t,
    opts: SolverSettings,
    position_only_target: bool,
    region: bool,
    aim: Aim | None = None,
):
    """(errors (N, 2), orientation measured): each placement's position and orientation
    errors against its target (rotations ``R_t``, positions ``p_t``, C-ordered float64),
    the distances outside the region where ``opts`` and the targets' ``aim`` give one
    (``region``: whether they do); NaN where the orientation is not measured. An aim is
    measured whatever the weights and the target's kind: its angle outside the cone."""
    measured = arm._derived.get(MEASURED)  # read as a dict, not through a call
    if measured is None:
        measured = MEASURED(arm)
    w, weighted, measure_rot = measured[(opts.weights, opts.position_only, position_only_target)]
    if region:
        out = region_errors(
            arm.T_base_world,
            R_w,
            p_w,
            R_t,
            p_t,
            np.array(opts.region_bounds),
            w,
            *_aim_args(aim),
        )
        measure_rot = measure_rot or aim is not None
        if not measure_rot:
            out[:, 1] = np.nan
        return out, measure_rot
    ch = arm.kernel_chain.chain
    out = np.empty((len(p_w), 2))
    pose_errors(ch.base_R, ch.base_p, R_w, p_w, R_t, p_t, w, weighted, measure_rot, out)
    return out, measure_rot


def measure_batch(
    arm: ArmModel, Q: np.ndarray, targets: TargetBatch, opts: SolverSettings
) -> BatchMeasure:
    """Measure row i of ``Q`` (N, dof) against target i, as ``measure`` does for one: Pinocchio
    FK for the placements, compiled code for the errors and the limits. A row with a
    non-finite value fails (NaN errors, outside the limits). For the violated joints of a row
    by name, call ``arm.limit_violations(Q[i])``."""
    Q = np.array(Q, dtype=float)  # a C-ordered, writable copy (what the kernel is built for)
    n = len(targets.positions)
    if Q.shape != (n, arm.dof):
        raise ValueError(f"Q must have shape ({n}, {arm.dof}), got {Q.shape}")
    finite = np.isfinite(Q).all(axis=1)  # a non-finite row: NaN placements and errors
    # Without continuous joints (one coordinate per joint) a row of Q is Pinocchio's
    # configuration itself: no conversion, no copy.
    rows = Q if arm.model.nq == arm.dof else map(arm.to_pin, Q)
    R_w, p_w = _placements(arm, rows, finite.tolist())
    R_t = targets.rotations
    if R_t is None:
        R_t = np.broadcast_to(_EYE, (n, 3, 3))
    R_t = np.array(R_t, dtype=float, order="C")
    p_t = np.array(targets.positions, dtype=float, order="C")
    aim = targets.aim
    region = opts.bounds is not None or aim is not None
    position_only = targets.rotations is None
    out, rotation = _errors(arm, R_w, p_w, R_t, p_t, opts, position_only, region, aim)
    ch = arm.kernel_chain.chain
    inside = np.empty(n, dtype=np.bool_)
    within_limits(Q, ch.lower, ch.upper, LIMIT_TOL, inside)
    tol_p, tol_r = opts.tol_position, opts.tol_orientation
    cone = None if aim is None else cone_words(aim)
    free = (
        _SAID
        if opts.weights is None and opts.bounds is None
        else opts.left_free(position_only, aim is not None)
    )
    return BatchMeasure(out[:, 0], out[:, 1], inside, tol_p, tol_r, rotation, region, cone, free)
