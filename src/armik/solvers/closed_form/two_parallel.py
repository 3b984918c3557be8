"""IK of 6R arms with axes 2 and 3 parallel and nothing else, by a one-dimensional search
over q1 (IK-Geo's ``IK_2_parallel``): the classifier and the solver's registration. The
search's equations and branches are in ``search_q1``, its zero finder in ``search_zeros``.
Up to 16 solutions; branch labels as the closed forms read them, numbered where two
solutions share one ("...#2").
"""

from __future__ import annotations

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.solvers.closed_form import search_zeros, sixr
from armik.solvers.closed_form.family import Family
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "one-dimensional search (axes 2 and 3 parallel)"
FAMILY = "two_parallel"
PRIORITY = 60
SUMMARY = "1-D search over q1 for 6R arms with axes 2, 3 parallel: up to 16 solutions"


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The geometry of a 6R arm with axes 2 and 3 parallel, or the reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    ang = angle_between(H[1], H[2])
    if ang > ANGLE_TOL:
        return (
            f"axes 2 and 3 are not parallel: they are {fmt(ang)} rad apart (tolerance "
            f"{ANGLE_TOL:g} rad)"
        )
    if angle_between(H[3], H[1]) < ANGLE_TOL:
        return (
            "axis 4 is parallel to axes 2 and 3: the search's SP6 loses q4; "
            "three_parallel_general solves this arm in closed form"
        )
    w, miss = meeting_point(P[3:], H[3:])
    if miss <= DISTANCE_TOL:
        return (
            f"the last three axes meet (a spherical wrist at {np.round(w, 6).tolist()} m): "
            "the search's SP6 has no wrist offsets to work on; spherical_general solves "
            "this arm in closed form"
        )
    text = f"axes 2 and 3 parallel along {np.round(H[1], 6).tolist()}"
    return sixr.chain_6r(FAMILY, "over_q1", ax, [P[0], P[1], P[2], P[3], P[4], P[5]], text)


def _classify(arm: ArmModel):
    return classify(arm)


SPEC = Family(
    FAMILY, _classify, CLOSED_FORM, search_zeros.kernel, search_zeros.solve_into,
    search_zeros.kernel_many, search_zeros.ZEROS, search_zeros.solve_all_into,
).register(FAMILY, PRIORITY, SUMMARY, complete=False)  # fmt: skip
