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
/* Joint a's value nearest ti at which joint b = qb + sgn (qa - value) lies within its
   limits, turns by 2 pi allowed (joint a within its own, or within pi of ti without
   them); ti itself where none does (line_split.split_at). */
static double split_at(double qa, double qb, double sgn, double ti, int a, int b)
{
    const double two_pi = 2.0 * IK_PI;
    double lo = LO[a] > ti - IK_PI ? LO[a] : ti - IK_PI;
    double hi = HI[a] < ti + IK_PI ? HI[a] : ti + IK_PI;
    double c = qb + sgn * qa, x, y, x0, x1, t, best = ti, gap = HUGE_VAL;
    long m, last;
    if (isfinite(LO[a]) && isfinite(HI[a])) {
        lo = LO[a];
        hi = HI[a];
    }
    if (!(isfinite(LO[b]) && isfinite(HI[b]))) return ti < lo ? lo : (ti > hi ? hi : ti);
    x = sgn > 0.0 ? c - HI[b] : LO[b] - c;  /* joint b = c - sgn t (+ 2 pi m) at joint a = t */
    y = sgn > 0.0 ? c - LO[b] : HI[b] - c;
    last = (long)floor((hi - x) / two_pi);
    for (m = (long)ceil((lo - y) / two_pi); m <= last; m++) {
        x0 = x + two_pi * m > lo ? x + two_pi * m : lo;
        x1 = y + two_pi * m < hi ? y + two_pi * m : hi;
        if (x0 <= x1) {
            t = ti < x0 ? x0 : (ti > x1 ? x1 : ti);
            if (fabs(t - ti) < gap) {
                best = t;
                gap = fabs(t - ti);
            }
        }
    }
    return best;
}

/* The (up to 2) wrist solutions for a placed wrist centre, appended to W; joint 4 free
   (axes 4 and 6 in line) at Q0's value, or the value nearest it that keeps joint 6 within
   its limits, its bit set in *mask. */
static int wrist(mat3 R03, mat3 R06, const double *Q0, int *mask, double q[6], double c[6],
                 double s[6], double W[][DOF], double C[][DOF], double S[][DOF], int n)
{
    mat3 R36 = mtm(R03, R06), R45;
    double a[2], b[2], ca[2], sa[2], cb[2], sb[2], sgn, t;
    int nw = sp2cs(mv(R36, h6), h6, neg(h4), h5, Q0[J3], a, b, ca, sa, cb, sb), i;
    int free4 = nw == -1;
    if (free4) {
        nw = 1;
        *mask |= 1 << J3;
    }
    for (i = 0; i < nw; i++) {
        q[3] = a[i];
        q[4] = b[i];
        c[3] = ca[i];
        s[3] = sa[i];
        c[4] = cb[i];
        s[4] = sb[i];
        R45 = mm(rot_cs(h4, c[3], s[3]), rot_cs(h5, c[4], s[4]));
        q[5] = sp1cs(h5, mv(mtm(R45, R36), h5), h6, &c[5], &s[5]);
        if (free4) {  /* only q4 + q6 (q4 - q6 with the axes opposed) turns the tool */
            sgn = dot(h4, mv(R45, h6)) > 0.0 ? 1.0 : -1.0;
            t = split_at(q[3], q[5], sgn, Q0[J3], J3, J5);
            if (t != q[3]) {
                q[5] = q[5] + sgn * (q[3] - t);
                q[3] = t;
                c[3] = cos(t);
                s[3] = sin(t);
                c[5] = cos(q[5]);
                s[5] = sin(q[5]);
            }
        }
        n = put_row(W, C, S, n, q, c, s);
    }
    return n;
}
"""

PARALLEL_23 = r"""
static int rows(mat3 R, vec3 pos, const double *Q0, int *mask, double W[][DOF],
                double C[][DOF], double S[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R1, R3, R03;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0), v;
    double t1[2], t3[2], q[6], c[6], s[6];
    int n1, n3, roots, i1, i3, start, mid, n = 0;
    n1 = sp4(h2, p16, neg(h1), D1, t1);
    if (n1 == -1) {  /* wrist centre on axis 1 */
        n1 = 1;
        t1[0] = Q0[J0];
        *mask |= 1 << J0;
    }
    for (i1 = 0; i1 < n1; i1++) {
        q[0] = t1[i1];
        c[0] = cos(q[0]);
        s[0] = sin(q[0]);
        R1 = rot_cs(h1, c[0], s[0]);
        v = sub(mtv(R1, p16), p1);
        n3 = elbow_roots(p3, neg(p2), h3, norm(v), t3, &roots);
        if (n3 == -1) {
            n3 = 1;
            t3[0] = Q0[J2];
            *mask |= 1 << J2;
        }
        start = mid = n;
        for (i3 = 0; i3 < roots; i3++) {
            if (i3 == 1) mid = n;
            q[2] = t3[i3];
            c[2] = cos(q[2]);
            s[2] = sin(q[2]);
            R3 = rot_cs(h3, c[2], s[2]);
            q[1] = sp1cs(add(p2, mv(R3, p3)), v, h2, &c[1], &s[1]);
            R03 = mm(mm(R1, rot_cs(h2, c[1], s[1])), R3);
            n = wrist(R03, R06, Q0, mask, q, c, s, W, C, S, n);
        }
        if (roots > n3)  /* a merged root and its mirror: the better rows of the two */
            n = keep_nearer(W, C, S, start, mid, n, J2, Q0);
    }
    return n;
}
"""

MEETING_12 = r"""
static int rows(mat3 R, vec3 pos, const double *Q0, int *mask, double W[][DOF],
                double C[][DOF], double S[][DOF])
{
    mat3 R06 = mmt(R, R_TIP0), R1, R3;
    vec3 p16 = sub(sub(pos, mv(R06, p6)), p0), u;
    double t3[2], a[2], b[2], ca[2], sa[2], cb[2], sb[2], q[6], c[6], s[6], e;
    int n3, roots, n12, i3, i, start, mid, n = 0;
    n3 = elbow_roots(p3, neg(p2), h3, norm(p16), t3, &roots);
    if (n3 == -1) {
        n3 = 1;
        t3[0] = Q0[J2];
        *mask |= 1 << J2;
    }
    start = mid = n;
    for (i3 = 0; i3 < roots; i3++) {
        if (i3 == 1) mid = n;
        q[2] = t3[i3];
        if (n3 == 1) {  /* stretched or folded: a span along axis 2 leaves joint 2 free */
            e = elbow_extreme(p3, neg(p2), h3, q[2]);
            u = add(p2, mv(rot(h3, e), p3));
            q[1] = Q0[J1];
            c[1] = cos(q[1]);
            s[1] = sin(q[1]);
            q[0] = sp1cs(mv(rot_cs(h2, c[1], s[1]), u), p16, h1, &c[0], &s[0]);
            R1 = mm(rot_cs(h1, c[0], s[0]), rot_cs(h2, c[1], s[1]));
            if (norm(cross(h2, u)) <= STRAIGHT && norm(sub(mv(R1, u), p16)) <= STRAIGHT) {
                q[2] = e;
                c[2] = cos(e);
                s[2] = sin(e);
                *mask |= 1 << J1;
                n = wrist(mm(R1, rot_cs(h3, c[2], s[2])), R06, Q0, mask, q, c, s, W, C, S, n);
                continue;
            }
        }
        c[2] = cos(q[2]);
        s[2] = sin(q[2]);
        R3 = rot_cs(h3, c[2], s[2]);
        n12 = sp2cs(p16, add(p2, mv(R3, p3)), neg(h1), h2, Q0[J0], a, b, ca, sa, cb, sb);
        if (n12 == -1) {  /* wrist centre on axis 1 */
            n12 = 1;
            *mask |= 1 << J0;
        }
        for (i = 0; i < n12; i++) {
            q[0] = a[i];
            q[1] = b[i];
            c[0] = ca[i];
            s[0] = sa[i];
            c[1] = cb[i];
            s[1] = sb[i];
            R1 = mm(rot_cs(h1, c[0], s[0]), rot_cs(h2, c[1], s[1]));
            n = wrist(mm(R1, R3), R06, Q0, mask, q, c, s, W, C, S, n);
        }
    }
    if (roots > n3)  /* a merged root and its mirror: the better rows of the two */
        n = keep_nearer(W, C, S, start, mid, n, J2, Q0);
    return n;
}
"""


# the chain's free joints (1, 3, 2, 4) in the order ``spherical_wrist.kernel`` sweeps them
FREE = (0, 2, 1, 3)


def chain_text(geo: Chain6R, joints: tuple[int, ...] = FREE, last: int = 5) -> str:
    """The constants of the chain ``geo`` (a spherical-wrist ``Chain6R``, either variant)
    and the C of its ``wrist`` and ``rows``; ``joints``: the arm's indices of the chain's
    joints 1, 3, 2 and 4 (``J0``, ``J2``, ``J1``, ``J3``: a free joint's value is read from
    the seed ``Q0`` and its bit set in ``*mask`` at them); ``last``: the arm's index of the
    chain's joint 6 (``J5``: its limits bound a free joint 4's value)."""
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
    j0, j2, j1, j3 = joints
    free = f"enum {{ J0 = {j0}, J1 = {j1}, J2 = {j2}, J3 = {j3}, J5 = {last} }};  /* free */\n"
    if body is MEETING_12:  # m: joint 2 free there (spherical_wrist.STRAIGHT)
        free += f"static const double STRAIGHT = {c_source.num(spherical_wrist.STRAIGHT)};\n"
    return c_source.constants(names) + "\n" + free + c_source.KEEP_NEARER + WRIST + body


PUT_REVERSED = r"""
/* Row n of the reversed chain (joints 6 to 1) in the arm's order. */
static inline IK_UNUSED int put_reversed(double W[][DOF], double C[][DOF], double S[][DOF], int n,
                               const double *q, const double *c, const double *s)
{
    int j;
    for (j = 0; j < 6; j++) {
        W[n][5 - j] = wrap(q[j]);
        C[n][5 - j] = c[j];
        S[n][5 - j] = s[j];
    }
    return n + 1;
}
"""


def reversed_text(geo: Chain6R) -> str:
    """The C of a spherical-wrist chain read from the tip of an arm (``geo``: joints 6 to
    1): its ``reversed_rows`` solve it for T^-1 and write each row in the arm's order
    (``put_reversed``), a free joint's value read from the seed ``Q0`` in the arm's order."""
    chain = (
        chain_text(geo, tuple(5 - j for j in FREE), last=0)
        .replace("put_row(", "put_reversed(")
        .replace("static int rows(", "static int reversed_rows(")
    )
    return PUT_REVERSED + chain


def rows(arm: ArmModel, ax: Axes) -> Rows:
    """The C rows of ``arm``, a spherical-wrist arm (``spherical_wrist.classify`` holds)."""
    geo = spherical_wrist.classify(arm, ax)
    assert isinstance(geo, Chain6R)  # the caller chose the family by its solver's test
    summary = f"a 6R arm with a spherical wrist ({geo.description})"
    return Rows(chain_text(geo), 8, SNAP, summary, sweep=FREE)
