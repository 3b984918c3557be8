"""SRS arms at one elbow swivel angle: ``arm.solve_all(T, swivel=psi)``.

A 7R arm's self-motion is one parameter. ``hold={"joint": value}`` fixes it by a joint
(``armik.solve.held``); on an SRS arm (the KUKA iiwa: a spherical shoulder, an elbow, a
spherical wrist) the natural parameter is no joint but the elbow's turn about the line
from the shoulder to the wrist, which keeps the tip where it is: ``swivel=psi`` (rad, the
convention of ``armik.solvers.closed_form.srs_kernel``). ``solve_all`` returns every
branch at that angle (up to 8), ``solve`` the nearest q0, each verified by Pinocchio FK
and the limits like every answer. ``armik.solvers.closed_form.srs.swivel_of(arm, q)``
reads a configuration's angle.
"""

from __future__ import annotations

from armik.errors import OptionError
from armik.model.arm_model import ArmModel
from armik.options import Options
from armik.solvers.closed_form import srs
from armik.targets.pose import parsed
from armik.verify.verdict import finish


def solve_swivel(arm: ArmModel, target, q0, solver: str, opts: Options, every: bool, t0: float):
    """The verified results at ``opts.swivel``: a list with ``every``, else one result.
    ``OptionError`` for an arm that is not SRS, another solver, a held joint, collisions,
    or a target or options the closed form does not take (a position, bounds, weights)."""
    psi = opts.swivel
    why = srs.applies(arm, None, None)
    if why is not None:
        raise OptionError(
            f"swivel={psi!r} is for 7R arms with a spherical shoulder and wrist (SRS, the KUKA "
            f"iiwa); arm {arm.name!r} is not one: {why}. Hold a joint instead: "
            "hold={joint: value}",
            option="swivel",
            value=psi,
        )
    if solver not in ("auto", srs.SPEC.name):
        raise OptionError(
            f"swivel= is solved by the {srs.SPEC.name!r} closed form, not {solver!r}: leave "
            "solver='auto'",
            option="swivel",
            value=psi,
        )
    if opts.hold is not None:
        raise OptionError(
            f"swivel= and hold={dict(opts.hold)!r} each fix the self-motion: give one",
            option="swivel",
            value=psi,
        )
    if opts.collisions:
        raise OptionError(
            "swivel= with obstacles or self_collision is not solved yet: solve_all(T, "
            "swivel=...) and check each answer with arm.min_distance",
            option="swivel",
            value=psi,
        )
    tgt = parsed(target, arm)
    why = srs.applies(arm, tgt, opts)
    if why is not None:
        raise OptionError(f"swivel={psi!r}: {why}", option="swivel", value=psi)
    seed = arm.seed(q0)
    answers = srs.at_swivel(arm, tgt, seed, float(psi))  # type: ignore[arg-type]
    results = finish(arm, srs.SPEC.name, answers, tgt, opts, seed, every, t0)
    return results if every else results[0]
