"""The true distances of an answer to its target, beside what its verdict measured.

A request with weights on the axes or a region around the target (bounds, a cone, a
look-at) is verified on what it asks for: the weighted axes, the distances outside the
region. A result reports the true distances all the same: ``position_error`` (m) is the
tip's distance to the target's position, ``orientation_error`` (rad) the geodesic angle to
its rotation (None where the target has none or ``position_only`` ignores it), or to the
direction an axis should point along; a component a region leaves free (an infinite
bound) is no part of the target and does not count. A target that holds no position (an
aim whose bounds free x, y and z: ``armik.Axis``, ``armik.LookAt`` alone) has no
``position_error`` (None; NaN in a batch), as the servo and the task solver say. What the
verdict measured is kept under its own name, ``IKResult.measured`` (``extra["measured"]``,
a batch's ``measured`` columns), and a success's reason says both.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from armik import reasons
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.result import IKResult
from armik.targets.aim import cone_words
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target
from armik.verify.measure import BatchMeasure, measure, measure_batch


def plain(opts: SolverSettings) -> SolverSettings:
    """``opts`` measuring the distances themselves: no weights, a region shrunk to its
    centre (each finite bound 0; an infinite one frees its component, which is then no
    part of the target). A target's aim is shrunk by ``centred``."""
    changes: dict = {"weights": None}
    if opts.bounds is not None:
        changes["bounds"] = tuple(0.0 if math.isfinite(b) else b for b in opts.bounds)
    return frozen(type(opts), **{**opts.__dict__, **changes})


def holds_no_position(opts: SolverSettings, aim: object) -> bool:
    """Whether a target with ``aim`` (None: none) holds no position: its bounds free x, y
    and z beside the aim, what ``armik.Axis`` and ``armik.LookAt`` alone lower to. A pose
    whose bounds free its position is 0 m from it, in no component; an aim replaces the
    rotation, and with the position free nothing of a pose is left."""
    b = opts.bounds
    return aim is not None and b is not None and b[0] == b[1] == b[2] == math.inf


def centred(target: Target) -> Target:
    """``target`` with its aim 0 wide: the angle of the tip's axis to the direction it
    should point along is its distance (the target's rotation otherwise an artefact of the
    axis' lowering)."""
    aim = target.aim
    return target if aim is None else target.aimed(aim.centred())


def with_distances(arm: ArmModel, results: list[IKResult], target, opts: SolverSettings) -> list:
    """``results`` of a request measured apart (weights, a region): each with its true
    distances to ``target`` (Pinocchio's FK), the verdict's measure kept as ``measured``."""
    distance = plain(opts)
    at = centred(target)
    weighted = opts.weights is not None
    aim = getattr(target, "aim", None)
    region = opts.bounds is not None or aim is not None
    cone = cone_words(aim)
    no_position = holds_no_position(opts, aim)
    out = []
    for r in results:
        m = measure(arm, r.q, at, distance)
        pos, ori = None if no_position else m.position_error, m.orientation_error
        out.append(_apart(r, pos, ori, weighted, region, m.free, cone))
    return out


def _words(
    reason: str, pos, ori, weighted: bool, region: bool, free=(False, False), cone=None
) -> str:
    """A success's reason measured apart: the verdict's words, then the distances, to the
    region's centre (its free components left out; ``free``: a part wholly free, not
    said) where the target is a region, in an aim's terms where it has one (``cone``)."""
    return reasons.measured_apart(reason, pos, ori, weighted, region or not weighted, free, cone)


_CLEAR = "; " + reasons.clear(None, 0.0, 0.0).partition(":")[0] + ":"  # "; collision-free:"


def _cleared(reason: str, pos, ori, weighted: bool, region: bool, free: tuple, cone) -> str:
    """``_words`` of a success whose collision check spoke first (``solve_all`` with
    obstacles): the distances said after what the verdict measured, as ``solve`` says
    them, its closest pair after them."""
    measured, clear, rest = reason.partition(_CLEAR)
    return _words(measured, pos, ori, weighted, region, free, cone) + clear + rest


def _apart(r: IKResult, pos, ori, weighted: bool, region: bool, free: tuple, cone) -> IKResult:
    said = _cleared(r.reason, pos, ori, weighted, region, free, cone) if r.success else r.reason
    return dataclasses.replace(
        r,
        position_error=pos,
        orientation_error=ori,
        reason=said,  # a success's words say both; a failure's say why it failed
        extra={**r.extra, "measured": (r.position_error, r.orientation_error)},
    )


def fields_apart(fields: dict, pos: float, ori: float | None, weighted: bool) -> tuple:
    """The fields of a prepared solve's result (``armik.verify.verdict.claimed_verdict``)
    given its true distances, in place, its reason saying both; returns the verdict's
    measure, for the result's ``extra["measured"]``."""
    measured = (fields["position_error"], fields["orientation_error"])
    fields["position_error"], fields["orientation_error"] = pos, ori
    said = fields.pop("_reason", None)
    if said is not None:
        fields["_reason"] = (_said_apart, (said, pos, ori, weighted))
    else:
        fields["reason"] = reasons.measured_apart(
            fields["reason"], pos, ori, weighted, not weighted
        )
    return measured


def _said_apart(said: tuple, pos: float, ori: float | None, weighted: bool) -> str:
    # ``said``: ``verify.verdict.success_reason`` and its arguments, whose seventh says
    # whether the verdict measured a region, the eighth its aim, the ninth the parts free
    region = len(said[1]) > 6 and bool(said[1][6])
    cone = said[1][7] if len(said[1]) > 7 else None
    free = said[1][8] if len(said[1]) > 8 else (False, False)
    return _words(said[0](*said[1]), pos, ori, weighted, region, free, cone)


def batch_distances(arm: ArmModel, Q: np.ndarray, targets: TargetBatch, opts: SolverSettings):
    """The true distances of a batch's answers ``Q`` to their targets (``BatchMeasure``)."""
    aim = targets.aim
    if aim is not None:
        targets = TargetBatch(targets.positions, targets.rotations, aim.centred())
    m: BatchMeasure = measure_batch(arm, Q, targets, plain(opts))
    if holds_no_position(opts, aim):
        return np.full(len(Q), math.nan), m.orientation_error
    return m.position_error, m.orientation_error
