"""6R arms with axes 2, 3, 4 parallel and a general wrist as C: the kernel of
``armik.solvers.closed_form.three_parallel_general``, step for step (SP6 for joints 1 and
5, SP1 for joint 6 and the sum of joints 2 to 4, SP3 and SP1 for the elbow), on the
``Chain6R`` its ``classify`` gives, with the chain's numbers folded in as constants.
"""

from __future__ import annotations

from armik.export import c_source, c_subproblems_56
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import subproblems as sp
from armik.solvers.closed_form import three_parallel_general
from armik.solvers.closed_form.sixr import SNAP, Chain6R

ROWS = r"""
static int rows(mat3 R, vec3 pos, double W[][DOF], double C[][DOF], double S[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R1, R5, M, R14;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0), H6[4], K6[4], P6[4], a, v;
    double t1[4], t5[4], t3[2], c3[2], s3[2], q[6], c[6], s[6], q14, c14, s14, nv;
    int m, ls, i, i3, n3, roots, n = 0;
    H6[0] = H6[1] = H6[2] = H6[3] = h2;
    K6[0] = K6[2] = neg(h1);
    K6[1] = K6[3] = h5;
    P6[0] = p16;
    P6[1] = neg(p5);
    P6[2] = mv(R06, h6);
    P6[3] = neg(h6);
    m = sp6(H6, K6, P6, D1, 0.0, t1, t5, &ls);
    if (m == -1) m = 1;  /* a continuum: one of it */
    for (i = 0; i < m; i++) {  /* each angle's cosine and sine computed once, kept */
        q[0] = t1[i];
        q[4] = t5[i];
        c[0] = cos(q[0]);
        s[0] = sin(q[0]);
        c[4] = cos(q[4]);
        s[4] = sin(q[4]);
        R1 = rot_cs(h1, c[0], s[0]);
        R5 = rot_cs(h5, c[4], s[4]);
        M = mtm(R1, R06);
        a = mtv(R5, h2);
        if (norm(cross(a, h6)) < IK_SINGLE) {  /* wrist singular: q6 free */
            q[5] = MID[5];
            c[5] = cos(q[5]);
            s[5] = sin(q[5]);
        } else {
            q[5] = sp1cs(a, mtv(M, h2), neg(h6), &c[5], &s[5]);
        }
        R14 = mmt(mmt(M, rot_cs(h6, c[5], s[5])), R5);
        q14 = sp1cs(X, mv(R14, X), h2, &c14, &s14);
        v = sub(sub(mtv(R1, p16), p1), mv(R14, add(p4, mv(R5, p5))));
        nv = norm(v);
        n3 = elbow_roots_cs(p3, neg(p2), h3, nv, t3, c3, s3, &roots);
        if (n3 == -1) {
            n3 = 1;
            t3[0] = MID[2];
            c3[0] = cos(MID[2]);
            s3[0] = sin(MID[2]);
        }
        for (i3 = 0; i3 < roots; i3++) {
            q[2] = t3[i3];
            c[2] = c3[i3];
            s[2] = s3[i3];
            q[1] = sp1cs(add(p2, mv(rot_cs(h3, c[2], s[2]), p3)), v, h2, &c[1], &s[1]);
            q[3] = S4 * (q14 - q[1] - S3 * q[2]);
@Q4_CS@
            n = put_row(W, C, S, n, q, c, s);
        }
        if (roots > n3)  /* a merged root and its mirror: the better row of the two */
            n = keep_nearer(W, C, S, n - 2, n - 1, n, 2, MID);
    }
    return n;
}
"""


# joint 4's cosine and sine: from those of q14 (joints 2 to 4), joint 2 and joint 3 by the
# angle sums when S3 and S4 are +-1 to rounding (axes 2, 3, 4 parallel as written), else
# from libm
Q4_SUMS = """            {
                double cu = c14 * c[1] + s14 * s[1], su = s14 * c[1] - c14 * s[1];
                c[3] = cu * c[2] + @S3@ * su * s[2];
                s[3] = @S4@ * (su * c[2] - @S3@ * cu * s[2]);
            }"""
Q4_LIBM = """            c[3] = cos(q[3]);
            s[3] = sin(q[3]);
            (void)c14;
            (void)s14;"""


def _q4_cs(s3: float, s4: float) -> str:
    """The C of joint 4's cosine and sine (``Q4_SUMS`` or ``Q4_LIBM``)."""
    if max(abs(abs(s3) - 1.0), abs(abs(s4) - 1.0)) > 1e-15:
        return Q4_LIBM
    signs = {"@S3@": "1.0" if s3 > 0 else "-1.0", "@S4@": "1.0" if s4 > 0 else "-1.0"}
    text = Q4_SUMS
    for key, value in signs.items():
        text = text.replace(key, value)
    return text


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm`` (``three_parallel_general.classify`` holds)."""
    geo = three_parallel_general.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    h, p = geo.h, geo.p
    x = sp.cross.py_func(h[1], h[0])
    add, dot = sp.add.py_func, sp.dot.py_func
    names = {f"h{i + 1}": h[i] for i in (0, 1, 2, 4, 5)}  # h4 only as S4
    names.update({f"p{i}": p[i] for i in range(7)})
    names.update(
        R_TIP0=geo.R_tip0,
        X=sp.scale.py_func(x, 1.0 / sp.norm.py_func(x)),
        D1=dot(h[1], add(add(p[1], p[2]), add(p[3], p[4]))),
        S3=dot(h[2], h[1]),
        S4=dot(h[3], h[1]),
    )
    body = ROWS.replace("@Q4_CS@", _q4_cs(names["S3"], names["S4"]))
    text = c_source.constants(names) + "\n" + c_subproblems_56.source(sp6=True)
    text += c_source.KEEP_NEARER + body
    summary = f"a 6R arm with axes 2, 3, 4 parallel, the wrist general ({geo.description})"
    return Rows(text, 8, SNAP, summary)
