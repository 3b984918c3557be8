"""6R arms with a spherical shoulder (the Panda or the iiwa with joint 7 locked) as C: joints
6 to 1 read from the tip are a spherical-wrist chain solved by that family's rows
(``spherical_wrist.chain_text``) for T^-1, as
``armik.solvers.closed_form.spherical_shoulder``'s kernel solves it; its rows are written
back in the arm's order (joint 1 first).
"""

from __future__ import annotations

from armik.export import spherical_wrist
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import spherical_shoulder
from armik.solvers.closed_form.sixr import SNAP, Chain6R

ROWS = r"""
static int rows(mat3 R, vec3 pos, const double *Q0, int *mask, double W[][DOF],
                double C[][DOF], double S[][DOF])
{
    mat3 Ri;
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) Ri.m[3 * i + j] = R.m[3 * j + i];
    return reversed_rows(Ri, neg(mv(Ri, pos)), Q0, mask, W, C, S);
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm``, a spherical-shoulder arm (``spherical_shoulder.classify``
    holds)."""
    geo = spherical_shoulder.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    text = spherical_wrist.reversed_text(spherical_shoulder.reversed_chain(geo)) + ROWS
    summary = f"a 6R arm with a spherical shoulder ({geo.description})"
    sweep = tuple(5 - j for j in spherical_wrist.FREE)  # the reversed chain's, as it sweeps
    return Rows(text, 8, SNAP, summary, sweep=sweep, reversed=True)
