"""SP5 and SP6 as C99 text, after ``armik.solvers.closed_form.subproblems_56`` (the same
tolerances, the same candidates, the same grid, the same order of roots), so that an
exported family built on them (``spherical_general``, ``three_parallel_general``) finds
the branches its Python kernel finds. It goes after ``c_source.HELPERS`` (vectors,
``sp1``, ``wrap``) and ``c_roots``.

The polish of each candidate is cheaper than the Python's: Newton's steps on the square
2 x 2 system of ``pairs``' form (two sines and cosines a step, stopped once the residual
is below ``POLISHED`` of the largest length), where the Python takes damped steps on
|f|^2 / 2 with its gradient and Hessian (SP5's three rotations a step) down to 1e-16.
A candidate is gated and judged exact by the same residuals as in the Python (SP5's
by the circles' heights along k2 and distances from it, which SP1's t2 attains), and
one that Newton's steps leave inexact goes through the Python's damped steps from where
it came, so an ill-conditioned root is refined as the Python refines it.

``sp5(u0, u1, u2, u3, k1, k2, k3, t1, t2, t3, &ls)`` and ``sp6(H, K, P, d1, d2, t1, t2,
&ls)`` return the count n (-1: a continuum, one of it written) and write the angles of
solution i into ``t1[i]``, ... (4 slots each; unused slots 0), ``ls`` when the one answer
is a least-squares one.
"""

from __future__ import annotations

from armik.export import c_roots
from armik.export.c_source import num
from armik.solvers.closed_form import subproblems_56 as sp56

TEXT = r"""
static const double SP_EXACT = @EXACT@, SP_ROOT_GATE = @ROOT_GATE@, SP_SINGULAR = @SINGULAR@;
static const double SP_POLISHED = @POLISHED@;

/* Candidate angle pairs of M[0] sa + M[1] ca + M[2] sb + M[3] cb = f[0] and the same with
   M[4..7] = f[1], unrefined, with their sines and cosines in sc (sa, ca, sb, cb); *free_
   when they form a continuum. */
static int pairs(const double M[8], const double f[2], double size, double out[8][2],
                 double sc[8][4], int *free_)
{
    double a0 = M[0], b0 = M[1], a1 = M[2], b1 = M[3], a2 = M[4], b2 = M[5], a3 = M[6];
    double b3 = M[7], det1, det2, small, n1, n2, q1, q2, Ma[4], Mb[4], det, i00, i01, i10;
    double i11, g0, g1, B00, B01, B10, B11, S00, S01, S11, A0, A1, B1, A2, B2, big, ts[4];
    double ss[4], cs[4], yn, yd, ry, sy, cy;
    double sx, cx, ty, v0, v1, nv, w0, w1, ra, rb, u0, u1, ta, sa, ca, rest, x0, x1;
    int n = 0, m, i, j, ls, mb, lsb;
    *free_ = 0;
    det1 = a0 * b2 - b0 * a2;
    det2 = a1 * b3 - b1 * a3;
    small = (1e-12 * size) * (1e-12 * size);
    n1 = a0 * a0 + b0 * b0 + a2 * a2 + b2 * b2;
    n2 = a1 * a1 + b1 * b1 + a3 * a3 + b3 * b3;
    if (n1 <= small || n2 <= small) { *free_ = 1; return 0; }
    q1 = fabs(det1) / n1;
    q2 = fabs(det2) / n2;
    if (pmax(q1, q2) >= SP_SINGULAR) {
        if (q2 >= q1) {
            Ma[0] = a0; Ma[1] = b0; Ma[2] = a2; Ma[3] = b2;
            Mb[0] = a1; Mb[1] = b1; Mb[2] = a3; Mb[3] = b3;
            det = det2;
        } else {
            Ma[0] = a1; Ma[1] = b1; Ma[2] = a3; Ma[3] = b3;
            Mb[0] = a0; Mb[1] = b0; Mb[2] = a2; Mb[3] = b2;
            det = det1;
        }
        i00 = Mb[3] / det; i01 = -Mb[1] / det; i10 = -Mb[2] / det; i11 = Mb[0] / det;
        g0 = i00 * f[0] + i01 * f[1];
        g1 = i10 * f[0] + i11 * f[1];
        B00 = i00 * Ma[0] + i01 * Ma[2]; B01 = i00 * Ma[1] + i01 * Ma[3];
        B10 = i10 * Ma[0] + i11 * Ma[2]; B11 = i10 * Ma[1] + i11 * Ma[3];
        S00 = B00 * B00 + B10 * B10;
        S01 = B00 * B01 + B10 * B11;
        S11 = B01 * B01 + B11 * B11;
        A0 = g0 * g0 + g1 * g1 - 1.0 + 0.5 * (S00 + S11);
        A1 = -2.0 * (B00 * g0 + B10 * g1);
        B1 = -2.0 * (B01 * g0 + B11 * g1);
        A2 = S01;
        B2 = 0.5 * (S11 - S00);
        big = pmax(pmax(pmax(pmax(fabs(A0), fabs(A1)), fabs(B1)), fabs(A2)), fabs(B2));
        if (big <= 1e-10 * (g0 * g0 + g1 * g1 + S00 + S11 + 1.0)) { *free_ = 1; return 0; }
        m = trig2(A0, A1, B1, A2, B2, ts, ss, cs);
        for (i = 0; i < m; i++) {
            sx = ss[i];
            cx = cs[i];
            yn = g0 - B00 * sx - B01 * cx;
            yd = g1 - B10 * sx - B11 * cx;
            ty = atan2(yn, yd);
            ry = sqrt(yn * yn + yd * yd);
            sy = ry > 0.0 ? yn / ry : sin(ty);
            cy = ry > 0.0 ? yd / ry : cos(ty);
            out[i][0] = q2 >= q1 ? ts[i] : ty;
            out[i][1] = q2 >= q1 ? ty : ts[i];
            sc[i][0] = q2 >= q1 ? sx : sy;
            sc[i][1] = q2 >= q1 ? cx : cy;
            sc[i][2] = q2 >= q1 ? sy : sx;
            sc[i][3] = q2 >= q1 ? cy : cx;
        }
        return m;
    }
    if (a1 * a1 + a3 * a3 >= b1 * b1 + b3 * b3) { v0 = a1; v1 = a3; }
    else { v0 = b1; v1 = b3; }
    nv = hypot(v0, v1);
    v0 /= nv;
    v1 /= nv;
    w0 = -v1;
    w1 = v0;
    ra = w0 * a0 + w1 * a2;
    rb = w0 * b0 + w1 * b2;
    if (hypot(ra, rb) <= 1e-12 * size) { *free_ = 1; return 0; }
    m = trig1(ra, rb, w0 * f[0] + w1 * f[1], &u0, &u1, &ls);
    for (i = 0; i < (ls ? 0 : m); i++) {
        ta = i == 0 ? u0 : u1;
        sa = sin(ta);
        ca = cos(ta);
        rest = v0 * (f[0] - a0 * sa - b0 * ca) + v1 * (f[1] - a2 * sa - b2 * ca);
        mb = trig1(v0 * a1 + v1 * a3, v0 * b1 + v1 * b3, rest, &x0, &x1, &lsb);
        for (j = 0; j < (lsb ? 0 : mb); j++) {
            out[n][0] = ta;
            out[n][1] = j == 0 ? x0 : x1;
            sc[n][0] = sa;
            sc[n][1] = ca;
            sc[n][2] = sin(out[n][1]);
            sc[n][3] = cos(out[n][1]);
            n++;
        }
    }
    return n;
}

"""

SP5 = r"""
/* -- SP5 ----------------------------------------------------------------------------- */

typedef struct { vec3 q0, q1, q2, q3, e1, e2, e3; } sp5_in;

static void circle(vec3 o, vec3 k, vec3 p, vec3 *c, vec3 *a, vec3 *b)
{
    vec3 along = scale(k, dot(k, p));
    *c = add(o, along);
    *a = cross(k, p);
    *b = sub(p, along);
}

static inline IK_UNUSED vec3 on(vec3 c, vec3 a, vec3 b, double t)
{ return add(c, add(scale(a, sin(t)), scale(b, cos(t)))); }

/* |f|, the gradient and the Hessian of |f|^2 / 2 at x for SP5's residual. */
static double f5(const sp5_in *s, const double x[3], double g[3], double H[9])
{
    mat3 R2 = rot(s->e2, x[1]);
    vec3 u = mv(rot(s->e1, x[0]), s->q1), w3 = mv(rot(s->e3, x[2]), s->q3);
    vec3 w = mv(R2, add(s->q2, w3)), f = sub(add(s->q0, u), w), js[3], d11, d22, d33, d23;
    int a, b;
    js[0] = cross(s->e1, u);
    js[1] = neg(cross(s->e2, w));
    js[2] = neg(mv(R2, cross(s->e3, w3)));
    d11 = cross(s->e1, cross(s->e1, u));
    d22 = neg(cross(s->e2, cross(s->e2, w)));
    d33 = neg(mv(R2, cross(s->e3, cross(s->e3, w3))));
    d23 = cross(s->e2, js[2]);
    for (a = 0; a < 3; a++) {
        g[a] = dot(js[a], f);
        for (b = 0; b < 3; b++) H[3 * a + b] = dot(js[a], js[b]);
    }
    H[0] += dot(f, d11);
    H[4] += dot(f, d22);
    H[8] += dot(f, d33);
    H[5] += dot(f, d23);
    H[7] += dot(f, d23);
    return norm(f);
}

/* Damped Newton steps on SP5's |f|^2 / 2 from x (updated in place); returns |f|. */
static double refine5(const sp5_in *s, double x[3], int iters, double floor_)
{
    double g[3], H[9], y[3], gy[3], Hy[9], step[3], r, ry, mu = 0.0, tr;
    int it, k;
    r = f5(s, x, g, H);
    for (it = 0; it < iters; it++) {
        if (r <= floor_) break;
        if (newton_step(H, g, 3, mu, step)) {
            for (k = 0; k < 3; k++) y[k] = x[k] + step[k];
            ry = f5(s, y, gy, Hy);
            if (ry < r) {
                for (k = 0; k < 3; k++) { x[k] = y[k]; g[k] = gy[k]; }
                for (k = 0; k < 9; k++) H[k] = Hy[k];
                r = ry;
                mu *= 0.1;
                continue;
            }
        }
        tr = fabs(H[0]) + fabs(H[4]) + fabs(H[8]) + 1e-300;
        mu = pmax(10.0 * mu, 1e-12 * tr);
        if (mu > 1e12 * tr) break;
    }
    return r;
}

static void profile(vec3 c, vec3 a, vec3 b, vec3 e2, double t, double *h, double *rho)
{
    vec3 v = on(c, a, b, t);
    *h = dot(e2, v);
    *rho = norm(sub(v, scale(e2, *h)));
}

/* SP5's least-squares answer into best (3 angles); returns |residual|. */
static double ls5(const sp5_in *s, double best[3])
{
    vec3 c1, a1, b1, c3, a3, b3;
    double ht1[SP_GRID], r1[SP_GRID], ht3[SP_GRID], r3[SP_GRID], D[SP_GRID][SP_GRID], t, x[3];
    double floor_, rbest = HUGE_VAL, r;
    int starts[SP_STARTS][2], i, j, k, m;
    circle(s->q0, s->e1, s->q1, &c1, &a1, &b1);
    circle(s->q2, s->e3, s->q3, &c3, &a3, &b3);
    for (i = 0; i < SP_GRID; i++) {
        t = -IK_PI + 2.0 * IK_PI * i / SP_GRID;
        profile(c1, a1, b1, s->e2, t, &ht1[i], &r1[i]);
        profile(c3, a3, b3, s->e2, t, &ht3[i], &r3[i]);
    }
    for (i = 0; i < SP_GRID; i++)
        for (j = 0; j < SP_GRID; j++)
            D[i][j] = (ht1[i] - ht3[j]) * (ht1[i] - ht3[j]) + (r1[i] - r3[j]) * (r1[i] - r3[j]);
    for (i = 0; i < SP_STARTS; i++) starts[i][0] = starts[i][1] = 0;
    floor_ = 1e-16 * pmax(pmax(pmax(norm(s->q0), norm(s->q1)), norm(s->q2)), norm(s->q3));
    best[0] = best[1] = best[2] = 0.0;
    m = grid_minima(D, starts);
    for (k = 0; k < m; k++) {
        x[0] = -IK_PI + 2.0 * IK_PI * starts[k][0] / SP_GRID;
        x[2] = -IK_PI + 2.0 * IK_PI * starts[k][1] / SP_GRID;
        x[1] = sp1(on(c3, a3, b3, x[2]), on(c1, a1, b1, x[0]), s->e2);
        r = refine5(s, x, 60, floor_);
        if (r < rbest) {
            best[0] = x[0]; best[1] = x[1]; best[2] = x[2];
            rbest = r;
        }
    }
    return rbest;
}

/* The least distance of v1 from rot(k2, t2) v3 over t2: by their heights along k2 and
   their distances from it (SP1's t2 attains it). */
static double gap5(vec3 e2, vec3 v1, vec3 v3)
{
    double ht1 = dot(e2, v1), ht3 = dot(e2, v3), d;
    d = norm(sub(v1, scale(e2, ht1))) - norm(sub(v3, scale(e2, ht3)));
    return sqrt((ht1 - ht3) * (ht1 - ht3) + d * d);
}

/* A pair (t1, t3) of pairs: gated as the Python gates it (its residual with t2 by SP1),
   refined by newton2 on pairs' form, t2 by SP1, kept when exact; refine5's damped steps
   from the pair as it came (the Python's) when newton2 leaves it inexact. cab: the
   circles' c1, a1, b1, c3, a3, b3. */
static int try5(const sp5_in *s, const vec3 cab[6], const double M[8], const double f[2],
                double t1, double t3, const double sc0[4], double sol[4][3], double res[4],
                int n, double size)
{
    vec3 v1, v3, w1, w3;
    double x[3], y[2] = {t1, t3}, sc[4] = {sc0[0], sc0[1], sc0[2], sc0[3]}, r[2], g;
    v1 = add(cab[0], add(scale(cab[1], sc[0]), scale(cab[2], sc[1])));
    v3 = add(cab[3], add(scale(cab[4], sc[2]), scale(cab[5], sc[3])));
    if (gap5(s->e2, v1, v3) > SP_ROOT_GATE * size) return n;
    newton2(M, f, y, sc, r, resid2(M, f, sc, r), 8, SP_POLISHED * size);
    w1 = add(cab[0], add(scale(cab[1], sc[0]), scale(cab[2], sc[1])));
    w3 = add(cab[3], add(scale(cab[4], sc[2]), scale(cab[5], sc[3])));
    g = gap5(s->e2, w1, w3);
    if (g <= SP_EXACT * size) {
        x[0] = y[0];
        x[1] = sp1(w3, w1, s->e2);
        x[2] = y[1];
        return keep_distinct(sol, res, n, 3, x, g);
    }
    x[0] = t1;
    x[1] = sp1(v3, v1, s->e2);
    x[2] = t3;
    g = refine5(s, x, 8, 1e-16 * size);
    if (g <= SP_EXACT * size) n = keep_distinct(sol, res, n, 3, x, g);
    return n;
}

/* Angles with u0 + rot(k1, t1) u1 = rot(k2, t2) (u2 + rot(k3, t3) u3): the count (-1: a
   continuum), solution i (t1[i], t2[i], t3[i]), *ls when it is a least-squares one. */
static int sp5(vec3 u0, vec3 u1, vec3 u2, vec3 u3, vec3 k1, vec3 k2, vec3 k3,
               double t1[4], double t2[4], double t3[4], int *ls)
{
    sp5_in s;
    vec3 c1, a1, b1, c3, a3, b3;
    double size, sol[4][3], res[4], M[8], f[2], lengths, pr[8][2], psc[8][4], x[3], r;
    vec3 cab[6];
    int i, j, m, free_, n = 0;
    s.q0 = u0; s.q1 = u1; s.q2 = u2; s.q3 = u3; s.e1 = k1; s.e2 = k2; s.e3 = k3;
    size = pmax(pmax(pmax(norm(u0), norm(u1)), norm(u2)), norm(u3));
    for (i = 0; i < 4; i++) {
        res[i] = HUGE_VAL;
        t1[i] = t2[i] = t3[i] = 0.0;
        for (j = 0; j < 3; j++) sol[i][j] = 0.0;
    }
    *ls = 0;
    if (size == 0.0) return -1;
    circle(u0, k1, u1, &c1, &a1, &b1);
    circle(u2, k3, u3, &c3, &a3, &b3);
    M[0] = dot(k2, a1); M[1] = dot(k2, b1); M[2] = -dot(k2, a3); M[3] = -dot(k2, b3);
    M[4] = dot(c1, a1) / size; M[5] = dot(c1, b1) / size;
    M[6] = -dot(c3, a3) / size; M[7] = -dot(c3, b3) / size;
    lengths = dot(c3, c3) + dot(a3, a3) - dot(c1, c1) - dot(a1, a1);
    f[0] = dot(k2, c3) - dot(k2, c1);
    f[1] = 0.5 * lengths / size;
    m = pairs(M, f, size, pr, psc, &free_);
    cab[0] = c1; cab[1] = a1; cab[2] = b1; cab[3] = c3; cab[4] = a3; cab[5] = b3;
    for (i = 0; i < m; i++)
        n = try5(&s, cab, M, f, pr[i][0], pr[i][1], psc[i], sol, res, n, size);
    if (n == 0) {
        r = ls5(&s, x);
        keep_distinct(sol, res, 0, 3, x, r);
        n = 1;
        *ls = r > SP_EXACT * size;
    }
    for (i = 0; i < n; i++) {
        t1[i] = sol[i][0];
        t2[i] = sol[i][1];
        t3[i] = sol[i][2];
    }
    return free_ ? -1 : n;
}

"""

SP6 = r"""
/* -- SP6 ----------------------------------------------------------------------------- */

/* |r|, the gradient and the Hessian (flat) of |r|^2 / 2 at x for SP6's residuals. */
static double f6(const double M[8], const double f[2], const double x[2], double g[2],
                 double H[4])
{
    double s1 = sin(x[0]), c1 = cos(x[0]), s2 = sin(x[1]), c2 = cos(x[1]), r1, r2;
    double j0, j1, j2, j3;
    r1 = M[0] * s1 + M[1] * c1 + M[2] * s2 + M[3] * c2 - f[0];
    r2 = M[4] * s1 + M[5] * c1 + M[6] * s2 + M[7] * c2 - f[1];
    j0 = M[0] * c1 - M[1] * s1;
    j1 = M[2] * c2 - M[3] * s2;
    j2 = M[4] * c1 - M[5] * s1;
    j3 = M[6] * c2 - M[7] * s2;
    g[0] = j0 * r1 + j2 * r2;
    g[1] = j1 * r1 + j3 * r2;
    H[0] = j0 * j0 + j2 * j2 - r1 * (M[0] * s1 + M[1] * c1) - r2 * (M[4] * s1 + M[5] * c1);
    H[1] = H[2] = j0 * j1 + j2 * j3;
    H[3] = j1 * j1 + j3 * j3 - r1 * (M[2] * s2 + M[3] * c2) - r2 * (M[6] * s2 + M[7] * c2);
    return hypot(r1, r2);
}

static double refine6(const double M[8], const double f[2], double x[2], int iters,
                      double floor_)
{
    double g[2], H[4], y[2], gy[2], Hy[4], step[3], r, ry, mu = 0.0, tr;
    int it, k;
    r = f6(M, f, x, g, H);
    for (it = 0; it < iters; it++) {
        if (r <= floor_) break;
        if (newton_step(H, g, 2, mu, step)) {
            y[0] = x[0] + step[0];
            y[1] = x[1] + step[1];
            ry = f6(M, f, y, gy, Hy);
            if (ry < r) {
                x[0] = y[0]; x[1] = y[1]; g[0] = gy[0]; g[1] = gy[1];
                for (k = 0; k < 4; k++) H[k] = Hy[k];
                r = ry;
                mu *= 0.1;
                continue;
            }
        }
        tr = fabs(H[0]) + fabs(H[3]) + 1e-300;
        mu = pmax(10.0 * mu, 1e-12 * tr);
        if (mu > 1e12 * tr) break;
    }
    return r;
}

static double ls6(const double M[8], const double f[2], double floor_, double best[2])
{
    double D[SP_GRID][SP_GRID], ta, sa, ca, tb, sb, cb, r1, r2, x[2], r, rbest = HUGE_VAL;
    int starts[SP_STARTS][2], i, j, k, m;
    for (i = 0; i < SP_GRID; i++) {
        ta = -IK_PI + 2.0 * IK_PI * i / SP_GRID;
        sa = sin(ta);
        ca = cos(ta);
        for (j = 0; j < SP_GRID; j++) {
            tb = -IK_PI + 2.0 * IK_PI * j / SP_GRID;
            sb = sin(tb);
            cb = cos(tb);
            r1 = M[0] * sa + M[1] * ca + M[2] * sb + M[3] * cb - f[0];
            r2 = M[4] * sa + M[5] * ca + M[6] * sb + M[7] * cb - f[1];
            D[i][j] = r1 * r1 + r2 * r2;
        }
    }
    for (i = 0; i < SP_STARTS; i++) starts[i][0] = starts[i][1] = 0;
    best[0] = best[1] = 0.0;
    m = grid_minima(D, starts);
    for (k = 0; k < m; k++) {
        x[0] = -IK_PI + 2.0 * IK_PI * starts[k][0] / SP_GRID;
        x[1] = -IK_PI + 2.0 * IK_PI * starts[k][1] / SP_GRID;
        r = refine6(M, f, x, 60, floor_);
        if (r < rbest) {
            best[0] = x[0];
            best[1] = x[1];
            rbest = r;
        }
    }
    return rbest;
}

/* A pair (t1, t2) of pairs: gated as the Python gates it, refined by newton2, kept when
   exact; refine6's damped steps from the pair as it came when newton2 leaves it inexact. */
static int try6(const double M[8], const double f[2], double t1, double t2,
                const double sc0[4], double sol[4][3], double res[4], int n, double size)
{
    double x[2] = {t1, t2}, sc[4] = {sc0[0], sc0[1], sc0[2], sc0[3]}, r[2], rabs;
    rabs = resid2(M, f, sc, r);
    if (rabs > SP_ROOT_GATE * size) return n;
    rabs = newton2(M, f, x, sc, r, rabs, 8, SP_POLISHED * size);
    if (!(rabs <= SP_EXACT * size)) {
        x[0] = t1;
        x[1] = t2;
        rabs = refine6(M, f, x, 8, 1e-16 * size);
    }
    if (rabs <= SP_EXACT * size) n = keep_distinct(sol, res, n, 2, x, rabs);
    return n;
}

/* h . rot(k, theta) p = e + alpha sin + beta cos: e, and alpha, beta into *a, *b. */
static double term(vec3 h, vec3 k, vec3 p, double *a, double *b)
{
    double e = dot(h, k) * dot(k, p);
    *a = dot(h, cross(k, p));
    *b = dot(h, p) - e;
    return e;
}

/* Angles with H[0] . rot(K[0], t1) P[0] + H[1] . rot(K[1], t2) P[1] = d1 and
   H[2] . rot(K[2], t1) P[2] + H[3] . rot(K[3], t2) P[3] = d2: as sp5. */
static int sp6(const vec3 H[4], const vec3 K[4], const vec3 P[4], double d1, double d2,
               double t1[4], double t2[4], int *ls)
{
    double M[8], f[2], e[4], size = 0.0, sol[4][3], res[4], pr[8][2], psc[8][4], x[2], r;
    int i, j, m, free_, n = 0;
    for (i = 0; i < 4; i++) {
        e[i] = term(H[i], K[i], P[i], &M[2 * i], &M[2 * i + 1]);
        size = pmax(size, norm(H[i]) * norm(P[i]));
        res[i] = HUGE_VAL;
        t1[i] = t2[i] = 0.0;
        for (j = 0; j < 3; j++) sol[i][j] = 0.0;
    }
    f[0] = d1 - e[0] - e[1];
    f[1] = d2 - e[2] - e[3];
    size = pmax(pmax(size, fabs(d1)), fabs(d2));
    *ls = 0;
    if (size == 0.0) return -1;
    m = pairs(M, f, size, pr, psc, &free_);
    for (i = 0; i < m; i++) n = try6(M, f, pr[i][0], pr[i][1], psc[i], sol, res, n, size);
    if (n == 0) {
        r = ls6(M, f, 1e-16 * size, x);
        keep_distinct(sol, res, 0, 2, x, r);
        n = 1;
        *ls = r > SP_EXACT * size;
    }
    for (i = 0; i < n; i++) {
        t1[i] = sol[i][0];
        t2[i] = sol[i][1];
    }
    return free_ ? -1 : n;
}
"""

# newton2 stops at a residual this small (relative to the largest length): the angles are
# then within rounding of the root for the verdict's FK, far below EXACT
POLISHED = 1e-14

_CONSTANTS = {
    "EXACT": sp56.EXACT,
    "ROOT_GATE": sp56.ROOT_GATE,
    "SINGULAR": sp56.SINGULAR,
    "POLISHED": POLISHED,
}


def source(sp5: bool = False, sp6: bool = False) -> str:
    """The C text of the root finding (``c_roots``) and of SP5 and/or SP6, with the Python
    modules' constants (only what is asked: an unused static function is an error under
    -Wall -Werror)."""
    text = TEXT + (SP5 if sp5 else "") + (SP6 if sp6 else "")
    for name, value in _CONSTANTS.items():
        text = text.replace(f"@{name}@", num(value))
    return c_roots.source() + text
