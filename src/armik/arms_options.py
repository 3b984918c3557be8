"""Each chain's options from a robot's (``armik.Arms``): the held joints a chain has, and
its own joints' part of a posture over every joint; the rest as given."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from armik.constraints.hold import Hold
from armik.errors import JointError, OptionError, listing
from armik.model.arm_model import ArmModel
from armik.options import spelled
from armik.problem.scores import Posture, fit_posture

_PER_CHAIN = frozenset(("hold", "constraints", "secondary", "posture"))


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
    prefer = _posture(options.get("prefer"), joint_names)
    if not _PER_CHAIN.intersection(options) and prefer is None:
        return dict.fromkeys(chains, options)
    rest = spelled(options)
    posture = rest.pop("posture", None)
    if posture is not None:  # over every joint of the robot, then split by chain
        fit_posture(len(posture[0]), joint_names, "the robot", "secondary")
    given = rest.pop("hold", None)
    holds = () if given is None else Hold.parse(given)
    for h in holds:
        if h.joint not in joint_names:
            raise JointError(
                f"hold: unknown joint {h.joint!r}; the joints of tips {list(chains)}: "
                f"{listing(joint_names)}",
                joint=h.joint,
                candidates=joint_names,
            )
    out = {}
    for tip, arm in chains.items():
        mine = {h.joint: h.value for h in holds if h.joint in arm.joint_names}
        out[tip] = {**rest, "hold": mine} if mine else dict(rest)
        if posture is not None:
            q_ref, weights = (np.asarray(v)[columns[tip]] for v in posture)
            out[tip]["secondary"] = [Posture(q_ref, weights)]
        if prefer is not None:
            cols = columns[tip]
            out[tip]["prefer"] = Posture(prefer.q_ref[cols], prefer.weights[cols])
    return out


def _posture(prefer: object, joint_names: Sequence[str]) -> Posture | None:
    """``prefer=`` where it is a ``Posture`` (then split by chain), else None; an
    ``OptionError`` naming the robot's joints for one of another length (as for
    ``secondary=``)."""
    if not isinstance(prefer, Posture):
        return None
    fit_posture(prefer.q_ref.size, joint_names, "the robot", "prefer")
    return prefer


def refuse_own_checks(options: dict) -> None:
    """An ``OptionError`` for a constraint of the user's own class on several tips: its
    check reads one arm's joints, and which (a chain's, the robot's) is not said; dropping
    it would call answers that violate it successes."""
    if "constraints" not in options:
        return
    own = spelled({"constraints": options["constraints"]}).get("checks", ())
    if own:
        raise OptionError(
            f"constraints: {own[0]!r} checks one arm's joints; on several tips give "
            "armik.Hold and armik.Collisions, or solve each tip's chain "
            "(robot.chain(tip).solve(..., constraints=[...]))",
            option="constraints",
            value=own[0],
        )
