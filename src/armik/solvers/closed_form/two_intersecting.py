"""IK of 6R arms with axes 5 and 6 meeting and nothing else, by a one-dimensional search
over q4 (IK-Geo's ``IK_2_intersecting``): the classifier and the solver's registration.
The search's equations and branches are in ``search_q4``, its zero finder in
``search_zeros``. Up to 16 solutions; branch labels as the closed forms read them, two
solutions sharing one numbered ("...#2").
"""

from __future__ import annotations

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.solvers.closed_form import search_zeros, sixr
from armik.solvers.closed_form.family import Family
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

CLOSED_FORM = "one-dimensional search (axes 5 and 6 meet)"
FAMILY = "two_intersecting"
PRIORITY = 60
SUMMARY = "1-D search over q4 for 6R arms with axes 5, 6 meeting: up to 16 solutions"


def classify(arm: ArmModel, ax: Axes | None = None) -> sixr.Chain6R | str:
    """The geometry of a 6R arm whose axes 5 and 6 meet, or the reason it is not one."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    if angle_between(H[4], H[5]) < ANGLE_TOL:
        return "axes 5 and 6 are parallel"
    c56, d56 = meeting_point(P[4:], H[4:])
    if d56 > DISTANCE_TOL:
        return f"axes 5 and 6 do not meet: they miss by {fmt(d56)} m (tolerance {DISTANCE_TOL:g} m)"
    s, d123 = meeting_point(P[:3], H[:3])
    if d123 <= DISTANCE_TOL:
        return (
            f"axes 1, 2, 3 meet in one point (a spherical shoulder at "
            f"{np.round(s, 6).tolist()} m): the search's SP5 degenerates"
        )
    text = f"axes 5 and 6 meet at {np.round(c56, 6).tolist()} m"
    return sixr.chain_6r(FAMILY, "over_q4", ax, [P[0], P[1], P[2], P[3], c56, c56], text)


def _classify(arm: ArmModel):
    return classify(arm)


SPEC = Family(
    FAMILY, _classify, CLOSED_FORM, search_zeros.kernel, search_zeros.solve_into,
    search_zeros.kernel_many, search_zeros.ZEROS, search_zeros.solve_all_into,
).register(FAMILY, PRIORITY, SUMMARY, complete=False)  # fmt: skip
