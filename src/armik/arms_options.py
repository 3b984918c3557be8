"""Each chain's options from a robot's (``armik.Arms``): the held joints a chain has, and
its own joints' part of a posture over every joint; the rest as given. The options are
read once (``armik.solve.read``) for what they hold and spell, however given (``hold=``,
``armik.Hold``, ``secondary=``); each chain's solve reads its own part."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from armik.constraints.base import Constraint
from armik.constraints.hold import Hold
from armik.errors import JointError, OptionError, did_you_mean, listing
from armik.model.arm_model import ArmModel
from armik.problem.scores import Posture, fit_posture
from armik.solve.read import options as read_options

_PER_CHAIN = frozenset(("hold", "constraints", "secondary", "posture"))
_CHAIN_OWN = ("prefer", "solver")  # each chain's solve reads them: no setting


def per_chain(
    options: dict,
    chains: Mapping[str, ArmModel],
    columns: Mapping[str, np.ndarray],
    joint_names: Sequence[str],
) -> dict[str, dict]:
    """Each tip's options: its chain (``chains[tip]``, the robot's joints ``columns[tip]``)
    holds the held joints it has (``hold=``, ``Hold``s; a held joint on no chain is a
    ``JointError``) and follows its joints' part of a posture over every joint
    (``secondary=[armik.Posture(q_ref, weights)]``, ``prefer=armik.Posture(q_ref, weights)``:
    one value per joint of the robot)."""
    own = chain_constraints(options, chains)
    if own is not None:  # each tip's own constraints: added to its options last
        options = {k: v for k, v in options.items() if k != "constraints"}
        each = per_chain(options, chains, columns, joint_names)
        return {tip: _with(each[tip], own.get(tip, [])) for tip in chains}
    prefer = _posture(options.get("prefer"), joint_names)
    if not _PER_CHAIN.intersection(options) and prefer is None:
        return dict.fromkeys(chains, options)
    opts = read_options({k: v for k, v in options.items() if k not in _CHAIN_OWN})
    rest = {k: v for k, v in options.items() if k not in _PER_CHAIN}
    if "constraints" in options:  # read: a constraint or several; a ``Hold`` split by chain
        given = options["constraints"]  # None: none, as on one arm
        given = [given] if isinstance(given, Constraint) else () if given is None else given
        others = [c for c in given if type(c) is not Hold]
        if others:
            rest["constraints"] = others
    posture = opts.posture
    if posture is not None:  # over every joint of the robot, then split by chain
        fit_posture(len(posture[0]), joint_names, "the robot", "secondary")
    holds = opts.hold or ()
    for joint, value in holds:
        if joint not in joint_names:
            # a locked joint or a mimic joint is named as one, not as unknown
            why = next(
                filter(None, (Hold(joint, value).not_free(a) for a in chains.values())), None
            )
            why = why or _off_chains(joint, chains)
            raise JointError(
                why
                or f"hold: unknown joint {joint!r}; {did_you_mean(joint, joint_names)}the "
                f"joints of tips {list(chains)}: "
                f"{listing(joint_names)}",
                joint=joint,
                candidates=joint_names,
            )
    out = {}
    for tip, arm in chains.items():
        mine = {joint: value for joint, value in holds if joint in arm.joint_names}
        out[tip] = {**rest, "hold": mine} if mine else dict(rest)
        if posture is not None:
            q_ref, weights = (np.asarray(v)[columns[tip]] for v in posture)
            out[tip]["secondary"] = [Posture(q_ref, weights)]
        if prefer is not None:
            cols = columns[tip]
            out[tip]["prefer"] = Posture(prefer.q_ref[cols], prefer.weights[cols])
    return out


def _off_chains(joint: str, chains: Mapping[str, ArmModel]) -> str | None:
    """Why ``joint``, a joint of the URDF on none of ``chains``, cannot be held: a fixed
    joint, or off every chain; None for any other name."""
    arm = next(iter(chains.values()))
    kind = arm.info.joint_types.get(joint)
    if kind is None or kind == "fixed":
        return Hold(joint).off_chain(arm)
    return (
        f"hold: joint {joint!r} is on none of the chains of tips {list(chains)}: off them, "
        f"it is a fixed transform at its neutral value; set that with "
        f"robot.with_locked({{{joint!r}: value}})"
    )


def at_seed(each: dict[str, dict], joint_names: Sequence[str], seed: np.ndarray) -> dict:
    """Each tip's options (``per_chain``'s) with a joint held at None (q0's value) held at
    its value in ``seed`` (over ``joint_names``): the value q0 gives it wherever the
    chain's solve starts."""
    out = {}
    for tip, options in each.items():
        held = options.get("hold")
        if held and None in held.values():
            at = {j: float(seed[joint_names.index(j)]) if v is None else v for j, v in held.items()}
            options = {**options, "hold": at}
        out[tip] = options
    return out


def check_held(
    chains: Mapping[str, ArmModel],
    each: Mapping[str, dict],
    seeds: np.ndarray,
    columns: Mapping[str, np.ndarray],
) -> None:
    """A ``JointError`` for a held joint's value outside its limits, as a chain's solve
    says it, before any chain runs: each tip's held joints (``each``, ``per_chain``'s), a
    value of None at each row of ``seeds`` (rows over the robot's joints)."""
    for tip, options in each.items():
        arm = chains[tip]
        for joint, value in (options.get("hold") or {}).items():
            if value is None:
                column = seeds[:, columns[tip][arm.joint_names.index(joint)]]
                values = [float(column.min()), float(column.max())]
            else:
                values = [value]
            for v in values:
                Hold(joint, v).at(arm, arm.middle)


def _posture(prefer: object, joint_names: Sequence[str]) -> Posture | None:
    """``prefer=`` where it is a ``Posture`` (then split by chain), else None; an
    ``OptionError`` naming the robot's joints for one of another length (as for
    ``secondary=``)."""
    if not isinstance(prefer, Posture):
        return None
    fit_posture(prefer.q_ref.size, joint_names, "the robot", "prefer")
    return prefer


def refuse_own_checks(options: dict, tips: Sequence[str]) -> None:
    """An ``OptionError`` for a constraint of the user's own class in a flat list on
    several tips: its check reads one arm's joints, and which chain's is not said (dropping
    it would call answers that violate it successes); given by tip (``constraints={tip:
    [...]}``), each is its chain's, checked here (``chain_constraints``)."""
    if "constraints" not in options:
        return
    if isinstance(options["constraints"], Mapping):
        chain_constraints(options, tips)
        return
    own = read_options({"constraints": options["constraints"]}).checks
    if own:
        raise OptionError(
            f"constraints: {own[0]!r} checks one arm's joints; on several tips give it by "
            "the tip whose chain it checks (constraints={tip: [...]}), or solve that chain "
            "(robot.chain(tip).solve(..., constraints=[...]))",
            option="constraints",
            value=own[0],
        )


def chain_constraints(options: dict, tips: Iterable[str]) -> dict[str, list] | None:
    """``constraints=`` given by tip (tip -> a constraint or several, each checking that
    tip's chain as it would alone), checked: known tips, and checks of the user's own (a
    ``Hold`` or ``Collisions`` names what it acts on: the flat list takes it); None where
    ``constraints`` is no mapping."""
    given = options.get("constraints")
    if not isinstance(given, Mapping):
        return None
    tips = list(tips)
    out: dict[str, list] = {}
    for tip, value in given.items():
        if tip not in tips:
            raise OptionError(
                f"constraints: unknown tip {tip!r}; give each tip's constraints under one "
                f"of {tips}",
                option="constraints",
                value=tip,
            )
        try:
            items = [value] if isinstance(value, Constraint) else list(value)
        except TypeError:  # no constraint and no iterable of them
            raise OptionError(
                f"constraints[{tip!r}] must be a constraint or a list of them, got {value!r:.80}",
                option="constraints",
                value=value,
            ) from None
        for c in items:
            if not isinstance(c, Constraint) or c.said():
                raise OptionError(
                    f"constraints[{tip!r}] holds {c!r}: by tip, give constraints of your own "
                    "class (a check of that chain); armik.Hold and armik.Collisions go in "
                    "the flat list (constraints=[...]), which names what they act on",
                    option="constraints",
                    value=c,
                )
        out[tip] = items
    return out


def _with(options: dict, constraints: list) -> dict:
    """``options`` with ``constraints`` added to those it has."""
    if not constraints:
        return options
    had = options.get("constraints")
    before = [] if had is None else [had] if isinstance(had, Constraint) else list(had)
    return {**options, "constraints": [*before, *constraints]}


def held_apart(
    seeds: Mapping[str, np.ndarray],
    each: Mapping[str, dict],
    chains: Mapping[str, ArmModel],
    solved: Iterable[str],
) -> dict[str, np.ndarray]:
    """Each chain's seed (its joint values, or rows of them), where its tip is not among
    ``solved`` (given no target) with the joints its options ``each`` (``per_chain``'s)
    hold at their values (checked within the limits, as a chain's solve checks them): a
    chain left out keeps q0's values but for those, as over shared joints."""
    out = dict(seeds)
    done = set(solved)
    for tip, options in each.items():
        held = {j: v for j, v in (options.get("hold") or {}).items() if v is not None}
        if tip in done or not held:
            continue
        arm, q = chains[tip], np.array(seeds[tip], dtype=float)
        for joint, value in held.items():
            q[..., arm.joint_names.index(joint)] = Hold(joint, value).at(arm, arm.middle).value
        out[tip] = q
    return out
