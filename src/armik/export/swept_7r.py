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

IN_LINE = r"""
static double nearest(double qi, double ri, double lo, double hi);

/* A point on and the direction of the reversed chain's axis k at its joints qr. */
static void axis_line(const double *qr, int k, vec3 *point, vec3 *dir)
{
    mat3 R = rot_cs(LINE_H[0], 1.0, 0.0);
    vec3 o = LINE_P[0];
    int m;
    for (m = 0; m < k; m++) {
        R = mm(R, rot(LINE_H[m], qr[m]));
        o = add(o, mv(R, LINE_P[m + 1]));
    }
    *point = o;
    *dir = mv(R, LINE_H[k]);
}

/* Rows 0 to n - 1 where two axes of the reversed chain one joint apart lie in one line (the
   Panda's joints 3 and 5 at joint 4 = 0): only their sum turns the tip, split by the
   closed form's rounding (within IN_LINE; within IK_SINGLE, a row it leaves outside the
   limits). The first (in the reversed chain's order) is set to Q0's value, or the nearest
   that keeps both within their limits, the other takes the rest (swept_7r.in_line), once
   the free joints' values are chosen. */
static void in_line(double W[][DOF], double C[][DOF], double S[][DOF], int n)
{
    double q[6], t, sgn, c, far;
    vec3 Pi, Di, Pj, Dj;
    int r, i, k, a, b, outside, split;
    for (r = 0; r < n; r++) {
        for (k = 0; k < 6; k++) q[k] = nearest(W[r][5 - k], MID[5 - k], LO[5 - k], HI[5 - k]);
        split = 0;
        for (i = 0; i < 3; i++) {  /* axes (1, 3), (2, 4), (3, 5); (4, 6) is the wrist */
            if (norm(cross(LINE_H[i], mv(rot(LINE_H[i + 1], q[i + 1]), LINE_H[i + 2])))
                > IK_SINGLE)
                continue;
            axis_line(q, i, &Pi, &Di);
            axis_line(q, i + 2, &Pj, &Dj);
            c = norm(cross(Di, Dj));
            far = norm(cross(sub(Pj, Pi), Di));
            a = 5 - i;  /* the arm's joints */
            b = 3 - i;
            outside = !(LO[a] - LIMIT_TOL <= q[i] && q[i] <= HI[a] + LIMIT_TOL)
                      || !(LO[b] - LIMIT_TOL <= q[i + 2] && q[i + 2] <= HI[b] + LIMIT_TOL);
            if (c > IK_SINGLE || far > IK_SINGLE || (!outside && (c > IN_LINE || far > IN_LINE)))
                continue;
            sgn = dot(Di, Dj) > 0.0 ? 1.0 : -1.0;
            t = split_at(q[i], q[i + 2], sgn, MID[a], a, b);
            q[i + 2] = q[i + 2] + sgn * (q[i] - t);
            q[i] = t;
            split = 1;
        }
        for (k = 0; split && k < 6; k++) {
            W[r][5 - k] = q[k];
            C[r][5 - k] = cos(q[k]);
            S[r][5 - k] = sin(q[k]);
        }
    }
}
"""

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
    names = c_source.constants({"C7": sw.c, "U7": sw.u, "IN_LINE": swept_7r.IN_LINE})
    h, p = sw.geo.h, sw.geo.p  # the reversed chain's axes and the vectors between them
    lines = (
        f"static const vec3 LINE_H[6] = {{{', '.join(c_source.vec(x) for x in h)}}};\n"
        f"static const vec3 LINE_P[5] = {{{', '.join(c_source.vec(x) for x in p[:5])}}};\n"
    )
    text = f"{names}\n{lines}" + spherical_wrist.reversed_text(sw.geo) + IN_LINE + ROWS
    summary = f"a 7R arm with joint 7 held at an argument ({sw.description})"
    sweep = tuple(5 - j for j in spherical_wrist.FREE)  # the reversed chain's, as it sweeps
    return Rows(text, 8, SNAP, summary, held=HELD, sweep=sweep, reversed=True, settle="in_line")
