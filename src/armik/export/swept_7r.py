"""A 7R arm with joint 7 held (the Franka Panda) as C: the held value is ``N_ik``'s
argument, joints 6 to 1 read from the tip are a spherical-wrist chain solved by that
family's rows (``spherical_wrist.chain_text``) for the target the held joint leaves, as
``armik.solvers.closed_form.swept_7r.at_value`` solves it (``solve_all(T, hold={joint 7:
value})``).

With joint 7 at theta, the tip turns about joint 7's axis line (through C7 along U7 in the
tip frame at q = 0): joints 1 to 6 must reach T6 = T G(theta), G the turn by -theta about
that line, and the reversed chain reaches T6^-1. Its rows are written back in the arm's
order (joint 1 first), joint 7 at theta.
"""

from __future__ import annotations

from armik.export import c_source, spherical_wrist
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import swept_7r
from armik.solvers.closed_form.sixr import SNAP

HELD = 6  # the joint swept_7r holds: joint 7

ROWS = r"""
/* joints 1 to 6 by the reversed chain, joint 7 set after */
static int rows(mat3 R, vec3 pos, double held, const double *Q0, int *mask, double W[][DOF],
                double C[][DOF], double S[][DOF])
{
    mat3 Rg = rot(U7, -held), R6 = mm(R, Rg), Ri;
    vec3 p_end = add(mv(R, sub(C7, mv(Rg, C7))), pos), pi;
    double c7 = cos(held), s7 = sin(held);
    int i, j, n;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) Ri.m[3 * i + j] = R6.m[3 * j + i];
    pi = neg(mv(Ri, p_end));
    n = reversed_rows(Ri, pi, Q0, mask, W, C, S);
    for (i = 0; i < n; i++) {
        W[i][HELD] = held;
        C[i][HELD] = c7;
        S[i][HELD] = s7;
    }
    return n;
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm`` with joint 7 held (``swept_7r.classify`` holds)."""
    sw = swept_7r.classify(arm, ax)
    assert isinstance(sw, swept_7r.Swept)  # the caller chose the family by its test
    names = c_source.constants({"C7": sw.c, "U7": sw.u})
    text = f"{names}\n" + spherical_wrist.reversed_text(sw.geo) + ROWS
    summary = f"a 7R arm with joint 7 held at an argument ({sw.description})"
    sweep = tuple(5 - j for j in spherical_wrist.FREE)  # the reversed chain's, as it sweeps
    return Rows(text, 8, SNAP, summary, held=HELD, sweep=sweep, reversed=True)
