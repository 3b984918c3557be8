"""How a path of several tips (``Arms.solve_path``) judges its steps: a move larger than
``max_joint_step`` (``held``) and a jump hidden between two waypoints (``hidden_steps``),
as one arm's path judges them (``armik.solve.ladder``).

A hidden jump is looked for tip by tip, on each tip's chain (its columns of the rows), by
the rule one arm's path is judged by (``ladder.hidden_steps``): a step whose chain has no
solution at the halfway pose within the step of both ends has none for the robot either,
since the robot's configuration there would hold one for that chain.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from armik import path_reasons
from armik.batch_result import BatchResult
from armik.errors import ArmikError
from armik.request import but_options
from armik.result import IKResult
from armik.solve import ladder
from armik.solve.read import options as read_options
from armik.solve.turning import ANY
from armik.status import Status
from armik.targets.batch import parse_targets


def held(arms: Any, r: IKResult, q_prev: np.ndarray, step: np.ndarray, first: bool):
    """``r``, or ``r`` reported ``discontinuous`` when a joint moves by more than its step."""
    moved = np.abs(np.asarray(r.q) - q_prev)
    j = int(np.argmax(moved / step))
    if moved[j] <= step[j]:
        return r
    start = "q0 (the start)" if first else "the previous waypoint's answer"
    unit = "m" if arms.prismatic[j] else "rad"
    move = path_reasons.moved(arms.joint_names[j], moved[j], unit, start, step[j])
    return dataclasses.replace(
        r,
        success=False,
        status=Status.DISCONTINUOUS,
        reason=path_reasons.jump(
            path_reasons.jump_found(move),
            "that answer",
            f"position error {r.position_error:.3g} m",
        ),
    )


def hidden_steps(
    arms: Any, out: BatchResult, waypoints: Mapping[str, Any], step: np.ndarray, opts
) -> None:
    """Each success of ``out`` whose step from the row the path went on from hides a jump
    for some tip's chain made ``discontinuous``, in place, the reason naming the tip. Tips
    given poses or positions only (a task list, a ``Relative`` task, has no pose halfway);
    the halfway poses solved with ``opts``' tolerances, the chain free (a held joint is
    looser there: a jump may pass, none is made up); none where ``opts`` loosen the task
    (``position_only``, ``weights``, ``bounds``), which the halfway poses would not."""
    if opts.position_only or opts.weights is not None or opts.bounds is not None:
        return  # halfway solved as full poses: a step a looser task makes passes, never fails
    tols = {"tol_position": opts.tol_position, "tol_orientation": opts.tol_orientation}
    plain = but_options(read_options({}), **tols)
    for tip, rows in waypoints.items():
        try:
            targets = parse_targets(rows, arms._chains[tip])
        except ArmikError:
            continue
        chain, cols = arms._chains[tip], arms._columns[tip]
        part = BatchResult.for_arm(chain, len(out), out.solver, plain)
        part.q[:] = out.q[:, cols]
        part.success[:] = out.success
        part.status_code[:] = out.status_code
        errors = out.errors.get(tip)
        part.position_error[:] = out.position_error if errors is None else errors[:, 0]
        part.orientation_error[:] = out.orientation_error if errors is None else errors[:, 1]
        ladder.hidden_steps(chain, part, targets, step[cols], ("auto", plain, None, ANY))
        for k in np.flatnonzero(out.success & ~part.success).tolist():
            out.success[k] = False
            out.status_code[k] = Status.DISCONTINUOUS.code
            out.reasons[k] = f"{tip}: {part.reasons[k]}"
