"""One exported solver's two files, ``N_ik.h`` and ``N_ik.c``, around a family's rows.

A family (``planar2r``, ``three_parallel``, ``spherical_wrist`` in this package) gives the
C text of ``static int rows(mat3 R, vec3 p, double W[][DOF], double C[][DOF], double
S[][DOF])``: its candidate joint values for the target (R, p) written by ``put_row``, each
angle in (-pi, pi] with its cosine and sine, a singular case's free joint at the middle of
its limits (``solve_all``'s seed when none is given), or at the values ``Rows.sweep`` tries
where that leaves no row verified. This module adds what every family shares, as the Python
path does it:

- each angle shifted by 2 pi to the value nearest the middle of its limits within them
  (``sixr.nearest_equivalents``; a family's ``snap``: how far outside a limit counts as on
  it);
- the verdict: a row is kept when it is within the limits (``LIMIT_TOL``) and its forward
  kinematics (the product of exponentials of the arm's axis lines at q = 0, ``N_fk``'s,
  on the row's cosines and sines, which a shift by 2 pi leaves and a snap onto a limit
  moves by at most ``snap``) reaches the target within the tolerances (armik's
  ``Options.tol_position``, ``tol_orientation`` unless given), so a least-squares row or
  a NaN never leaves;
- the order of ``solve_all``: nearest the middle of the limits first, ties by the joint
  values (``before``, ``sixr.pack``'s rule), a row within ``DUPLICATE_TOL`` of one listed
  before it in every joint left out, as ``solve_all`` leaves it (a double root found twice).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

from armik.export import c_source, fk_code, free_sweep
from armik.kernel.descent import DUPLICATE_TOL
from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes
from armik.problem.settings import SolverSettings
from armik.solvers.closed_form.sixr import FREE_SWEEP, TIE
from armik.tolerances import LAST_ROW_TOL, LIMIT_TOL, MAX_POSITION, ROTATION_TOL

# a rotation further than this from orthonormal (an entry of |R^T R - I|) is snapped onto
# the nearest rotation before it is solved, as ``armik.targets.pose`` snaps a target's
ROTATION_SNAP = 1e-14


@dataclass(frozen=True)
class Rows:
    """A family's part of ``N_ik.c``: the text defining ``rows`` (and its helpers), the
    most rows it writes, how far outside a limit counts as on it (rad), and one line saying
    what it solves. ``held``: the index of a joint whose value ``N_ik`` takes as an argument
    (a 7R arm with a joint held; ``rows`` then takes it after the target, ``static int
    rows(mat3 R, vec3 p, double held, ...)``, and writes it in its column), else None.
    ``reversed``: the family solves the chain read from the tip (joints 6 to 1), so that
    ties in the distance go by the joints in that order, as its kernel's ``sixr.pack``.
    ``sweep``: the joints a singular pose leaves free, in the order the family's kernel
    sweeps them (``rows`` then takes the seed and a mask after the target and the held
    value, ``..., const double *Q0, int *mask, W, C, S)``: a free joint at Q0's value, its
    bit set in ``*mask``); where no row at the middle of the limits is verified, the first
    free joint's other values are tried as ``sixr.FREE_SWEEP`` does, nearest the middle
    first, and the first value that gives a verified row is kept. ``settle``: the C name of
    a pass over the rows once the free joints' values are chosen (``static void
    settle(double W[][DOF], double C[][DOF], double S[][DOF], int n)``, before the rows are
    judged again: the swept 7R arm's split of two joints in line), else empty."""

    text: str
    max_rows: int
    snap: float
    summary: str
    held: int | None = None
    sweep: tuple[int, ...] = ()
    reversed: bool = False
    settle: str = ""


def _comment(text: str) -> str:
    """``text`` wrapped for a C comment's lines (indented by three spaces after the first),
    in ASCII: a name from the URDF that is not is written with Python's escapes, so that the
    files are the same bytes whatever the locale and compiler read them as."""
    plain = text.replace("*/", "* /").encode("ascii", "backslashreplace").decode("ascii")
    return "\n   ".join(textwrap.wrap(plain, 86))


def header(
    name: str, dof: int, max_solutions: int, summary: str, tol_position: float,
    tol_orientation: float, held: int | None = None,
) -> str:  # fmt: skip
    up = name.upper()
    title = _comment(f"{name}_ik.h: closed-form inverse kinematics of {summary}.")
    last_row, rotation = c_source.num(LAST_ROW_TOL), c_source.num(ROTATION_TOL)
    max_position = f"{MAX_POSITION:g}"
    if held is None:
        call, arg, define, held_text = "(T, q)", "", "", ""
    else:
        call, arg = "(T, held, q)", "double held, "
        define = f"#define {up}_IK_HELD_JOINT {held}  /* q[.][{held}] is the held joint */\n"
        held_text = (
            f"\n   The joint of index {held} (joint {held + 1}) is held at `held` (rad), which must"
            f" lie within its\n   limits (up to {c_source.num(LIMIT_TOL)} outside one it is taken"
            " as on it; else, or when it is not finite,\n   -1); every solution has it there."
        )
    return f"""/* {title}
   Generated by armik (armik export); plain C99, needs only libm.

   {name}_ik{call}: every solution within the joint limits for the tip pose T (4x4,
   row-major, in the arm's base frame; the tip and tool offset as loaded), in the order
   armik's solve_all gives them (nearest the middle of the limits first), each verified by
   {name}_fk to {tol_position:g} m and {tol_orientation:g} rad. Returns how many (0: out of
   reach), or -1 when T is not finite, its position is beyond {max_position} m from the base
   in a coordinate, its last row is not (0, 0, 0, 1) to {last_row}, or its rotation is not
   orthonormal to {rotation} or has determinant -1 (a reflection): the poses solve_all
   refuses. A rotation within that of orthonormal is solved as the nearest rotation, as
   solve_all snaps it. At a singular pose a free joint is set to
   the middle of its limits, as solve_all sets it with no q0 (where that leaves none within
   the limits, its other values nearest the middle first, as solve_all tries them): a
   singular target gives no more solutions than a regular one next to it.{held_text}
   {name}_fk(q, T): the tip pose at joint values q (rad), row-major 4x4. */
#ifndef {up}_IK_H
#define {up}_IK_H

#define {up}_IK_DOF {dof}
#define {up}_IK_MAX_SOLUTIONS {max_solutions}
{define}
#ifdef __cplusplus
extern "C" {{
#endif

int {name}_ik(const double T[16], {arg}double q[][{up}_IK_DOF]);
void {name}_fk(const double q[{up}_IK_DOF], double T[16]);

#ifdef __cplusplus
}}
#endif

#endif
"""


def chain_constants(arm: ArmModel) -> str:
    """The limits ``LO``, ``HI`` and their middle ``MID`` (rad)."""
    lines = [
        f"static const double LO[DOF] = {c_source.array(arm.lower)};",
        f"static const double HI[DOF] = {c_source.array(arm.upper)};",
        f"static const double MID[DOF] = {c_source.array(arm.middle)};",
    ]
    return "\n".join(lines)


PUT = r"""
/* Row n of the candidates: each angle wrapped into (-pi, pi], with its cosine and sine
   (the verdict's forward kinematics reads them: no sine or cosine computed twice). */
static inline IK_UNUSED int put_row(double W[][DOF], double C[][DOF], double S[][DOF], int n,
                          const double *q, const double *c, const double *s)
{
    int j;
    for (j = 0; j < DOF; j++) {
        W[n][j] = wrap(q[j]);
        C[n][j] = c[j];
        S[n][j] = s[j];
    }
    return n + 1;
}
"""

COMMON = r"""
void @NAME@_fk(const double q[DOF], double T[16])
{
    mat3 R;
    vec3 p;
    int i;
    fk(q, &R, &p);
    for (i = 0; i < 3; i++) {
        T[4 * i] = R.m[3 * i];
        T[4 * i + 1] = R.m[3 * i + 1];
        T[4 * i + 2] = R.m[3 * i + 2];
        T[4 * i + 3] = p.v[i];
    }
    T[12] = T[13] = T[14] = 0.0;
    T[15] = 1.0;
}

/* qi shifted by a multiple of 2 pi to the value nearest ri within [lo, hi] (up to SNAP
   outside counts as on a limit; of two as near to TIE, ri + pi); qi itself when no such
   value exists (sixr.nearest_equivalents). */
static double nearest(double qi, double ri, double lo, double hi)
{
    const double two_pi = 2.0 * IK_PI;
    double near, best, c[3], d = qi - ri;
    int k, found = 0;
    if (-IK_PI <= d && d <= IK_PI + TIE && lo <= qi && qi <= hi)  /* a tie: ri + pi */
        return d <= -IK_PI + TIE && qi + two_pi <= hi ? qi + two_pi : qi;
    near = qi + two_pi * nearbyint((ri - qi) / two_pi);
    if (near - ri <= -IK_PI + TIE && near + two_pi <= hi + SNAP) near += two_pi;
    if (lo - SNAP <= near && near <= hi + SNAP) {
        best = near;
    } else {
        best = qi;
        c[0] = near - two_pi;
        c[1] = near + two_pi;
        c[2] = qi;
        for (k = 0; k < 3; k++)
            if (lo - SNAP <= c[k] && c[k] <= hi + SNAP
                && (!found || fabs(c[k] - ri) < fabs(best - ri))) {
                best = c[k];
                found = 1;
            }
        if (!found) return qi;
    }
    best = best > lo ? best : lo;
    return best < hi ? best : hi;
}

/* Whether row a (its distance to the middle ka) goes before row b (kb): nearer by more than
   TIE, or as near and smaller at the first joint, in the order of the chain the family
   solves (TIE_ORDER), where they differ by more than TIE (sixr._before). */
static int before(const double *a, double ka, const double *b, double kb)
{
    int i, j;
    if (fabs(ka - kb) > TIE) return ka < kb;
    for (i = 0; i < DOF; i++) {
        j = TIE_ORDER[i];
        if (fabs(a[j] - b[j]) > TIE) return a[j] < b[j];
    }
    return 0;
}

/* Whether row w is within DUPLICATE_TOL of one of the first count rows of q in every
   joint: the same solution (solve_all lists it once). */
static int listed(double q[][DOF], int count, const double *w)
{
    int i, j;
    for (i = 0; i < count; i++) {
        for (j = 0; j < DOF; j++)
            if (!(fabs(q[i][j] - w[j]) < DUPLICATE_TOL)) break;
        if (j == DOF) return 1;
    }
    return 0;
}

/* Whether joint values q (cosines c, sines s) reach the target (R, p) within the limits and
   the tolerances. */
static int verified(const double *q, const double *c, const double *s, mat3 R, vec3 p)
{
    mat3 A, E;
    vec3 x, w;
    double sa, ca;
    int j;
    for (j = 0; j < DOF; j++)
        if (!(LO[j] - LIMIT_TOL <= q[j] && q[j] <= HI[j] + LIMIT_TOL)) return 0;
    fk_cs(c, s, &A, &x);
    if (!(norm(sub(x, p)) <= TOL_POSITION)) return 0;
    E = mtm(A, R);  /* R_tip^T R_target: its angle is the orientation error */
    w.v[0] = E.m[7] - E.m[5];
    w.v[1] = E.m[2] - E.m[6];
    w.v[2] = E.m[3] - E.m[1];
    sa = 0.5 * norm(w);
    ca = 0.5 * (E.m[0] + E.m[4] + E.m[8] - 1.0);
    return @ORIENTATION@;
}

/* The rotation nearest R (R^T R within ROTATION_TOL of I, det R > 0): the orthogonal factor
   of R's polar decomposition, the parser's U V^T from R's SVD, by Newton's iteration
   R <- (R + R^-T) / 2, whose error squares at each step (1e-6, 5e-13, 1e-25). */
static mat3 nearest_rotation(mat3 R)
{
    mat3 F;
    double d;
    int i, step;
    for (step = 0; step < 3; step++) {
        for (i = 0; i < 3; i++) {  /* F = det(R) R^-T: the cofactors, row by row */
            const double *a = R.m + 3 * ((i + 1) % 3), *b = R.m + 3 * ((i + 2) % 3);
            F.m[3 * i] = a[1] * b[2] - a[2] * b[1];
            F.m[3 * i + 1] = a[2] * b[0] - a[0] * b[2];
            F.m[3 * i + 2] = a[0] * b[1] - a[1] * b[0];
        }
        d = R.m[0] * F.m[0] + R.m[1] * F.m[1] + R.m[2] * F.m[2];
        for (i = 0; i < 9; i++) R.m[i] = 0.5 * (R.m[i] + F.m[i] / d);
    }
    return R;
}

/* Rows 0 to n - 1 shifted by 2 pi nearest the middle, each one's distance to it in key; bit
   r of *taken set for each row not verified. Returns how many are verified. */
static int judge(int n, double W[][DOF], double C[][DOF], double S[][DOF], mat3 R, vec3 p,
                 double *key, int *taken)
{
    int r, j, kept = 0;
    for (r = 0; r < n; r++) {
        for (j = 0; j < DOF; j++)
            if (j != HELD) W[r][j] = nearest(W[r][j], MID[j], LO[j], HI[j]);
        key[r] = 0.0;
        for (j = 0; j < DOF; j++) key[r] += (W[r][j] - MID[j]) * (W[r][j] - MID[j]);
        key[r] = sqrt(key[r]);
        if (verified(W[r], C[r], S[r], R, p)) kept++;
        else *taken |= 1 << r;
    }
    return kept;
}
@SWEEP_FN@
int @NAME@_ik(const double T[16], @HELD_PARAM@double q[][DOF])
{
    double W[MAX_ROWS][DOF], C[MAX_ROWS][DOF], S[MAX_ROWS][DOF], key[MAX_ROWS], e;
    double worst = 0.0;  /* the largest entry of |R^T R - I| */
    int n, r, j, k, count = 0, taken = 0, best;
    mat3 R;
    vec3 p;
    for (j = 0; j < 12; j++)
        if (!isfinite(T[j])) return -1;
    for (j = 0; j < 4; j++)  /* the last row (0, 0, 0, 1); a NaN fails the test too */
        if (!(fabs(T[12 + j] - (j == 3 ? 1.0 : 0.0)) <= LAST_ROW_TOL)) return -1;
    for (j = 0; j < 3; j++) {
        R.m[3 * j] = T[4 * j];
        R.m[3 * j + 1] = T[4 * j + 1];
        R.m[3 * j + 2] = T[4 * j + 2];
        p.v[j] = T[4 * j + 3];
        if (!(fabs(p.v[j]) <= MAX_POSITION)) return -1;  /* a mistake, as armik refuses it */
    }
    for (j = 0; j < 3; j++)  /* R^T R = I: columns j and k, as armik's target parser */
        for (k = 0; k < 3; k++) {
            e = R.m[j] * R.m[k] + R.m[3 + j] * R.m[3 + k] + R.m[6 + j] * R.m[6 + k]
                - (j == k ? 1.0 : 0.0);
            if (!(fabs(e) <= ROTATION_TOL)) return -1;
            worst = fabs(e) > worst ? fabs(e) : worst;
        }
    e = R.m[0] * (R.m[4] * R.m[8] - R.m[5] * R.m[7])
        - R.m[1] * (R.m[3] * R.m[8] - R.m[5] * R.m[6])
        + R.m[2] * (R.m[3] * R.m[7] - R.m[4] * R.m[6]);
    if (e < 0.0) return -1;  /* determinant -1: a reflection, not a rotation */
    /* solved and verified on the nearest rotation, as the parser snaps it */
    if (worst > SNAP_ABOVE) R = nearest_rotation(R);
@HELD_CHECK@@ROWS@
    for (k = 0; k < n; k++) {  /* nearest the middle first, ties by before() */
        best = -1;
        for (r = 0; r < n; r++)
            if (!(taken & (1 << r)) && (best < 0 || before(W[r], key[r], W[best], key[best])))
                best = r;
        if (best < 0) break;
        taken |= 1 << best;
        if (listed(q, count, W[best])) continue;  /* a double root found twice: once */
        for (j = 0; j < DOF; j++) q[count][j] = W[best][j];
        count++;
    }
    return count;
}
"""


HELD_CHECK = """    if (!(LO[HELD] - LIMIT_TOL <= held && held <= HI[HELD] + LIMIT_TOL)) return -1;
    held = held > LO[HELD] ? held : LO[HELD];  /* clipped to its limits, as armik's Hold */
    held = held < HI[HELD] ? held : HI[HELD];
"""


ROWS = """    n = rows(R, p, @HELD_ARG@W, C, S);
    judge(n, W, C, S, R, p, key, &taken);"""


def _common(name: str, held: int | None, order: tuple[int, ...] = (), settle: str = "") -> str:
    """``COMMON`` for solver ``name``, with the held joint's argument when there is one and
    the sweep over a free joint when ``order`` names the free joints (``Rows.sweep``), its
    rows settled by ``settle`` when named (``Rows.settle``)."""
    text = COMMON.replace("@NAME@", name)
    if order:
        text = text.replace("@SWEEP_FN@", free_sweep.source(order, settle))
        text = text.replace("@ROWS@", free_sweep.ROWS)
    else:
        text = text.replace("@SWEEP_FN@", "").replace("@ROWS@", ROWS)
    parts = ("double held, ", HELD_CHECK, "held, ") if held is not None else ("", "", "")
    for key, value in zip(("@HELD_PARAM@", "@HELD_CHECK@", "@HELD_ARG@"), parts):
        text = text.replace(key, value)
    return text


def _orientation(tol: float) -> tuple[str, str]:
    """The verdict's orientation tolerance (its constant's line) and its test that the angle
    atan2(sa, ca) (sa >= 0) is within ``tol`` (rad): below pi / 2 as sa <= tan(tol) ca with
    ca > 0, which needs no atan2 (and is false on a NaN too)."""
    if 0.0 <= tol < 0.5 * math.pi:
        line = f"static const double TAN_ORIENTATION = {c_source.num(math.tan(tol))};"
        return (
            f"{line}  /* tan({c_source.num(tol)} rad) */",
            "ca > 0.0 && sa <= TAN_ORIENTATION * ca",
        )
    line = f"static const double TOL_ORIENTATION = {c_source.num(tol)};"
    return line, "atan2(sa, ca) <= TOL_ORIENTATION"


def source(name: str, arm: ArmModel, ax: Axes, rows: Rows, opts: SolverSettings) -> str:
    """``N_ik.c``: the helpers, the arm's constants, the family's rows and the rest; the
    verdict's tolerances are ``opts.tol_position`` (m) and ``opts.tol_orientation`` (rad)."""
    up = name.upper()
    orientation, test = _orientation(opts.tol_orientation)
    tie_order = range(arm.dof - 1, -1, -1) if rows.reversed else range(arm.dof)
    defines = "\n".join(
        [
            # this file's own macros, whatever the build defines (a user's -DHELD=...)
            "#undef DOF\n#undef MAX_ROWS\n#undef HELD\n#undef FREE_SWEEP",
            f"#define DOF {up}_IK_DOF",
            f"#define MAX_ROWS {rows.max_rows}",
            f"#define HELD {-1 if rows.held is None else rows.held}  /* a held joint's index */",
            f"static const double SNAP = {c_source.num(rows.snap)};",
            f"static const double TIE = {c_source.num(TIE)};  /* rad: as near, as one */",
            f"static const double DUPLICATE_TOL = {c_source.num(DUPLICATE_TOL)};  /* one */",
            f"static const int TIE_ORDER[DOF] = {{{', '.join(map(str, tie_order))}}};",
            f"#define FREE_SWEEP {FREE_SWEEP}  /* values of a free joint tried */",
            f"static const double LIMIT_TOL = {c_source.num(LIMIT_TOL)};",
            f"static const double ROTATION_TOL = {c_source.num(ROTATION_TOL)};",
            f"static const double SNAP_ABOVE = {c_source.num(ROTATION_SNAP)};  /* the parser's */",
            f"static const double LAST_ROW_TOL = {c_source.num(LAST_ROW_TOL)};",
            f"static const double MAX_POSITION = {c_source.num(MAX_POSITION)};  /* m */",
            f"static const double TOL_POSITION = {c_source.num(opts.tol_position)};",
            orientation,
        ]
    )
    where = f"from the arm {arm.name!r}, base {arm.base!r}, tip {arm.tip!r}"
    title = _comment(f"{name}_ik.c: closed-form inverse kinematics of {rows.summary}.")
    parts = [
        f"/* {title}\n   {_comment(f'Generated by armik (armik export) {where}.')}\n"
        "   Plain C99, needs only libm. */",
        "#include <math.h>\n",
        f'#include "{name}_ik.h"\n',
        defines,
        c_source.HELPERS,
        chain_constants(arm),
        fk_code.source(ax),
        PUT,
        rows.text,
        _common(name, rows.held, rows.sweep, rows.settle).replace("@ORIENTATION@", test),
    ]
    return "\n".join(parts)
