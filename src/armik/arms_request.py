"""``ArmsRequest``: what a call on several tips (``armik.Arms``) reads of its keyword
options, read once per call at the facade, as one arm's ``armik.request.Request`` is.

``Arms.solve``, each row of a batch or a path (``armik.arms_many``, ``armik.arms_rows``,
the judge of a path's steps halfway) and ``solve_all``'s searches solve a row from it
(``Arms._solve_row``: the request, the row's parsed targets, its seed), never from the
keyword options again. It is picklable: a batch's chunks of rows carry it to threads,
processes and a Dask cluster.

- ``options``: the options as given (replayable: ``armik.solve.read.replayable``), which the
  checks between chains that share no joint read (``armik.arms_collision``);
- ``solver``: the name each chain's solver is asked by ("auto");
- ``prefer``: the preference as given (a callable cost of the whole configuration too);
- ``each``: each tip's own options (``arms_options.per_chain``: the held joints its chain
  has, its part of a posture over every joint, its constraints given by tip; its part of a
  ``Posture`` preference where the chains share no joint), without the solver; None
  without options;
- ``score``: the preference's score over chains that share joints (the descent over
  their union ranks by it), else None;
- ``together``: the settings of that descent (settings, their constraints unbound, their
  budget: ``descent_settings``) where the chains share joints, else None;
- ``kept``: those of the descent over chains that share no joint, solved together for a
  task relating them (``coupled``), read where a row first needs them and kept for the
  call's other rows (the request of a call without options is kept with the robot, and
  these with it: the same for every such call).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from armik.arms_options import chain_constraints, per_chain, refuse_own_checks
from armik.constraints.on_chain import OnChain
from armik.errors import OptionError
from armik.problem.scores import Manipulability, Posture, Score, fit_posture, parse_score
from armik.solve.read import options as read_options
from armik.solve.refused import check_options
from armik.solvers.registry import refuse_on_none, validate_name

if TYPE_CHECKING:
    from armik.constraints.base import Constraint
    from armik.model.union import Union
    from armik.problem.budget import Budget
    from armik.problem.settings import SolverSettings

UNION_ITERATIONS = 40  # a restart's descent over chains that share joints (``descent_settings``)
_OWN = ("prefer", "solver")  # each chain's solve reads them, not the descent's settings


class ArmsRequest(NamedTuple):
    """A call's keyword options as every step of ``Arms`` reads them (module docstring)."""

    options: dict[str, Any]
    solver: str
    prefer: object
    each: dict[str, dict] | None
    score: Score | None
    together: tuple[SolverSettings, tuple[Constraint, ...], Budget] | None
    kept: dict[str, Any]

    def chains_options(self, tips: Sequence[str]) -> dict[str, dict]:
        """Each tip's options as its chain's own solve takes them (``Arm.solve_all``,
        ``Arm.solve_batch``, ``Arm.solve_path``): its own part (``each``) and the solver
        where one was given."""
        each = self.each or {tip: {} for tip in tips}
        if "solver" not in self.options:
            return each
        return {tip: {**options, "solver": self.solver} for tip, options in each.items()}


def read_request(arms: Any, options: dict[str, Any]) -> ArmsRequest:
    """The request of ``options`` (an ``Arms`` call's, replayable) on ``arms``: refused by
    name where an option is not one or cannot apply; that of a call without options read
    once and kept with the robot."""
    if options:
        return _read(arms, options)
    found = arms._bare
    if found is None:
        found = arms._bare = _read(arms, options)
    return found  # type: ignore[no-any-return]


def _read(arms: Any, options: dict[str, Any]) -> ArmsRequest:
    if "constraints" in options:  # a flat list of the user's own checks: whose chain's?
        refuse_own_checks(options, arms.tips)
    solver = options.get("solver", "auto")
    prefer = options.get("prefer")
    union = arms._union
    chains, columns, names = arms._chains, arms._columns, arms.joint_names
    if union is None:  # each chain by its own solver, a preference split by chain
        if type(solver) is not str:
            validate_name(solver)
        own = {k: v for k, v in options.items() if k != "solver"}
        each = per_chain(own, chains, columns, names) if own else None
        return ArmsRequest(options, solver, prefer, each, None, None, {})
    score = None if prefer is None else score_of(arms, prefer)
    if solver != "auto":
        refuse_on_none(solver, chains)  # refused here, not skipped by the chains' starts
    joint = {k: v for k, v in options.items() if k not in _OWN}
    each = per_chain(joint, chains, columns, names) if joint else None
    together = descent_settings(arms, on_union(arms, union, joint))
    return ArmsRequest(options, solver, prefer, each, score, together, {})


def coupled(arms: Any, request: ArmsRequest) -> tuple:
    """``together`` over chains that share no joint, solved at once for a task relating
    them (``arms._joint()``): read on the first row that needs them, then kept in
    ``request.kept``; an ``OptionError`` for an option that descent does not take."""
    found = request.kept.get("coupled")
    if found is None:
        if request.solver != "auto":
            refuse_on_none(request.solver, arms._chains)
        joint = {k: v for k, v in request.options.items() if k not in _OWN}
        found = descent_settings(arms, on_union(arms, arms._joint(), joint))
        request.kept["coupled"] = found
    return found  # type: ignore[no-any-return]


def together_options(request: ArmsRequest) -> dict[str, dict] | None:
    """Each tip's options for its chain's start of one descent over chains that share no
    joint (a task relating them): ``each`` without the chain's part of the preference,
    which the descent's score says over every joint (over chains that share joints
    ``each`` is read without it)."""
    each = request.each
    if not each:
        return each
    return {tip: {k: v for k, v in o.items() if k != "prefer"} for tip, o in each.items()}


def on_union(arms: Any, union: Union, options: dict) -> dict:
    """``options`` over ``union``'s joints: each tip's own constraints (``constraints={tip:
    [...]}``) read that chain's joints of the union's answers (``OnChain``)."""
    own = chain_constraints(options, arms.tips) if "constraints" in options else None
    if own is None:
        return options
    names = union.joint_names
    on = []
    for tip, given in own.items():
        columns = np.array([names.index(n) for n in arms._chains[tip].joint_names])
        on += [OnChain(c, tip, columns) for c in given]
    return {**options, "constraints": on}


def descent_settings(arms: Any, options: dict) -> tuple:
    """(settings, their constraints unbound, their budget): the descent's over every
    chain's joints, ``options`` read and checked, a descent of ``UNION_ITERATIONS``
    unless they say otherwise; those of a call without options read once and kept."""
    if not options and arms._plain is not None:
        return arms._plain  # type: ignore[no-any-return]
    aimed = next((k for k in ("cone", "look_at", "toward") if k in options), None)
    if aimed is not None:  # a target's aim: one descent over every joint takes tasks
        raise OptionError(
            f"{aimed} is not taken where several tips are solved together (chains that "
            "share joints, or a task relating them): say it as a task of the tip, "
            "armik.Axis(..., frame=tip) or armik.LookAt(..., frame=tip)",
            option=aimed,
            value=options[aimed],
        )
    opts = read_options(options)
    check_options(opts, "auto", several_tips=True)
    if "max_iterations" not in options:
        # short descents, many restarts: over every chain's joints a descent that has not
        # closed in after 40 steps seldom does (TALOS's hands: 3 misses in 1200 targets
        # against 11 with the default 100), and one closing in goes on (solve_tasks)
        opts = dataclasses.replace(opts, max_iterations=UNION_ITERATIONS)
    found = (opts, opts.constraints, opts.budget)
    if not options:
        arms._plain = found
    return found


def score_of(arms: Any, prefer: object) -> Score | None:
    """The score of ``prefer=`` over shared joints (moved along the tasks' null space,
    ``solve_tasks``), or None; an ``OptionError`` where it means nothing over several tips."""
    if isinstance(prefer, Posture):  # one value a joint of the robot, said so
        fit_posture(prefer.q_ref.size, arms.joint_names, "the robot", "prefer")
    score = parse_score(prefer, arms)
    if score is None:
        return None
    if arms._union is None:
        raise OptionError(
            f"prefer={prefer!r} is not available on tips placed relative to each other "
            "that share no joint: drop prefer=, or solve each chain "
            "(Arms.chain(tip).solve(..., prefer=...))",
            option="prefer",
            value=prefer,
        )
    if isinstance(score, Manipulability):
        raise OptionError(
            f"prefer='manipulability' over the joints {list(arms.shared)} shared by "
            f"several tips: the measure is of one tip's Jacobian; use 'nearest', "
            "'limits', armik.Posture(q_ref, weights) or a cost over every joint",
            option="prefer",
            value=prefer,
        )
    return score
