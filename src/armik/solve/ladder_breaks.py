"""Why a globally planned path breaks at a waypoint (``armik.solve.ladder``): its answer
made ``discontinuous`` in words (``broken_at``: a jump hidden inside every step onto it
and/or the smallest possible one), with where a path went on from without a jump where
one through another solution of the waypoint before goes on (``went_on_from``)."""

from __future__ import annotations

import dataclasses

import numpy as np

from armik import path_reasons
from armik.result import IKResult
from armik.status import Status


def went_on_from(i, rung, broken, has_q0, first, forbidden, onto) -> str | None:
    """Where a path that breaks at ``i`` went on from without a jump (the plan's last break
    or its start), where a solution of the waypoint before that the plan does not reach
    goes on to ``i`` in a step no jump hides in (``onto``: the steps' codes); else None."""
    if first or rung[i - 1] < 0 or not np.isin(onto, list(forbidden), invert=True).any():
        return None
    b = [k for k in range(i) if broken[k] and rung[k] >= 0]
    return f"waypoint {b[-1]}" if b else ("q0" if has_q0 else "its start")


def broken_at(arm, r: IKResult, j, size, step, hidden: bool, first, every, out, since=None):
    """``r`` (the planned answer at a waypoint every path breaks at) ``discontinuous``: the
    smallest possible jump moves joint ``j`` by ``size`` (over ``step``; -1: none) and/or a
    jump hides inside every step (``hidden``); ``since``: where a path went on from without
    a jump (``went_on_from``'s), else None."""
    measured = path_reasons.result_verified(r, out.tol_position, out.tol_orientation)
    smallest = None
    if j >= 0:
        unit = "m" if arm.prismatic[j] else "rad"
        smallest = (arm.joint_names[j], size, unit, step)
    return dataclasses.replace(
        r,
        success=False,
        status=Status.DISCONTINUOUS,
        reason=path_reasons.jump(
            path_reasons.every_path_breaks(every, first, hidden, smallest)
            if since is None
            else path_reasons.every_path_since_breaks(every, since, hidden, smallest),
            "the planned answer",
            measured,
        ),
    )
