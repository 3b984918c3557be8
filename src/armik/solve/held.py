"""7-joint arms with one joint held: ``arm.solve_all(T, hold={"joint": value})``.

Held at a value, the joint is a fixed transform and the other six form a 6R chain: the arm
with that joint locked (``ArmModel.with_locked``, built once per joint and value and kept, the
last ``KEPT``), solved by whichever solver applies to it ("auto": a closed-form family
when one fits, else the general 6R search); joint 7 of an arm in the ``swept`` class (the
Panda) by that solver's closed form at exactly the value. The answers are mapped back to
the 7 joints, the held joint at its value, and verified against the 7-joint arm's own FK
and limits like every answer. ``solve_all`` returns every solution with the joint there
(a redundant arm has infinitely many; these are the ones at that value), ``solve`` the
nearest q0.

``hold={"joint": None}`` holds the joint at q0's value (the middle of its limits without
q0). No sweep over other values: each held value is a 6R chain of its own (the ``swept``
solver sweeps joint 7 of a Panda-like arm, whose chain does not change with it).
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import replace
from typing import cast

import numpy as np

from armik import reasons
from armik.constraints.hold import Hold
from armik.errors import OptionError, SolverError
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.request import Request, with_seed
from armik.solvers import registry
from armik.solvers.answers import Answers
from armik.status import Status
from armik.targets.pose import Target, parsed
from armik.verify.verdict import finish

KEPT = 16  # locked arms kept per arm (one per joint and held value)


def held_joint(arm: ArmModel, hold: tuple[str, float | None], seed: np.ndarray):
    """(index, value) of the held joint, or an ``armik.errors`` error naming the bad value
    and the fix: an arm without 7 joints, an unknown joint, a value outside its limits."""
    name, value = hold
    if arm.dof != 7:
        raise OptionError(
            f"hold={{{name!r}: {value!r}}} here needs the closed form of a 7-joint arm with "
            f"one joint held; arm {arm.name!r} has {arm.dof} joints. The task solver holds "
            "it for a pose, a position or an aimed pose, or a target said as tasks "
            "(armik.Pose(T, weights=..., bounds=...), armik.Position(p), armik.LookAt), not "
            "for weights or rotation bounds with an aim; or solve on the arm with the joint "
            f"locked: arm.with_locked({{{name!r}: value}})",
            option="hold",
            value=name,
        )
    if value is not None:  # checked once per arm and value: a loop holds the same joint
        kept = arm._derived.get(_CHECKED)  # read as a dict, not through a call
        found = None if kept is None else kept.get(hold)
        if found is not None:
            return found
    held = Hold(name, value).at(arm, seed)  # a joint of the arm, a value within its limits
    found = held.index(arm), cast(float, held.value)
    if value is not None:
        kept = _CHECKED(arm)
        if len(kept) > 64:
            kept.clear()
        kept[hold] = found
    return found


# (index, value within the limits) of a held joint's (name, value), checked on this arm
_CHECKED: Derived[dict] = Derived("held joints checked", lambda _: {})


_KEPT: Derived[OrderedDict] = Derived("held arms", lambda _: OrderedDict())  # (name, value)


def locked_arm(arm: ArmModel, name: str, value: float):
    """``arm.with_locked({name: value})``, kept per arm (the last ``KEPT``)."""
    kept = _KEPT(arm)
    key = (name, value)
    sub = kept.get(key)
    if sub is None:
        sub = arm.with_locked({name: value})
        kept[key] = sub
        if len(kept) > KEPT:
            kept.popitem(last=False)
    else:
        kept.move_to_end(key)
    return sub


def solve_held(arm: ArmModel, req: Request, target, general):
    """The verified results of ``req``, a solve with a held joint (``hold=``; see the
    module), whose target is ``target`` (the stages parsed it): a list with ``every``,
    else one result. ``general``: ``armik.solve.stages``' general path, which
    solves the locked arm (passed in: that module calls this one)."""
    every = req.every
    opts = with_seed(req.opts, req.seed)
    seed = arm.seed(req.q0)
    tgt = target if type(target) is Target else parsed(target, arm)  # the stages parsed it
    held = Held(req, general)
    answers = held.run(arm, tgt, seed, opts, every)
    results = finish(arm, held.name, answers, tgt, opts, seed, every, req.t0)
    return results if every else results[0]


class Held:
    """The held solve as a solver the collision search runs (``armik.solve.avoid``): its
    ``run`` gives every answer at the held value, the whole arm's joints, unverified; its
    ``name`` is then the solver's that gave them. A closed form's branches, or the locked
    arm's every solution: the search checks them nearest first against the whole arm's
    collision model, as a closed form's."""

    kind = "analytic"

    def __init__(self, req: Request, general) -> None:
        self.req, self.general, self.name = req, general, req.solver

    def run(self, arm: ArmModel, tgt: Target, seed: np.ndarray, opts, every: bool) -> Answers:
        answers, self.name = _held_answers(arm, self.req, tgt, seed, opts, self.general)
        return answers


def _held_answers(arm: ArmModel, req: Request, tgt: Target, seed, opts, general):
    """(answers, solver name) of the held solve (see ``Held``)."""
    solver, t0 = req.solver, req.t0
    holds = cast("tuple[tuple[str, float | None], ...]", opts.hold)  # set: the caller checked
    if len(holds) != 1:
        raise OptionError(
            f"hold={dict(holds)!r} holds {len(holds)} joints; this solve holds one joint of a "
            "7-joint arm (a 6R chain): give the target as tasks (armik.Pose, armik.Position), "
            "which hold any joints, or lock them: arm.with_locked({...})",
            option="hold",
            value=dict(holds),
        )
    k, value = held_joint(arm, holds[0], seed)
    name = arm.joint_names[k]
    sweeping = _sweeping(arm, solver, req.key, k, tgt, opts)
    if sweeping is not None:  # a closed form at exactly that value (the Panda's joint 7)
        return sweeping.sweep.at_value(arm, tgt, seed, value), sweeping.name  # type: ignore[union-attr]
    sub = locked_arm(arm, name, value)
    asked_for = None  # a closed form of the whole arm asked for: "auto" solves the rest
    if solver != "auto" and _whole_arm_only(solver, arm, sub):
        asked_for, solver = solver, "auto"  # as a path passes its whole arm's choice (srs)
    free = np.delete(seed, k)
    # the checks and collisions are of the whole arm: its verdict and search run them
    alone = replace(opts, hold=None, checks=(), obstacles=(), self_collision=False)
    try:
        found = general(sub, tgt, free, solver, alone, True, t0)
    except SolverError as e:  # the solver named does not apply to the six joints left
        raise SolverError(
            f"with {name!r} held, six joints are left to solve: {e}",
            solver=solver,
            candidates=e.candidates,
        ) from None
    answers = Answers.of(
        [np.insert(np.asarray(r.q, dtype=float), k, value) for r in found],
        [Status.CONVERGED if r.success else r.status for r in found],
        [reasons.held(name, value, r.solver, _claim(r), asked_for) for r in found],
        arm.dof,
        iterations=[r.iterations for r in found],  # the six joints' search's counts
        restarts=[r.restarts for r in found],
        branch=[r.branch for r in found],
        singular=[r.singular for r in found],
    )
    return answers, found[0].solver if found else solver


def _sweeping(arm: ArmModel, solver: str, key: tuple | None, k: int, tgt: Target, opts):
    """The solver asked for (or for "auto", the first) that sweeps joint ``k`` and takes
    these options and target, or None: "auto"'s kept per arm under the request's ``key``
    (None: chosen every time), as the registry keeps its choice (applicability reads a
    target for its kind only)."""
    kept = arm._derived.get(_SWEEPING) if key is not None and solver == "auto" else None
    where = (key, k, tgt.rotation is None)
    if kept is not None and kept["generation"] == registry.generation and where in kept:
        return kept[where]
    asked = registry.sweeps(k) if solver == "auto" else [registry.get(solver)]
    held_by = (s for s in asked if s.sweep is not None and s.sweep.joint == k)
    found = next(
        (s for s in held_by if (s.declines(opts, target=tgt) or s.why_not(arm, tgt, opts)) is None),
        None,
    )
    if key is not None and solver == "auto":
        kept = arm._derived.get(_SWEEPING)
        if kept is None or kept["generation"] != registry.generation or len(kept) > 64:
            kept = arm._derived[_SWEEPING] = {"generation": registry.generation}
        kept[where] = found
    return found


_SWEEPING: Derived[dict] = Derived("held joints' sweeping solvers", lambda _: {})


def _claim(r) -> str:
    """What a result of the six joints left says of itself: a success's claim without the
    measure the whole arm's verdict writes again, a failure's words."""
    return reasons.claim_of(r.reason) if r.success else r.reason


def _whole_arm_only(solver: str, arm: ArmModel, sub: ArmModel) -> bool:
    """Whether ``solver`` is a closed form of the 7-joint arm that does not apply to the
    locked 6R arm (``srs``: "auto"'s choice for the whole arm, which a path hands on)."""
    spec = registry.get(solver)
    return (
        spec.kind == "analytic"
        and spec.declines(None) is None
        and spec.why_not(arm, None, None) is None
        and spec.why_not(sub, None, None) is not None
    )
