"""The planar 2-link arm as C: the rows of ``armik.solvers.closed_form.planar2r_kernel``
(both elbow branches, +acos first; one row when stretched, folded, or the target on the
shoulder with equal links), on the ``Geometry`` and ``Plane`` its solver reads.
The orientation the target asks is checked by the verdict every exported solver runs.
"""

from __future__ import annotations

from armik.export import c_source
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import planar2r
from armik.tolerances import LIMIT_TOL

ROWS = r"""
/* Row n of link angles t1, t2: q_i = s_i (t_i - alpha_i), as atan2(sin, cos). */
static int put(double W[][DOF], double C[][DOF], double S[][DOF], int n, double t1, double t2)
{
    double a = S1 * (t1 - ALPHA1), b = S2 * (t2 - ALPHA2);
    double c[2], s[2], q[2];
    c[0] = cos(a);
    s[0] = sin(a);
    c[1] = cos(b);
    s[1] = sin(b);
    q[0] = atan2(s[0], c[0]);
    q[1] = atan2(s[1], c[1]);
    return put_row(W, C, S, n, q, c, s);
}

static int rows(mat3 R, vec3 pos, double W[][DOF], double C[][DOF], double S[][DOF])
{
    vec3 d = sub(pos, ORIGIN);
    double d0 = dot(d, AX) - SHOULDER_X, d1 = dot(d, AY) - SHOULDER_Y;
    double r = hypot(d0, d1), c = (r * r - L1 * L1 - L2 * L2) / (2.0 * L1 * L2);
    double heading = atan2(d1, d0), t2;
    int k, stretched;
    (void)R;  /* the orientation is checked with the other rows' verdict */
    if (EQUAL_LINKS && r < ZERO_LENGTH) {  /* on the shoulder: joint 1 free */
        return put(W, C, S, 0, ALPHA1 + S1 * MID[0], IK_PI);
    }
    if (fabs(c) >= 1.0 - SINGULAR_TOL) {  /* stretched or folded: one row */
        stretched = c > 0;
        t2 = stretched ? 0.0 : IK_PI;
        return put(W, C, S, 0, (stretched || L1 >= L2) ? heading : heading + IK_PI, t2);
    }
    for (k = 0; k < 2; k++) {
        t2 = (k == 0 ? 1.0 : -1.0) * acos(c);
        put(W, C, S, k, heading - atan2(L2 * sin(t2), L1 + L2 * cos(t2)), t2);
    }
    return 2;
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm``, a planar 2-link arm (``planar2r.applies`` holds)."""
    geo, plane = planar2r.geometry(arm), arm.plane
    assert plane is not None  # the caller chose the family by its solver's test
    names = {
        "ORIGIN": plane.origin,
        "AX": plane.x,
        "AY": plane.y,
        "SHOULDER_X": float(geo.shoulder[0]),
        "SHOULDER_Y": float(geo.shoulder[1]),
        "L1": geo.l1,
        "L2": geo.l2,
        "ALPHA1": geo.alpha1,
        "ALPHA2": geo.alpha2,
        "S1": geo.s1,
        "S2": geo.s2,
        "ZERO_LENGTH": planar2r.ZERO_LENGTH,
        "SINGULAR_TOL": planar2r.SINGULAR_TOL,
    }
    equal = abs(geo.l1 - geo.l2) < planar2r.ZERO_LENGTH
    text = (
        c_source.constants(names)
        + f"\n#undef EQUAL_LINKS\n#define EQUAL_LINKS {int(equal)}\n"
        + ROWS
    )
    summary = (
        f"a planar 2-link arm (links {geo.l1:.6g} m and {geo.l2:.6g} m, "
        f"{plane.axes_words(list(arm.joint_names)).removeprefix('all ')})"
    )
    return Rows(text, 2, LIMIT_TOL, summary)
