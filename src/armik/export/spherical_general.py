"""6R arms with a spherical wrist and general first three axes as C: the kernel of
``armik.solvers.closed_form.spherical_general``, step for step (SP5 for joints 1 to 3, the
spherical wrist's SP2 and SP1 for joints 4 to 6), on the ``Chain6R`` its ``classify``
gives, with the chain's numbers folded in as constants.
"""

from __future__ import annotations

from armik.export import c_source, c_subproblems_56
from armik.export.solver_file import Rows
from armik.export.spherical_wrist import WRIST
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import spherical_general
from armik.solvers.closed_form.sixr import SNAP, Chain6R

ROWS = r"""
static int rows(mat3 R, vec3 pos, double W[][DOF], double C[][DOF], double S[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R03;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0);
    double t1[4], t2[4], t3[4], q[6], c[6], s[6];
    int m, ls, i, j, n = 0, mask = 0;  /* a free joint 4 stays at the middle: no sweep */
    m = sp5(neg(p1), p16, p2, p3, neg(h1), h2, h3, t1, t2, t3, &ls);
    if (m == -1) m = 1;  /* a continuum (the wrist centre on axis 1): one of it */
    for (i = 0; i < m; i++) {
        q[0] = t1[i];
        q[1] = t2[i];
        q[2] = t3[i];
        for (j = 0; j < 3; j++) {
            c[j] = cos(q[j]);
            s[j] = sin(q[j]);
        }
        R03 = mm(mm(rot_cs(h1, c[0], s[0]), rot_cs(h2, c[1], s[1])), rot_cs(h3, c[2], s[2]));
        n = wrist(R03, R06, MID, &mask, q, c, s, W, C, S, n);
    }
    return n;
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm`` (``spherical_general.classify`` holds)."""
    geo = spherical_general.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    h, p = geo.h, geo.p
    names = {f"h{i + 1}": h[i] for i in range(6)}
    names.update({f"p{i}": p[i] for i in (0, 1, 2, 3, 6)})
    names["R_TIP0"] = geo.R_tip0
    text = c_source.constants(names) + "\nenum { J3 = 3, J5 = 5 };  /* joints 4 and 6 */\n"
    text += c_subproblems_56.source(sp5=True) + WRIST + ROWS
    summary = f"a 6R arm with a spherical wrist, general first axes ({geo.description})"
    return Rows(text, 8, SNAP, summary)
