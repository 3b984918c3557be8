"""A globally planned path (``solve_path(..., plan="global")``): a ladder graph, as
ROS-Industrial's Descartes builds it, over every solution at every waypoint.

The rungs of a waypoint are every verified branch of its closed form (``solve_all``); a
joint whose limits allow more than one turn takes, at each step, the value of its branch
2 pi turns away that lies within the limits nearest the previous rung. An edge joins two
consecutive rungs where no joint moves by more than ``max_joint_step``; dynamic
programming keeps, for every rung, the least total joint motion (the sum of the steps'
Euclidean norms) from q0, and the path is read back from the best last rung. Where no edge
leaves a waypoint's rungs, every path breaks there: the waypoint is ``discontinuous`` with
the joint and the size of the smallest possible jump, and the plan goes on from every rung
after it. The first step is held to ``max_joint_step`` from q0 as every other; without q0
the path may start on any rung.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from armik import reasons
from armik.batch_result import BatchResult
from armik.errors import OptionError
from armik.kernel import ladder as kernel
from armik.model.arm_model import ArmModel
from armik.result import IKResult
from armik.solvers.registry import SolverSpec
from armik.status import Status


def check_plannable(spec: SolverSpec) -> None:
    """A ladder needs every solution of every waypoint: a closed form's."""
    if spec.kind == "numeric":
        raise OptionError(
            f"plan='global' needs every solution at every waypoint, which the numeric solver "
            f"{spec.name!r} does not give: use plan='follow', or on a 7-joint arm hold a "
            "joint (arm.with_locked) so that a closed form applies",
            option="plan",
            value="global",
        )


def plan(
    arm: ArmModel,
    rungs: list[list[IKResult]],
    q0: np.ndarray | None,
    step: np.ndarray,
    out: BatchResult,
) -> None:
    """The least-motion path over ``rungs`` (each waypoint's ``solve_all`` results) from
    ``q0`` (None: from any turn of any rung of the first waypoint), into ``out``'s rows
    (the dynamic programming in ``armik.kernel.ladder``)."""
    good = [[r for r in rs if r.success] for rs in rungs]
    offs = np.zeros(len(rungs) + 1, dtype=np.int64)
    offs[1:] = np.cumsum([len(g) for g in good])
    B = np.array([np.asarray(r.q) for g in good for r in g]).reshape(-1, arm.dof)
    lower, upper, no_period = arm._limit_lists
    start = np.zeros(arm.dof) if q0 is None else np.asarray(q0, dtype=float)
    rung, Q, broken, joint, size = kernel.plan(
        B, offs, start, q0 is not None, np.array(lower), np.array(upper),
        ~np.array(no_period, dtype=bool), np.asarray(step, dtype=float),
    )  # fmt: skip
    first = True
    for i, rs in enumerate(rungs):
        if rung[i] < 0:  # no solution at all: the waypoint's own failure
            out.put_result(i, rs[0])
            out.reasons[i] = rs[0].reason
            continue
        r = dataclasses.replace(good[i][int(rung[i] - offs[i])], q=Q[i])  # a turn: same pose
        if broken[i]:
            r = _broken(arm, r, int(joint[i]), float(size[i]), float(step[joint[i]]), first, out)
            out.reasons[i] = r.reason
        else:
            r = dataclasses.replace(r, reason=f"{r.reason}; planned over every branch")
        out.put_result(i, r)
        first = False


def _broken(arm, r: IKResult, j: int, size: float, step: float, first: bool, out) -> IKResult:
    unit = "m" if arm.prismatic[j] else "rad"
    start = "q0 (the start)" if first else "every solution of the waypoint before"
    measured = reasons.measured(
        r.position_error, r.orientation_error, out.tol_position, out.tol_orientation
    )
    return dataclasses.replace(
        r,
        success=False,
        status=Status.DISCONTINUOUS,
        reason=f"reachable only by a jump: every path breaks here: from {start}, the "
        f"smallest possible jump moves {arm.joint_names[j]} by {size:.3g} {unit} "
        f"(max_joint_step {step:g}); q is the planned answer, verified: {measured}",
    )
