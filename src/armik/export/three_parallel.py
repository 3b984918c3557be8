"""The UR family (axes 2, 3, 4 parallel, axes 5 and 6 meeting) as C: the kernel of
``armik.solvers.closed_form.three_parallel``, step for step, on the ``Chain6R`` its
``classify`` gives, with the chain's numbers folded in as constants.
"""

from __future__ import annotations

from armik.export import c_source
from armik.export.solver_file import Rows
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.solvers.closed_form import subproblems as sp
from armik.solvers.closed_form import three_parallel
from armik.solvers.closed_form.sixr import SNAP, Chain6R

dot = sp.dot.py_func  # the compiled solver's arithmetic, in Python: the same constants

ROWS = r"""
/* At the wrist singularity: the turn t nearest 0 such that, with q2 + q3 + q4 = theta + t,
   the elbow reaches the wrist point (three_parallel.reach_turn). */
static double reach_turn(vec3 c, double theta)
{
    double along = dot(p4, h2), cu, cw, B, k, low, high, t, ct, edge;
    vec3 u = sub(p4, scale(h2, along)), w = cross(h2, u);
    cu = dot(c, u);
    cw = dot(c, w);
    B = sqrt(cu * cu + cw * cw);
    if (B < 1e-12) return 0.0;
    k = dot(c, c) + dot(p4, p4) - 2.0 * dot(c, h2) * along;
    low = (k - SPAN2_HI) / (2.0 * B);
    high = (k - SPAN2_LO) / (2.0 * B);
    if (low > high || low > 1.0 + HAIR || high < -1.0 - HAIR) return 0.0;
    t = wrap(theta - atan2(cw, cu));
    ct = cos(t);
    if (ct > high) edge = acos(high - HAIR > -1.0 ? high - HAIR : -1.0);
    else if (ct < low) edge = acos(low + HAIR < 1.0 ? low + HAIR : 1.0);
    else return 0.0;
    return (t >= 0.0 ? edge : -edge) - t;
}

static int rows(mat3 R, vec3 pos, const double *Q0, int *mask, double W[][DOF],
                double C[][DOF], double S[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R1, M, R5, R234;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0), a, b, v;
    double t1[2], t5[2], t3[2], q[6], c[6], s[6], q234, c234, s234, turn, ca, sa, sg;
    int n1, n5, n3, roots, i1, i5, i3, n = 0;
    n1 = sp4(h2, p16, neg(h1), D1, t1);
    if (n1 == -1) {  /* wrist point on axis 1 */
        n1 = 1;
        t1[0] = Q0[0];
        *mask |= 1 << 0;
    }
    for (i1 = 0; i1 < n1; i1++) {
        q[0] = t1[i1];
        c[0] = cos(q[0]);
        s[0] = sin(q[0]);
        R1 = rot_cs(h1, c[0], s[0]);
        M = mtm(R1, R06);
        n5 = sp4(h2, h6, h5, dot(h2, mv(M, h6)), t5);
        if (n5 == -1) { n5 = 1; t5[0] = Q0[4]; }
        for (i5 = 0; i5 < n5; i5++) {
            q[4] = t5[i5];
            c[4] = cos(q[4]);
            s[4] = sin(q[4]);
            R5 = rot_cs(h5, c[4], s[4]);
            a = mtv(M, h2);
            b = mtv(R5, h2);
            if (norm(cross(a, h6)) < IK_SINGLE || norm(cross(b, h6)) < IK_SINGLE) {
                /* wrist singular: q6 kept at the seed's value unless the wrist point is then
                   out of the elbow's reach */
                q[5] = Q0[5];
                *mask |= 1 << 5;
                R234 = mmt(mmt(M, rot(h6, q[5])), R5);
                q234 = sp1(X, mv(R234, X), h2);
                turn = reach_turn(sub(mtv(R1, p16), p1), q234);
                q[5] -= dot(mv(M, h6), h2) > 0.0 ? turn : -turn;
            } else {
                q[5] = sp1(a, b, h6);
            }
            c[5] = cos(q[5]);
            s[5] = sin(q[5]);
            R234 = mmt(mmt(M, rot_cs(h6, c[5], s[5])), R5);
            q234 = sp1cs(X, mv(R234, X), h2, &c234, &s234);
            v = sub(sub(mtv(R1, p16), p1), mv(R234, p4));
            n3 = elbow_roots(p3, neg(p2), h3, norm(v), t3, &roots);
            if (n3 == -1) {
                n3 = 1;
                t3[0] = Q0[2];
                *mask |= 1 << 2;
            }
            for (i3 = 0; i3 < roots; i3++) {
                q[2] = t3[i3];
                c[2] = cos(q[2]);
                s[2] = sin(q[2]);
                q[1] = sp1cs(add(p2, mv(rot_cs(h3, c[2], s[2]), p3)), v, h2, &c[1], &s[1]);
                q[3] = S4 * (q234 - q[1] - S3 * q[2]);
                /* its cosine and sine by the sum formulas: q234 - q2, then - S3 q3, then S4 */
                ca = c234 * c[1] + s234 * s[1];
                sa = s234 * c[1] - c234 * s[1];
                sg = S3 > 0.0 ? s[2] : -s[2];
                c[3] = ca * c[2] + sa * sg;
                s[3] = sa * c[2] - ca * sg;
                s[3] = S4 > 0.0 ? s[3] : -s[3];
                n = put_row(W, C, S, n, q, c, s);
            }
            if (roots > n3)  /* a merged root and its mirror: the better row of the two */
                n = keep_nearer(W, C, S, n - 2, n - 1, n, 2, Q0);
        }
    }
    return n;
}
"""


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm``, a UR-family arm (``three_parallel.classify`` holds)."""
    geo = three_parallel.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    h, p = geo.h, geo.p
    x = sp.cross.py_func(h[1], h[0])
    lo, hi = three_parallel.elbow_span2.py_func(tuple(p[2]), tuple(p[3]), tuple(h[2]))
    names = {f"h{i + 1}": h[i] for i in (0, 1, 2, 4, 5)}  # h4 only as S4
    names.update({f"p{i}": p[i] for i in (0, 1, 2, 3, 4, 6)})
    names.update(
        R_TIP0=geo.R_tip0,
        X=sp.scale.py_func(x, 1.0 / sp.norm.py_func(x)),
        D1=dot(h[1], sp.add.py_func(sp.add.py_func(p[1], p[2]), sp.add.py_func(p[3], p[4]))),
        S3=dot(h[2], h[1]),
        S4=dot(h[3], h[1]),
        SPAN2_LO=lo,
        SPAN2_HI=hi,
        HAIR=three_parallel.HAIR,
    )
    summary = f"a 6R arm with axes 2, 3, 4 parallel and axes 5, 6 meeting ({geo.description})"
    # the free joints (1, 3, 6) in the order ``three_parallel.kernel`` sweeps them
    text = c_source.constants(names) + "\n" + c_source.KEEP_NEARER + ROWS
    return Rows(text, 8, SNAP, summary, sweep=(0, 2, 5))
