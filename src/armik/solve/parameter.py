"""A redundant arm's self-motion fixed by a parameter its solver declares: ``swivel=psi``.

A 7R arm's self-motion is one parameter. ``hold={"joint": value}`` fixes it by a joint
(``armik.solve.held``); a solver may declare another (``registry.Parameter``): on an SRS
arm (the KUKA iiwa) the natural one is no joint but the elbow's turn about the line from
the shoulder to the wrist, which keeps the tip where it is: ``swivel=psi`` (rad, the
convention of ``armik.solvers.closed_form.srs_kernel``). ``solve_all`` returns every branch
at that value, ``solve`` the nearest q0, each verified by Pinocchio FK and the limits like
every answer. This stage asks the registry which solver declares the option; it names none.
"""

from __future__ import annotations

from armik.errors import OptionError
from armik.model.arm_model import ArmModel
from armik.request import Request, with_seed
from armik.solvers import registry
from armik.targets.pose import parsed
from armik.verify.verdict import finish


def solve_at(arm: ArmModel, req: Request, option: str, value: float):
    """The verified results at ``option=value``: a list with ``req.every``, else one result.
    ``OptionError`` where no solver declaring the option applies to the arm, for another
    solver, a held joint, collisions, or a target the solver does not take."""
    target, q0, solver, opts, _, seed, every, t0 = req[:8]
    declared = registry.declaring(option)
    why = {s.name: s.why_not(arm, None, None) for s in declared}
    spec = next((s for s in declared if why[s.name] is None), None)
    if spec is None or spec.parameter is None:
        words = declared[0].parameter.words if declared and declared[0].parameter else option
        said = "; ".join(f"{name}: {text}" for name, text in why.items()) or "none declares it"
        raise OptionError(
            f"{option}={value!r} fixes {words}; no solver of it applies to arm {arm.name!r} "
            f"({said}). Hold a joint instead: hold={{joint: value}}",
            option=option,
            value=value,
        )
    if solver not in ("auto", spec.name):
        raise OptionError(
            f"{option}= is solved by the {spec.name!r} solver, not {solver!r}: leave solver='auto'",
            option=option,
            value=value,
        )
    if opts.hold is not None:
        raise OptionError(
            f"{option}= and hold={dict(opts.hold)!r} each fix the self-motion: give one",
            option=option,
            value=value,
        )
    if opts.collisions:
        raise OptionError(
            f"{option}= with obstacles or self_collision is not solved yet: solve_all(T, "
            f"{option}=...) and check each answer with arm.min_distance",
            option=option,
            value=value,
        )
    tgt = parsed(target, arm)
    opts = with_seed(opts, seed)
    why_target = spec.declines(opts, target=tgt) or spec.why_not(arm, tgt, opts)
    if why_target is not None:
        raise OptionError(f"{option}={value!r}: {why_target}", option=option, value=value)
    start = arm.seed(q0)
    answers = spec.parameter.at_value(arm, tgt, start, float(value))
    results = finish(arm, spec.name, answers, tgt, opts, start, every, t0)
    return results if every else results[0]
