"""6R arms with a spherical wrist (IRB 120, KUKA KR, ...) as C: the kernel of
``armik.solvers.closed_form.spherical_wrist``, step for step, on the ``Chain6R`` its
``classify`` gives (axes 2 and 3 parallel, or axes 1 and 2 meeting: only the variant of
the arm is written), with the chain's numbers folded in as constants.
"""

from __future__ import annotations

from armik.export import c_source
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import spherical_wrist
from armik.solvers.closed_form import subproblems as sp
from armik.solvers.closed_form.sixr import SNAP, Chain6R

WRIST = r"""
/* The (up to 2) wrist solutions for a placed wrist centre, appended to W. */
static int wrist(mat3 R03, mat3 R06, double q1, double q2, double q3, double W[][DOF], int n)
{
    mat3 R36 = mtm(R03, R06), R6;
    double a[2], b[2], q6;
    int nw = sp2(mv(R36, h6), h6, neg(h4), h5, MID[3], a, b), i;
    if (nw == -1) nw = 1;
    for (i = 0; i < nw; i++) {
        R6 = mtm(mm(rot(h4, a[i]), rot(h5, b[i])), R36);
        q6 = sp1(h5, mv(R6, h5), h6);
        W[n][0] = wrap(q1); W[n][1] = wrap(q2); W[n][2] = wrap(q3);
        W[n][3] = wrap(a[i]); W[n][4] = wrap(b[i]); W[n][5] = wrap(q6);
        n++;
    }
    return n;
}
"""

PARALLEL_23 = r"""
static int rows(mat3 R, vec3 pos, double W[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R1, R3;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0), v;
    double t1[2], t3[2], q1, q2, q3;
    int n1, n3, i1, i3, n = 0;
    n1 = sp4(h2, p16, neg(h1), D1, t1);
    if (n1 == -1) { n1 = 1; t1[0] = MID[0]; }  /* wrist centre on axis 1 */
    for (i1 = 0; i1 < n1; i1++) {
        q1 = t1[i1];
        R1 = rot(h1, q1);
        v = sub(mtv(R1, p16), p1);
        n3 = sp3(p3, neg(p2), h3, norm(v), t3);
        if (n3 == -1) { n3 = 1; t3[0] = MID[2]; }
        for (i3 = 0; i3 < n3; i3++) {
            q3 = t3[i3];
            R3 = rot(h3, q3);
            q2 = sp1(add(p2, mv(R3, p3)), v, h2);
            n = wrist(mm(mm(R1, rot(h2, q2)), R3), R06, q1, q2, q3, W, n);
        }
    }
    return n;
}
"""

MEETING_12 = r"""
static int rows(mat3 R, vec3 pos, double W[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R3;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0);
    double t3[2], a[2], b[2], q3;
    int n3, n12, i3, i, n = 0;
    n3 = sp3(p3, neg(p2), h3, norm(p16), t3);
    if (n3 == -1) { n3 = 1; t3[0] = MID[2]; }
    for (i3 = 0; i3 < n3; i3++) {
        q3 = t3[i3];
        R3 = rot(h3, q3);
        n12 = sp2(p16, add(p2, mv(R3, p3)), neg(h1), h2, MID[0], a, b);
        if (n12 == -1) n12 = 1;  /* wrist centre on axis 1 */
        for (i = 0; i < n12; i++)
            n = wrist(mm(mm(rot(h1, a[i]), rot(h2, b[i])), R3), R06, a[i], b[i], q3, W, n);
    }
    return n;
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm``, a spherical-wrist arm (``spherical_wrist.classify`` holds)."""
    geo = spherical_wrist.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    h, p = geo.h, geo.p
    names = {f"h{i + 1}": h[i] for i in range(6)}
    names.update({f"p{i}": p[i] for i in (0, 2, 3, 6)})
    names["R_TIP0"] = geo.R_tip0
    add = sp.add.py_func
    if geo.variant == "parallel_23":
        names["p1"] = p[1]  # zero when axes 1 and 2 meet
        names["D1"] = sp.dot.py_func(h[1], add(add(p[1], p[2]), p[3]))
        body = PARALLEL_23
    else:
        body = MEETING_12
    summary = f"a 6R arm with a spherical wrist ({geo.description})"
    return Rows(c_source.constants(names) + "\n" + WRIST + body, 8, SNAP, summary)
