"""Every reason text of a path's waypoints, written once: a waypoint reached through
intermediate poses, the best within max_joint_step, and why one is a jump (a move larger
than ``max_joint_step``, or every path breaking there)."""

from __future__ import annotations

from typing import Any

from armik import reasons


def best_within_step(reason: str, score: str, said: str, count: int) -> str:
    """A path's waypoint: the best by the preference ``score`` of ``count`` answers within
    max_joint_step of the previous one."""
    return f"{reason}; prefer={score}: {said}, the best of {count} answers within max_joint_step"


def through(reason: str, poses: int) -> str:
    """A waypoint reached continuously through ``poses`` intermediate poses."""
    return f"{reason}; reached through {poses} intermediate poses"


def jump_found(move: str) -> str:
    """Why a waypoint is a jump: the answer found makes ``move`` (``moved``)."""
    return f"the answer found {move}: add waypoints here or raise max_joint_step"


def continuous_but(move: str) -> str:
    """Why a waypoint is a jump: continuous motion reaches it, but in too large a step."""
    return f"the motion to it is continuous but {move}: add waypoints here or raise max_joint_step"


def not_continuous(move: str, poses: int) -> str:
    """Why a waypoint is a jump: no continuous motion through ``poses`` poses reaches it."""
    return (
        f"the nearest answer found {move}, and no continuous motion through {poses} "
        "intermediate poses reaches it (a singularity, a joint limit or a branch change on "
        "the way)"
    )


def every_path_breaks(
    every: bool, first: bool, hidden: bool, smallest: tuple[str, float, str, float] | None
) -> str:
    """Why a planned path's waypoint is a jump (``every``: over every solution, else the
    answers found; ``first``: from q0): a jump hidden inside every step (``hidden``)
    and/or the smallest possible one (joint, size, unit, max_joint_step)."""
    before = "every solution of" if every else "every answer found at"
    start = "q0 (the start)" if first else f"{before} the waypoint before"
    found = "" if every else "through the answers found "
    return f"every path {found}breaks here: from {start}, {_jumps(hidden, smallest)}"


def _jumps(hidden: bool, smallest: tuple[str, float, str, float] | None) -> str:
    """Why every step onto a waypoint is a jump: one hidden inside every step and/or the
    smallest possible one."""
    why = []
    if hidden:
        why.append(
            "every step within max_joint_step hides a jump between the waypoints (halfway, "
            "no solution lies near the step's middle: a singularity, a joint limit or the "
            "edge of the workspace crossed)"
        )
    if smallest is not None:
        joint, size, unit, step = smallest
        why.append(
            f"the smallest {'other ' if hidden else ''}possible jump moves "
            f"{joint} by {size:.3g} {unit} (max_joint_step {step:g})"
        )
    return "; ".join(why)


def planned_over(move: str) -> str:
    """Why a planned waypoint is a jump after all: the plan's step to it makes ``move``
    (``moved``), over the bound the plan is held to."""
    return f"the plan's step to it {move}, over the bound: no path planned within it"


VERIFIED = "verified by forward kinematics: "


def verified(reason: str, measured_text: str) -> str:
    """What a success's ``reason`` says after "verified by forward kinematics: " (its
    verdict's measure, a region's or the weighted axes' with the distances, a part left
    wholly free unsaid); ``measured_text`` where it says none."""
    for said in (VERIFIED, ", verified: "):  # a success's words, or a jump's (``jump``)
        at = reason.find(said)
        if at >= 0:
            return reason[at + len(said) :]
    return measured_text


def row_verified(rows: Any, k: int) -> str:
    """``verified`` of row ``k`` of a path's rows (a ``BatchResult``): where its reason
    says none, what its verdict measured (``measured``, else its distances)."""
    apart = rows.measured[k]
    if apart[0] == apart[0]:  # measured apart (weights, a region): not the distances
        errors = float(apart[0]), float(apart[1])
    else:
        errors = float(rows.position_error[k]), float(rows.orientation_error[k])
    return verified(
        rows.reason(k), reasons.measured(*errors, rows.tol_position, rows.tol_orientation)
    )


def result_verified(r: Any, tol_position: float, tol_orientation: float) -> str:
    """``verified`` of one result ``r``: where its reason says none, what its verdict
    measured (``r.measured``, else its distances)."""
    apart = r.measured
    pos, ori = (r.position_error, r.orientation_error) if apart is None else apart
    return verified(r.reason, reasons.measured(pos, ori, tol_position, tol_orientation))


def jump(why: str, answer: str, measured_text: str) -> str:
    """A waypoint reached only by a move larger than ``max_joint_step`` (``discontinuous``):
    ``why`` in words, ``answer`` what q is, ``measured_text`` its measure."""
    return f"reachable only by a jump: {why}; q is {answer}, verified: {measured_text}"


def moved(joint: str, size: float, unit: str, start: str, step: float) -> str:
    """A step beside its bound: 'moves panda_joint5 by 1.44 rad from the previous
    waypoint's answer (max_joint_step 0.3)'."""
    return f"moves {joint} by {size:.3g} {unit} from {start} (max_joint_step {step:g})"


def every_path_since_breaks(
    every: bool,
    since: str,
    hidden: bool,
    smallest: tuple[str, float, str, float] | None,
) -> str:
    """``every_path_breaks`` where a solution of the waypoint before that the plan does not
    reach goes on to this one within the bound: every path from ``since`` (the plan's last
    break, or its start) without a jump breaks here, and one through that solution breaks
    on its way to it."""
    why = _jumps(hidden, smallest)
    found = "" if every else "through the answers found "
    other = "solution" if every else "answer found"
    return (
        f"every path {found}from {since} without a jump breaks here (one through another "
        f"{other} of the waypoint before goes on here, but breaks on its way there): from "
        f"every {other} so reached at the waypoint before, {why}"
    )


def hidden_step(start: str) -> str:
    """Why a followed waypoint within max_joint_step of ``start`` is a jump (a flip)."""
    return (
        f"the step from {start} is within max_joint_step but hides a jump between the "
        "waypoints (halfway, no solution lies near the step's middle and the joints moved "
        "straight leave the path: a flip across a singularity, a joint limit or the edge of "
        'the workspace): add waypoints here, or plan="global" to go round it'
    )
