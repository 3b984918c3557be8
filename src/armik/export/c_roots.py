"""The root finding of ``armik.solvers.closed_form.roots`` as C99 text (the same
tolerances, the same brackets, the same order of roots): real roots of a quartic by its
derivative's, the trigonometric equations of degree 1 and 2, and what refines SP5's and
SP6's roots (``keep_distinct``, ``newton_step``, ``newton2``, ``grid_minima``).
``c_subproblems_56`` builds SP5 and SP6 on it; it goes after ``c_source.HELPERS``
(``wrap``). Python's ``max(a, b)`` is written ``pmax(a, b)``: a unless b is larger, as
Python has it.

Where the C is cheaper than a line-for-line copy, it finds the same roots: each bracket's
Newton starts from the root of the quadratic model at its critical end and ends on a step
within rounding (the Python starts from the middle and bisects the far end down to the
root); ``trig2`` reads its 8 samples' sines and cosines from tables of libm's values and
gives its roots' sines and cosines from the half-angle form.
"""

from __future__ import annotations

import math

from armik.export.c_source import num
from armik.solvers.closed_form import roots
from armik.solvers.closed_form import subproblems_56 as sp56

TEXT = r"""
static const double RT_LEAD = @LEAD@, RT_TOUCH = @TOUCH@, RT_MERGE = @MERGE@;
static const double RT_SAME = @SAME@;
#undef SP_GRID  /* this file's own, whatever the build defines */
#define SP_GRID @GRID@
#undef SP_STARTS
#define SP_STARTS @STARTS@

static inline IK_UNUSED double pmax(double a, double b) { return b > a ? b : a; }
static inline IK_UNUSED double pmin(double a, double b) { return b < a ? b : a; }

/* p(x) by Horner's rule, p'(x) into *df; c highest power first. */
static double poly_value(const double *c, int deg, double x, double *df)
{
    double f = c[0], d = 0.0;
    int i;
    for (i = 1; i <= deg; i++) {
        d = d * x + f;
        f = f * x + c[i];
    }
    *df = d;
    return f;
}

static double poly_size(const double *c, int deg, double x)  /* sum |c_i| |x|^i */
{
    double ax = fabs(x), m = fabs(c[0]);
    int i;
    for (i = 1; i <= deg; i++) m = m * ax + fabs(c[i]);
    return m;
}

/* The root in [lo, hi] (p(lo) = flo, p(hi) of the other sign): Newton, bisecting whenever
   Newton would leave the bracket. A Newton step within rounding ends it (where the Python
   bisects on until the bracket is as small, its far end untouched by Newton's steps
   from one side: up to 50 steps more for the same root). */
static double bracketed(const double *c, int deg, double lo, double hi, double flo,
                        double x)
{
    double f, df, xn;
    int it;
    for (it = 0; it < 200; it++) {
        f = poly_value(c, deg, x, &df);
        if (f == 0.0) return x;
        if ((f < 0.0) == (flo < 0.0)) lo = x;
        else hi = x;
        xn = df != 0.0 ? x - f / df : 0.5 * (lo + hi);
        if (df != 0.0 && fabs(xn - x) <= 4e-16 * pmax(1.0, fabs(x)))
            return lo <= xn && xn <= hi ? xn : x;
        if (!(lo < xn && xn < hi)) xn = 0.5 * (lo + hi);
        if (fabs(xn - x) <= 4e-16 * pmax(1.0, fabs(x)) || hi - lo <= 4e-16 * pmax(1.0, fabs(x)))
            return xn;
        x = xn;
    }
    return x;
}

/* Where bracketed starts in [lo, hi]: the root of p's quadratic model p(e) + p''(e)
   (x - e)^2 / 2 at the end e that is a root of the derivative (the one where |p| is
   smaller when both are), when it lies within; else the middle. From the middle, Newton's
   steps cut the distance to a root far from it by only 1 / deg a step. */
static double start(const double *c, int deg, double lo, double hi, double flo, double fhi,
                    int k, int ncrit)
{
    double e, fe, h = 0.0, d1 = 0.0, f = c[0], x, r;
    int i, left;
    if (ncrit == 0) return 0.5 * (lo + hi);
    if (k == 0) left = 0;  /* [-bound, crit[0]] */
    else if (k == ncrit) left = 1;  /* [crit[ncrit - 1], bound] */
    else left = fabs(flo) <= fabs(fhi);
    e = left ? lo : hi;
    fe = left ? flo : fhi;
    for (i = 1; i <= deg; i++) {  /* h = p''(e) / 2 by Horner's rule */
        h = h * e + d1;
        d1 = d1 * e + f;
        f = f * e + c[i];
    }
    r = -fe / h;
    if (!(r > 0.0)) return 0.5 * (lo + hi);
    x = left ? e + sqrt(r) : e - sqrt(r);
    return lo < x && x < hi ? x : 0.5 * (lo + hi);
}

/* The real roots of p given its derivative's ncrit real roots crit (ascending). */
static int roots_between(const double *c, int deg, const double *crit, int ncrit, double *out)
{
    double lead = fabs(c[0]), bound = 0.0, lo, flo, hi, fhi, df, x;
    int i, k, n = 0, crossing, touch;
    for (i = 1; i <= deg; i++) bound = pmax(bound, fabs(c[i]) / lead);
    bound += 1.0;
    lo = -bound;
    flo = poly_value(c, deg, lo, &df);
    for (k = 0; k <= ncrit; k++) {
        hi = k < ncrit ? crit[k] : bound;
        fhi = poly_value(c, deg, hi, &df);
        crossing = flo != 0.0 && fhi != 0.0 && ((flo < 0.0) != (fhi < 0.0));
        if (crossing && hi > lo) {
            x = bracketed(c, deg, lo, hi, flo, start(c, deg, lo, hi, flo, fhi, k, ncrit));
            if (n == 0 || x - out[n - 1] > RT_MERGE * (1.0 + fabs(x))) out[n++] = x;
        }
        touch = k < ncrit && !crossing && fabs(fhi) <= RT_TOUCH * poly_size(c, deg, hi);
        if ((touch || fhi == 0.0) && (n == 0 || hi - out[n - 1] > RT_MERGE * (1.0 + fabs(hi))))
            out[n++] = hi;
        lo = hi;
        flo = fhi;
    }
    return n;
}

/* The real roots of the degree-deg polynomial c (leading term nonzero), ascending. */
static int real_roots(const double *c, int deg, double *out)
{
    double dc[5] = {0.0, 0.0, 0.0, 0.0, 0.0}, crit[4] = {0.0, 0.0, 0.0, 0.0};
    double a, b, e, disc, sq, q, r0, r1;
    int i, ncrit;
    if (deg == 0) return 0;
    if (deg == 1) { out[0] = -c[1] / c[0]; return 1; }
    if (deg == 2) {
        a = c[0]; b = c[1]; e = c[2];
        disc = b * b - 4.0 * a * e;
        if (disc < 0.0) {
            if (-disc > 4.0 * RT_TOUCH * (b * b + 4.0 * fabs(a * e))) return 0;
            disc = 0.0;
        }
        if (disc == 0.0) { out[0] = -b / (2.0 * a); return 1; }
        sq = sqrt(disc);
        q = b >= 0.0 ? -0.5 * (b + sq) : -0.5 * (b - sq);
        r0 = q / a;
        r1 = q != 0.0 ? e / q : -q / a;
        out[0] = pmin(r0, r1);
        out[1] = pmax(r0, r1);
        return out[0] == out[1] ? 1 : 2;
    }
    for (i = 0; i < deg; i++) dc[i] = c[i] * (deg - i);
    ncrit = real_roots(dc, deg - 1, crit);
    return roots_between(c, deg, crit, ncrit, out);
}

/* The real roots of coef[0] x^4 + ... + coef[4], ascending; -1 when every coefficient is
   0. Leading coefficients below RT_LEAD of the largest are dropped. */
static int quartic(const double coef[5], double out[4])
{
    double big = 0.0, c[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
    int i, start = 0;
    out[0] = out[1] = out[2] = out[3] = 0.0;
    for (i = 0; i < 5; i++) big = pmax(big, fabs(coef[i]));
    if (big == 0.0 || !isfinite(big)) return -1;
    while (start < 4 && fabs(coef[start]) <= RT_LEAD * big) start++;
    for (i = start; i < 5; i++) c[i - start] = coef[i] / big;
    return real_roots(c, 4 - start, out);
}

/* theta with a sin + b cos = c: the count (-1: a = b = 0), *ls when none is exact. */
static int trig1(double a, double b, double c, double *t0, double *t1, int *ls)
{
    double rho = hypot(a, b), phi, x, t;
    *t0 = *t1 = 0.0;
    if (rho == 0.0) { *ls = c != 0.0; return -1; }
    phi = atan2(a, b);
    x = c / rho;
    if (fabs(x) >= 1.0) {
        *t0 = wrap(x > 0 ? phi : phi + IK_PI);
        *ls = fabs(x) > 1.0 + 1e-12;
        return 1;
    }
    t = acos(x);
    *t0 = wrap(phi + t);
    *t1 = wrap(phi - t);
    *ls = 0;
    return 2;
}

/* The real roots of A0 + A1 sin t + B1 cos t + A2 sin 2t + B2 cos 2t, up to 4, with their
   sines and cosines (from the half-angle form, no libm call). The 8 samples t = 2 pi i / 8
   and t0 = t - pi read their sines and cosines from tables (libm's values, folded in). */
static const double T2_S[8] = @T2_S@, T2_C[8] = @T2_C@;
static const double T2_S2[8] = @T2_S2@, T2_C2[8] = @T2_C2@;
static const double T2_S0[8] = @T2_S0@, T2_C0[8] = @T2_C0@;
static const double T2_S20[8] = @T2_S20@, T2_C20[8] = @T2_C20@;
static int trig2(double A0, double A1, double B1, double A2, double B2, double out[4],
                 double so[4], double co[4])
{
    double best = -1.0, v, c, s, c2, s2, a1, b1, a2, b2, coef[5], x[4], d, cx, sx;
    int i, k = 0, n;
    for (i = 0; i < 8; i++) {
        v = A0 + A1 * T2_S[i] + B1 * T2_C[i];
        v = fabs(v + A2 * T2_S2[i] + B2 * T2_C2[i]);
        if (v > best) { best = v; k = i; }
    }
    c = T2_C0[k]; s = T2_S0[k]; c2 = T2_C20[k]; s2 = T2_S20[k];
    a1 = A1 * c - B1 * s; b1 = A1 * s + B1 * c;
    a2 = A2 * c2 - B2 * s2; b2 = A2 * s2 + B2 * c2;
    coef[0] = A0 - b1 + b2;
    coef[1] = 2.0 * a1 - 4.0 * a2;
    coef[2] = 2.0 * A0 - 6.0 * b2;
    coef[3] = 2.0 * a1 + 4.0 * a2;
    coef[4] = A0 + b1 + b2;
    n = quartic(coef, x);
    n = n > 0 ? n : 0;
    for (i = 0; i < n; i++) {
        out[i] = (2.0 * IK_PI * k / 8.0 - IK_PI) + 2.0 * atan(x[i]);
        d = 1.0 / (1.0 + x[i] * x[i]);  /* 2 atan(x): cosine (1 - x^2) d, sine 2 x d */
        cx = (1.0 - x[i] * x[i]) * d;
        sx = 2.0 * x[i] * d;
        so[i] = s * cx + c * sx;
        co[i] = c * cx - s * sx;
    }
    return n;
}

/* Add solution t (m angles) of residual r to the n kept (at most 4, distinct). */
static int keep_distinct(double sol[4][3], double res[4], int n, int m, const double *t, double r)
{
    int i, j, same, slot;
    for (i = 0; i < n; i++) {
        same = 1;
        for (j = 0; j < m; j++)
            if (fabs(wrap(sol[i][j] - t[j])) > RT_SAME) same = 0;
        if (same) {
            if (r < res[i]) {
                for (j = 0; j < m; j++) sol[i][j] = t[j];
                res[i] = r;
            }
            return n;
        }
    }
    slot = n;
    if (n == 4) {
        slot = 0;
        for (i = 1; i < 4; i++)
            if (res[i] > res[slot]) slot = i;
        if (r >= res[slot]) return n;
    }
    for (j = 0; j < m; j++) sol[slot][j] = wrap(t[j]);
    res[slot] = r;
    return n < 4 ? n + 1 : n;
}

/* s with (H + mu I) s = -g (m = 2 or 3, H flat row-major); 0 unless positive definite. */
static int newton_step(const double *H, const double *g, int m, double mu, double s[3])
{
    double a, b, d, det, a00, a01, a02, a11, a12, a22, c00, c01, c02, c11, c12, c22;
    s[0] = s[1] = s[2] = 0.0;
    if (m == 2) {
        a = H[0] + mu; b = H[1]; d = H[3] + mu;
        det = a * d - b * b;
        if (!(a > 0.0 && det > 0.0)) return 0;
        s[0] = -(d * g[0] - b * g[1]) / det;
        s[1] = -(a * g[1] - b * g[0]) / det;
        return 1;
    }
    a00 = H[0] + mu; a01 = H[1]; a02 = H[2];
    a11 = H[4] + mu; a12 = H[5]; a22 = H[8] + mu;
    c00 = a11 * a22 - a12 * a12;
    c01 = a02 * a12 - a01 * a22;
    c02 = a01 * a12 - a02 * a11;
    c11 = a00 * a22 - a02 * a02;
    c12 = a01 * a02 - a00 * a12;
    c22 = a00 * a11 - a01 * a01;
    det = a00 * c00 + a01 * c01 + a02 * c02;
    if (!(a00 > 0.0 && c22 > 0.0 && det > 0.0)) return 0;
    s[0] = -(c00 * g[0] + c01 * g[1] + c02 * g[2]) / det;
    s[1] = -(c01 * g[0] + c11 * g[1] + c12 * g[2]) / det;
    s[2] = -(c02 * g[0] + c12 * g[1] + c22 * g[2]) / det;
    return 1;
}

/* The residual r = M (sin x0, cos x0, sin x1, cos x1) - (f0, f1) at sc = (sin x0, cos x0,
   sin x1, cos x1) into r; returns |r|. */
static inline IK_UNUSED double resid2(const double M[8], const double f[2], const double sc[4],
                            double r[2])
{
    r[0] = M[0] * sc[0] + M[1] * sc[1] + M[2] * sc[2] + M[3] * sc[3] - f[0];
    r[1] = M[4] * sc[0] + M[5] * sc[1] + M[6] * sc[2] + M[7] * sc[3] - f[1];
    return sqrt(r[0] * r[0] + r[1] * r[1]);
}

/* Newton's steps on the square system r(x) = 0 of SP5's and SP6's pairs from x (sines and cosines
   sc, residual r, |r| = rabs), each kept only when it lowers |r|, none once |r| <= stop,
   at most iters: x, sc and r updated in place; returns |r|. Two sines and cosines a step,
   where refine5 and refine6 take the gradient and Hessian of |r|^2 / 2 (their damped
   steps remain for what this leaves inexact). */
static double newton2(const double M[8], const double f[2], double x[2], double sc[4],
                      double r[2], double rabs, int iters, double stop)
{
    double j00, j01, j10, j11, det, y[2], sy[4], ry[2], rn;
    int it;
    for (it = 0; it < iters && rabs > stop; it++) {
        j00 = M[0] * sc[1] - M[1] * sc[0];
        j01 = M[2] * sc[3] - M[3] * sc[2];
        j10 = M[4] * sc[1] - M[5] * sc[0];
        j11 = M[6] * sc[3] - M[7] * sc[2];
        det = j00 * j11 - j01 * j10;
        if (!(fabs(det) > 0.0)) break;
        y[0] = x[0] - (j11 * r[0] - j01 * r[1]) / det;
        y[1] = x[1] - (j00 * r[1] - j10 * r[0]) / det;
        sy[0] = sin(y[0]); sy[1] = cos(y[0]); sy[2] = sin(y[1]); sy[3] = cos(y[1]);
        rn = resid2(M, f, sy, ry);
        if (!(rn < rabs)) break;
        x[0] = y[0]; x[1] = y[1];
        sc[0] = sy[0]; sc[1] = sy[1]; sc[2] = sy[2]; sc[3] = sy[3];
        r[0] = ry[0]; r[1] = ry[1];
        rabs = rn;
    }
    return rabs;
}

/* The local minima of the periodic grid D, lowest first, into out; their count. */
static int grid_minima(double D[SP_GRID][SP_GRID], int out[SP_STARTS][2])
{
    double vals[SP_STARTS], top = 0.0, d;
    int i, j, di, dj, a, k, low, n = 0;
    for (i = 0; i < SP_STARTS; i++) vals[i] = HUGE_VAL;
    for (i = 0; i < SP_GRID; i++)
        for (j = 0; j < SP_GRID; j++) top = pmax(top, D[i][j]);
    for (i = 0; i < SP_GRID; i++)
        for (j = 0; j < SP_GRID; j++) {
            d = D[i][j];
            low = 1;
            for (di = -1; di <= 1; di++)
                for (dj = -1; dj <= 1; dj++)
                    if ((di != 0 || dj != 0)
                        && D[(i + di + SP_GRID) % SP_GRID][(j + dj + SP_GRID) % SP_GRID] < d)
                        low = 0;
            if (!low || (n == SP_STARTS && d >= vals[SP_STARTS - 1])) continue;
            for (a = 0; a < n; a++)
                if ((out[a][0] == i || out[a][1] == j)
                    && fabs(vals[a] - d) <= 1e-9 * d + 1e-14 * top)
                    low = 0;
            if (!low) continue;
            k = n < SP_STARTS - 1 ? n : SP_STARTS - 1;
            while (k > 0 && vals[k - 1] > d) {
                vals[k] = vals[k - 1];
                out[k][0] = out[k - 1][0];
                out[k][1] = out[k - 1][1];
                k--;
            }
            vals[k] = d;
            out[k][0] = i;
            out[k][1] = j;
            n = n + 1 < SP_STARTS ? n + 1 : SP_STARTS;
        }
    return n;
}

"""

_CONSTANTS = {"LEAD": roots.LEAD, "TOUCH": roots.TOUCH, "MERGE": roots.MERGE, "SAME": roots.SAME}


def _samples() -> dict[str, str]:
    """``trig2``'s tables: the sines and cosines of its 8 samples t, of 2 t, of t0 = t - pi
    and of 2 t0, as the Python computes them."""
    ts = [2.0 * math.pi * i / 8.0 for i in range(8)]
    rows = {
        "T2_S": [math.sin(t) for t in ts],
        "T2_C": [math.cos(t) for t in ts],
        "T2_S2": [math.sin(2.0 * t) for t in ts],
        "T2_C2": [math.cos(2.0 * t) for t in ts],
        "T2_S0": [math.sin(t - math.pi) for t in ts],
        "T2_C0": [math.cos(t - math.pi) for t in ts],
        "T2_S20": [math.sin(2 * (t - math.pi)) for t in ts],
        "T2_C20": [math.cos(2 * (t - math.pi)) for t in ts],
    }
    return {name: "{" + ", ".join(num(x) for x in xs) + "}" for name, xs in rows.items()}


def source() -> str:
    """The C text of the root finding, with the Python modules' constants."""
    text = TEXT.replace("@GRID@", str(sp56.GRID)).replace("@STARTS@", str(sp56.STARTS))
    for name, table in _samples().items():
        text = text.replace(f"@{name}@", table)
    for name, value in _CONSTANTS.items():
        text = text.replace(f"@{name}@", num(value))
    return text
