"""The true distances of an answer to its target, beside what its verdict measured.

A request with weights on the axes or a region around the target (bounds, a cone, a
look-at) is verified on what it asks for: the weighted axes, the distances outside the
region. A result reports the true distances all the same, one rule for every request:
``position_error`` (m) is the tip's distance to the target's position, whatever the
weights and bounds (an infinite one included); ``orientation_error`` (rad) the geodesic
angle to the target's rotation (a cone on a pose, a spin left free included), or, where
the target has no rotation of its own but aims the tip's axis (a look-at's point, a
direction given by ``toward``, an ``armik.Axis`` lowered to a pose: ``Target.along``),
that axis' angle to its direction; None where the target has neither or ``position_only``
ignores the rotation. A target that holds no position (an aim whose bounds free x, y and
z: ``armik.Axis``, ``armik.LookAt`` alone) has no ``position_error`` (None; NaN in a
batch), as the servo and the task solver say. What the verdict measured is kept under its
own name, ``IKResult.measured`` (``extra["measured"]``, a batch's ``measured`` columns),
and a success's reason says both.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from armik import reasons
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.reasons import Cone
from armik.result import IKResult
from armik.targets.aim import Aim, cone_words
from armik.targets.batch import TargetBatch
from armik.verify.measure import BatchMeasure, measure, measure_batch

_new = tuple.__new__


def plain(opts: SolverSettings, region: bool) -> SolverSettings:
    """``opts`` measuring the distances themselves: no weights; a region (``region``:
    bounds or an aim) shrunk to its centre, every bound 0, so that its distances are
    measured as the prepared plan measures them (``verify.region``), to the bit."""
    bounds = (0.0,) * 6 if region else None
    return frozen(type(opts), **{**opts.__dict__, "weights": None, "bounds": bounds})


def frees_position(opts: SolverSettings, aim: object) -> bool:
    """Whether ``opts``' bounds free x, y and z beside an ``aim`` (None: none)."""
    b = opts.bounds
    return aim is not None and b is not None and b[0] == b[1] == b[2] == math.inf


def holds_no_position(opts: SolverSettings, aim: Aim | None, along: tuple | None) -> bool:
    """Whether a target with ``aim`` (None: none) holds no position: what ``armik.Axis``
    (``along``: its axis) and ``armik.LookAt`` alone lower to, the aim in place of the
    rotation and the bounds freeing x, y and z. A pose whose bounds free its position
    holds it all the same, a cone about one of its axes too: its distance is the tip's."""
    if not frees_position(opts, aim):
        return False
    return along is not None or aim.point is not None or aim.toward is not None  # type: ignore[union-attr]


def distance_aim(aim: Aim | None, along: tuple | None) -> Aim | None:
    """The aim the true orientation distance is measured by, 0 wide: a look-at's or a
    direction's (``toward``), or the axis an ``armik.Axis`` lowered to a pose holds
    (``along``); None where the target's rotation is its own (a cone on a pose too): the
    geodesic angle to it."""
    if aim is not None and (aim.point is not None or aim.toward is not None):
        return aim.centred()
    if along is None:
        return None
    return aim.centred() if aim is not None else _new(Aim, (along, 0.0, None, None))


def axis_words(aim: Aim | None, along: tuple | None) -> Cone | None:
    """What a result's distances call the tip's axis where its orientation distance is
    that axis' angle (``distance_aim``); None where it is the angle to the rotation."""
    if aim is not None and (aim.point is not None or aim.toward is not None or along is not None):
        return cone_words(aim)
    return None if along is None else _new(Cone, (0.0, False))


def with_distances(arm: ArmModel, results: list[IKResult], target, opts: SolverSettings) -> list:
    """``results`` of a request measured apart (weights, a region): each with its true
    distances to ``target`` (Pinocchio's FK), the verdict's measure kept as ``measured``."""
    aim, along = target.aim, target.along
    distance = plain(opts, opts.bounds is not None or aim is not None)
    at = target.aimed(distance_aim(aim, along))
    weighted = opts.weights is not None
    said = axis_words(aim, along)
    no_position = holds_no_position(opts, aim, along)
    out = []
    for r in results:
        m = measure(arm, r.q, at, distance)
        pos, ori = None if no_position else m.position_error, m.orientation_error
        out.append(_apart(r, pos, ori, weighted, said))
    return out


_CLEAR = "; " + reasons.clear(None, 0.0, 0.0).partition(":")[0] + ":"  # "; collision-free:"


def _cleared(reason: str, pos, ori, weighted: bool, said: Cone | None) -> str:
    """A success's reason measured apart (``reasons.measured_apart``) whose collision check
    spoke first (``solve_all`` with obstacles): the distances said after what the verdict
    measured, as ``solve`` says them, its closest pair after them."""
    measured, clear, rest = reason.partition(_CLEAR)
    return reasons.measured_apart(measured, pos, ori, weighted, said) + clear + rest


def _apart(r: IKResult, pos, ori, weighted: bool, said: Cone | None) -> IKResult:
    words = _cleared(r.reason, pos, ori, weighted, said) if r.success else r.reason
    return dataclasses.replace(
        r,
        position_error=pos,
        orientation_error=ori,
        reason=words,  # a success's words say both; a failure's say why it failed
        extra={**r.extra, "measured": (r.position_error, r.orientation_error)},
    )


def fields_apart(fields: dict, pos, ori: float | None, weighted: bool, said: Cone | None) -> tuple:
    """The fields of a prepared solve's result (``armik.verify.verdict.claimed_verdict``)
    given its true distances, in place, its reason saying both (``said``: ``axis_words``);
    returns the verdict's measure, for the result's ``extra["measured"]``."""
    measured = (fields["position_error"], fields["orientation_error"])
    fields["position_error"], fields["orientation_error"] = pos, ori
    reason = fields.pop("_reason", None)
    if reason is not None:
        fields["_reason"] = (_said_apart, (reason, pos, ori, weighted, said))
    else:
        fields["reason"] = reasons.measured_apart(fields["reason"], pos, ori, weighted, said)
    return measured


def _said_apart(reason: tuple, pos, ori: float | None, weighted: bool, said) -> str:
    # ``reason``: ``verify.verdict.success_reason`` and its arguments
    return reasons.measured_apart(reason[0](*reason[1]), pos, ori, weighted, said)


def batch_distances(arm: ArmModel, Q: np.ndarray, targets: TargetBatch, opts: SolverSettings):
    """The true distances of a batch's answers ``Q`` to their targets (``BatchMeasure``)."""
    aim, along = targets.aim, targets.along
    at = TargetBatch(targets.positions, targets.rotations, distance_aim(aim, along), along)
    m: BatchMeasure = measure_batch(
        arm, Q, at, plain(opts, opts.bounds is not None or aim is not None)
    )
    if holds_no_position(opts, aim, along):
        return np.full(len(Q), math.nan), m.orientation_error
    return m.position_error, m.orientation_error
