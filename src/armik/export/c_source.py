"""C99 text shared by every exported solver: literals, the vector and rotation helpers and
the Paden-Kahan subproblems, a line for line translation of
``armik.solvers.closed_form.subproblems`` (the same tolerances, the same branches).

Vectors are ``vec3`` and rotations ``mat3`` (row-major), small structs passed by value as the
compiled Python passes tuples. Every helper is ``static inline IK_UNUSED``: a family uses
some of them, and gcc warns of no unused inline function where clang does
(``-Wunused-function``, an error under ``-Wall -Wextra -Werror``), so ``IK_UNUSED`` is
``__attribute__((unused))`` under gcc and clang, nothing elsewhere.
"""

from __future__ import annotations

import math

import numpy as np

from armik.solvers.closed_form.subproblems import DEGENERATE, ELBOW, EPS, SINGLE


def num(x: float) -> str:
    """A C double literal that reads back as ``x`` exactly (``repr`` round-trips), or
    ``HUGE_VAL`` for an infinity."""
    x = float(x)
    if math.isinf(x):
        return "HUGE_VAL" if x > 0 else "-HUGE_VAL"
    if math.isnan(x):
        raise ValueError("a NaN cannot be folded into C")
    text = repr(x)
    return text if ("." in text or "e" in text) else text + ".0"


def vec(v) -> str:
    """A ``vec3`` initialiser."""
    a = np.asarray(v, dtype=float).ravel()
    return "{{" + ", ".join(num(x) for x in a) + "}}"


def mat(R) -> str:
    """A ``mat3`` initialiser, row-major."""
    a = np.asarray(R, dtype=float).ravel()
    return "{{" + ", ".join(num(x) for x in a) + "}}"


def array(values) -> str:
    """A ``double[]`` initialiser."""
    return "{" + ", ".join(num(x) for x in np.asarray(values, dtype=float).ravel()) + "}"


def constants(names: dict[str, object]) -> str:
    """``static const`` lines: a ``vec3`` for a 3-vector, a ``mat3`` for a 3x3, a double
    for a number."""
    lines = []
    for name, value in names.items():
        a = np.asarray(value, dtype=float)
        if a.shape == (3,):
            lines.append(f"static const vec3 {name} = {vec(a)};")
        elif a.shape == (3, 3):
            lines.append(f"static const mat3 {name} = {mat(a)};")
        else:
            lines.append(f"static const double {name} = {num(float(a))};")
    return "\n".join(lines)


HELPERS = (
    r"""
#ifndef IK_UNUSED  /* a helper a family does not call draws no warning */
#if defined(__GNUC__) || defined(__clang__)
#define IK_UNUSED __attribute__((unused))
#else
#define IK_UNUSED
#endif
#endif

typedef struct { double v[3]; } vec3;
typedef struct { double m[9]; } mat3;

static const double IK_PI = 3.141592653589793;
static const double IK_EPS = @EPS@;
static const double IK_SINGLE = @SINGLE@;
static const double IK_DEGENERATE = @DEGENERATE@;
static const double IK_ELBOW = @ELBOW@;

static inline IK_UNUSED vec3 add(vec3 a, vec3 b)
{ vec3 r = {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]}}; return r; }
static inline IK_UNUSED vec3 sub(vec3 a, vec3 b)
{ vec3 r = {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]}}; return r; }
static inline IK_UNUSED vec3 scale(vec3 a, double s)
{ vec3 r = {{a.v[0] * s, a.v[1] * s, a.v[2] * s}}; return r; }
static inline IK_UNUSED vec3 neg(vec3 a) { vec3 r = {{-a.v[0], -a.v[1], -a.v[2]}}; return r; }
static inline IK_UNUSED vec3 cross(vec3 a, vec3 b)
{
    vec3 r = {{a.v[1] * b.v[2] - a.v[2] * b.v[1], a.v[2] * b.v[0] - a.v[0] * b.v[2],
               a.v[0] * b.v[1] - a.v[1] * b.v[0]}};
    return r;
}
static inline IK_UNUSED double dot(vec3 a, vec3 b)
{ return a.v[0] * b.v[0] + a.v[1] * b.v[1] + a.v[2] * b.v[2]; }
static inline IK_UNUSED double norm(vec3 a)
{ return sqrt(a.v[0] * a.v[0] + a.v[1] * a.v[1] + a.v[2] * a.v[2]); }

/* The angle in (-pi, pi]. */
static inline IK_UNUSED double wrap(double a)
{
    if (-IK_PI < a && a <= IK_PI) return a;
    a -= 2.0 * IK_PI * floor(a / (2.0 * IK_PI));
    return a > IK_PI ? a - 2.0 * IK_PI : a;
}

/* Rotation by t about the unit axis k (Rodrigues), with c = cos t and s = sin t. */
static inline IK_UNUSED mat3 rot_cs(vec3 k, double c, double s)
{
    double v = 1.0 - c, x = k.v[0], y = k.v[1], z = k.v[2];
    mat3 r = {{c + x * x * v, x * y * v - z * s, x * z * v + y * s,
               y * x * v + z * s, c + y * y * v, y * z * v - x * s,
               z * x * v - y * s, z * y * v + x * s, c + z * z * v}};
    return r;
}
static inline IK_UNUSED mat3 rot(vec3 k, double t) { return rot_cs(k, cos(t), sin(t)); }

static inline IK_UNUSED vec3 mv(mat3 A, vec3 x)  /* A x */
{
    const double *a = A.m;
    vec3 r = {{a[0] * x.v[0] + a[1] * x.v[1] + a[2] * x.v[2],
               a[3] * x.v[0] + a[4] * x.v[1] + a[5] * x.v[2],
               a[6] * x.v[0] + a[7] * x.v[1] + a[8] * x.v[2]}};
    return r;
}
static inline IK_UNUSED vec3 mtv(mat3 A, vec3 x)  /* A^T x */
{
    const double *a = A.m;
    vec3 r = {{a[0] * x.v[0] + a[3] * x.v[1] + a[6] * x.v[2],
               a[1] * x.v[0] + a[4] * x.v[1] + a[7] * x.v[2],
               a[2] * x.v[0] + a[5] * x.v[1] + a[8] * x.v[2]}};
    return r;
}
static inline IK_UNUSED mat3 mm(mat3 A, mat3 B)  /* A B */
{
    mat3 r; int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            r.m[3 * i + j] = A.m[3 * i] * B.m[j] + A.m[3 * i + 1] * B.m[3 + j]
                             + A.m[3 * i + 2] * B.m[6 + j];
    return r;
}
static inline IK_UNUSED mat3 mtm(mat3 A, mat3 B)  /* A^T B */
{
    mat3 r; int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            r.m[3 * i + j] = A.m[i] * B.m[j] + A.m[3 + i] * B.m[3 + j] + A.m[6 + i] * B.m[6 + j];
    return r;
}
static inline IK_UNUSED mat3 mmt(mat3 A, mat3 B)  /* A B^T */
{
    mat3 r; int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            r.m[3 * i + j] = A.m[3 * i] * B.m[3 * j] + A.m[3 * i + 1] * B.m[3 * j + 1]
                             + A.m[3 * i + 2] * B.m[3 * j + 2];
    return r;
}

/* SP1: theta with rot(k, theta) p1 = p2 (least squares when none). */
static inline IK_UNUSED double sp1(vec3 p1, vec3 p2, vec3 k)
{
    vec3 kxp = cross(k, p1);
    return atan2(dot(kxp, p2), -dot(cross(k, kxp), p2));
}

/* SP1 with the cosine and sine of theta too (by libm when p1 and p2 leave it free, so
   that they are theta's whatever sign atan2 gives a zero). */
static inline IK_UNUSED double sp1cs(vec3 p1, vec3 p2, vec3 k, double *c, double *s)
{
    vec3 kxp = cross(k, p1);
    double a = dot(kxp, p2), b = -dot(cross(k, kxp), p2), r = sqrt(a * a + b * b), t;
    t = atan2(a, b);
    *c = r > 0.0 ? b / r : cos(t);
    *s = r > 0.0 ? a / r : sin(t);
    return t;
}

/* SP4: theta with h . rot(k, theta) p = d; returns the count (2, 1, or -1 when every
   theta gives the same value), the roots in t[0], t[1], *ls set when one root is only the
   least-squares answer. Two roots that a change of d by merge (m) or less makes one are
   one, phi + r kept (subproblems._sp4). */
static inline IK_UNUSED int sp4m(vec3 h, vec3 p, vec3 k, double d, double merge, double t[2],
                       int *ls)
{
    vec3 kxp = cross(k, p);
    double a = dot(h, kxp), b = -dot(h, cross(k, kxp));
    double c = d - dot(h, k) * dot(k, p);
    double rho = hypot(a, b), phi, x, tol, np = norm(p), ad = fabs(d), r;
    tol = np > ad ? np : ad;
    tol = IK_DEGENERATE * (tol > 1.0 ? tol : 1.0);
    t[0] = t[1] = 0.0;
    *ls = 0;
    if (rho <= tol) return -1;
    phi = atan2(a, b);
    x = c / rho;
    if (fabs(x) >= 1.0) {
        *ls = fabs(x) > 1.0 + IK_EPS;
        t[0] = wrap(x > 0 ? phi : phi + IK_PI);
        return 1;
    }
    r = acos(x);
    if (r < IK_SINGLE) { t[0] = wrap(phi); return 1; }
    if (r > IK_PI - IK_SINGLE) { t[0] = wrap(phi + IK_PI); return 1; }
    t[0] = wrap(phi + r);
    if (rho * (1.0 - fabs(x)) <= merge) return 1;  /* a double root but for rounding */
    t[1] = wrap(phi - r);
    return 2;
}
static inline IK_UNUSED int sp4(vec3 h, vec3 p, vec3 k, double d, double t[2])
{
    int ls;
    return sp4m(h, p, k, d, 0.0, t, &ls);
}

/* SP3 at an elbow: theta with |rot(k, theta) p1 - p2| = d, its two roots one where a change
   of d by IK_ELBOW (m) or less makes them a double root (subproblems.elbow). */
static inline IK_UNUSED int sp3(vec3 p1, vec3 p2, vec3 k, double d, double t[2], int *ls)
{
    double n2 = norm(p2);
    *ls = 0;
    if (n2 <= IK_EPS) { t[0] = t[1] = 0.0; return -1; }
    return sp4m(scale(p2, 1.0 / n2), p1, k, (dot(p1, p1) + n2 * n2 - d * d) / (2.0 * n2),
                IK_ELBOW * d / n2, t, ls);
}

/* The angle nearest t where |rot(k, .) p1 - p2| is at its largest or smallest (the elbow
   stretched or folded; subproblems.elbow_extreme). */
static inline IK_UNUSED double elbow_extreme(vec3 p1, vec3 p2, vec3 k, double t)
{
    vec3 kxp = cross(k, p1);
    double phi = atan2(dot(p2, kxp), -dot(p2, cross(k, kxp)));
    return cos(t - phi) >= 0.0 ? phi : wrap(phi + IK_PI);
}

/* The elbow's roots as the closed forms solve them (elbow_pair.elbow_roots): sp3's count (-1, 1
   or 2) returned, how many roots to solve in *roots. Where rounding split a stretched or
   folded elbow's double root into one (1, not least squares), its mirror about the extreme
   beside it is t[1], both exact: both solved (2; 1 where the mirror is the root itself),
   the better row of each pair kept by keep_nearer. 1 where every turn spans d (-1). */
static inline IK_UNUSED int elbow_roots(vec3 p1, vec3 p2, vec3 k, double d, double t[2],
                              int *roots)
{
    int ls, n = sp3(p1, p2, k, d, t, &ls);
    *roots = n == 2 ? 2 : 1;
    if (n == 1 && !ls) {
        t[1] = wrap(2.0 * elbow_extreme(p1, p2, k, t[0]) - t[0]);
        *roots = t[1] != t[0] ? 2 : 1;
    }
    return n;
}

/* elbow_roots with the cosines and sines of its angles too: the two regular roots' from
   SP4's atan2 and acos terms by the angle sums (no libm call), the others' from libm. */
static inline IK_UNUSED int elbow_roots_cs(vec3 p1, vec3 p2, vec3 k, double d, double t[2],
                                 double c[2], double s[2], int *roots)
{
    double n2 = norm(p2), a, b, rho, x, sr;
    vec3 h, kxp;
    int n = elbow_roots(p1, p2, k, d, t, roots), i;
    if (n == 2) {  /* as sp4 found them: phi + r and phi - r, cos r = x */
        h = scale(p2, 1.0 / n2);
        kxp = cross(k, p1);
        a = dot(h, kxp);
        b = -dot(h, cross(k, kxp));
        rho = sqrt(a * a + b * b);
        x = ((dot(p1, p1) + n2 * n2 - d * d) / (2.0 * n2) - dot(h, k) * dot(k, p1)) / rho;
        sr = sqrt(1.0 - x * x);
        a /= rho;
        b /= rho;
        c[0] = b * x - a * sr;
        s[0] = a * x + b * sr;
        c[1] = b * x + a * sr;
        s[1] = a * x - b * sr;
        return n;
    }
    for (i = 0; i < 2; i++) {
        c[i] = cos(t[i]);
        s[i] = sin(t[i]);
    }
    return n;
}

/* SP2: (a[i], b[i]) with rot(k1, a) p1 = rot(k2, b) p2, -1 when p1 lies on k1 (a = free),
   with their cosines and sines (ca, sa, cb, sb) from SP1's (no libm call but the free
   angle's). */
static inline IK_UNUSED int sp2cs(vec3 p1, vec3 p2, vec3 k1, vec3 k2, double free_, double a[2],
                        double b[2], double ca[2], double sa[2], double cb[2], double sb[2])
{
    double n1 = norm(p1), n2 = norm(p2), k12, den, c1, c2, alpha, beta, g2, g;
    vec3 u1 = scale(p1, 1.0 / n1), u2 = scale(p2, 1.0 / n2), base, k1xk2, c;
    a[1] = b[1] = 0.0;
    ca[1] = cb[1] = 1.0;
    sa[1] = sb[1] = 0.0;
    if (norm(cross(k1, u1)) <= IK_SINGLE) {
        a[0] = free_;
        ca[0] = cos(free_);
        sa[0] = sin(free_);
        b[0] = sp1cs(u2, mv(rot_cs(k1, ca[0], sa[0]), u1), k2, &cb[0], &sb[0]);
        return -1;
    }
    k12 = dot(k1, k2);
    den = 1.0 - k12 * k12;
    c1 = dot(k1, u1);
    c2 = dot(k2, u2);
    alpha = (c1 - k12 * c2) / den;
    beta = (c2 - k12 * c1) / den;
    g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * k12) / den;
    g = g2 > 0.0 ? sqrt(g2) : 0.0;
    base = add(scale(k1, alpha), scale(k2, beta));
    k1xk2 = cross(k1, k2);
    c = add(base, scale(k1xk2, g));
    a[0] = sp1cs(u1, c, k1, &ca[0], &sa[0]);
    b[0] = sp1cs(u2, c, k2, &cb[0], &sb[0]);
    if (g < 1e-9) return 1;
    c = sub(base, scale(k1xk2, g));
    a[1] = sp1cs(u1, c, k1, &ca[1], &sa[1]);
    b[1] = sp1cs(u2, c, k2, &cb[1], &sb[1]);
    return 2;
}
""".replace("@EPS@", num(EPS))
    .replace("@SINGLE@", num(SINGLE))
    .replace("@DEGENERATE@", num(DEGENERATE))
    .replace("@ELBOW@", num(ELBOW))
)


# The C of ``elbow_pair.keep_nearer`` (after the limits ``LO``, ``HI``, ``SNAP`` and ``TIE``): of a
# merged elbow root's rows and its mirror's, the better of each pair kept. Joints 1 to 6 of
# the chain the family solves are columns 0 to 5 (in the arm's order when it is read from the
# tip; a held seventh joint is written after).
KEEP_NEARER = r"""
/* |c - ref| for c the value of angle v (by whole turns) nearest ref within [lo, hi] (up to
   SNAP past a limit counts as on it); INFINITY when no turn of it is (elbow_pair._from_ref). */
static IK_UNUSED double from_ref(double v, double ref, double lo, double hi)
{
    const double two_pi = 2.0 * IK_PI;
    double near = v + two_pi * nearbyint((ref - v) / two_pi), best = INFINITY, c;
    int k;
    for (k = -1; k <= 1; k++) {
        c = near + k * two_pi;
        if (lo - SNAP <= c && c <= hi + SNAP && fabs(c - ref) < best) best = fabs(c - ref);
    }
    return best;
}

/* Rows [a, b) solved from a merged elbow root and rows [b, c) from its mirror (both exact,
   the same branches in the same order): of each pair within DUPLICATE_TOL of each other in
   every joint (one solution) the row with fewer joints outside the limits, then with the
   elbow (column e) nearer Q0's within its limits by more than TIE, is left in [a, b); a
   pair further apart is two solutions, the mirror's row kept after [a, b). Returns the row
   count; where the counts differ the first rows are kept (elbow_pair.keep_nearer). */
static IK_UNUSED int keep_nearer(double W[][DOF], double C[][DOF], double S[][DOF], int a,
                                 int b, int c, int e, const double *Q0)
{
    int i, j, out_a, out_b, n = b, apart;
    double d_a, d_b;
    if (c - b != b - a) return b;
    for (i = 0; i < b - a; i++) {
        apart = 0;
        for (j = 0; j < 6; j++)
            if (fabs(wrap(W[a + i][j] - W[b + i][j])) >= DUPLICATE_TOL) apart = 1;
        if (apart) {  /* rows from [b, c) move down to n <= b + i */
            for (j = 0; j < DOF; j++) {
                W[n][j] = W[b + i][j];
                C[n][j] = C[b + i][j];
                S[n][j] = S[b + i][j];
            }
            n++;
            continue;
        }
        out_a = out_b = 0;
        for (j = 0; j < 6; j++) {
            out_a += from_ref(W[a + i][j], Q0[j], LO[j], HI[j]) == INFINITY;
            out_b += from_ref(W[b + i][j], Q0[j], LO[j], HI[j]) == INFINITY;
        }
        d_a = from_ref(W[a + i][e], Q0[e], LO[e], HI[e]);
        d_b = from_ref(W[b + i][e], Q0[e], LO[e], HI[e]);
        if (out_b < out_a || (out_b == out_a && d_b < d_a - TIE))
            for (j = 0; j < 6; j++) {
                W[a + i][j] = W[b + i][j];
                C[a + i][j] = C[b + i][j];
                S[a + i][j] = S[b + i][j];
            }
    }
    return n;
}
"""
