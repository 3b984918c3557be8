"""What the closed-form 6R solvers share: the compiled output layout, 2 pi equivalents,
branch labels, reasons, and the glue from the compiled kernel to ``Answers``.

A kernel computes up to 8 rows in a work array ``W`` (8, 11; 16 rows for a one-dimensional
search), ``n`` the row count: per row the joint values (columns 0-5), ``flags`` (column 6;
bit 1: least squares, the target is not reached; bit 2: singular, a free angle kept at
q0), ``code`` (column 8: which step was solved only in the least-squares sense) and 2
numbers for the reason (columns 9, 10: what the target asks, what the arm can do). ``pack``
copies them into the caller's ``out`` nearest-first and adds the branch (column 7) of the
rows handed over (``branch_bits``). The caller owns ``out``: a batch allocates it once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from armik import reasons
from armik.model.arm_model import ArmModel
from armik.model.derived import DerivedBy
from armik.model.geometry import Axes
from armik.model.mimic import reason as mimic_reason
from armik.solvers.closed_form.subproblems import (
    add,
    cross,
    dot,
    mat,
    mm,
    mv,
    norm,
    rot,
    scale,
    sub,
    vec,
    wrap,
)
from armik.status import Status
from armik.targets.pose import Target
from armik.tolerances import LIMIT_TOL

FREE_SWEEP = 64  # values of a free joint tried where q0's leaves every row outside the limits
LS = 1
SINGULAR = 2
TWO_PI = 2.0 * math.pi
# rad: a closed form's rounding (1e-12 and more), or a singular row's turn a hair inside the
# elbow's reach (``three_parallel.reach_turn``: 1e-9 and more), can put a joint that lies on
# its limit just outside it; a value this close is put on the limit (moving the tip by up to
# 1e-7 m per metre of reach, which the FK check measures as always). At 1e-9, the UR5's
# stretched wrist-singular row at 2 pi + 1.006e-9 was turned to 0 instead, and a path
# spinning wrist 3 onto its limit jumped 2 pi back.
SNAP = 1e-7
# rad: Newton steps stop at a pose error of 1e-14, which near a double root (a singular
# pose, where the error grows with the square of the step) leaves a root ~1e-7 from where it
# lies: one on a limit can come back that far past it, and more (the Panda with joint 4
# held at a pose that loses a rank: 1.4e-7). Such a row, its Jacobian near rank 5, is put
# on the limit (``general_6r.onto_limits``; the FK check measures the tip as always).
POLISHED_SNAP = 1e-6
# rad: a value within this of pi from q0's either way is a tie, which goes to q0 + pi; rows
# whose distances to q0 are this close go by the first joint (in the chain's order) whose
# values differ by more than it, the smaller first. The exported C's ``nearest`` and
# ``before`` have the same rule.
TIE = 1e-9

# Reason codes of the kernels.
SHOULDER_OFFSET = 1
TOO_FAR = 2
TOO_CLOSE = 3
WRIST_ORIENTATION = 4
ORIENTATION = 5
MISSED = 6  # a position subproblem (SP5, SP6) solved only in the least-squares sense
NOT_FOUND = 7  # a one-dimensional search found no solution


@dataclass(frozen=True)
class Chain6R:
    """A 6R chain in product-of-exponentials form for the subproblem solvers.

    With R_i = rot(h_i, q_i) and R_0i = R_1 ... R_i:
    p_tip = p[0] + R_01 p[1] + R_02 p[2] + ... + R_06 p[6],  R_tip = R_06 R_tip0.
    ``h``: (6, 3) unit axes at q = 0 in the base frame; ``p``: (7, 3) vectors between the
    chosen points on consecutive axes (the first from the base origin, the last to the tip).
    """

    kind: str  # "spherical_wrist" or "three_parallel"
    variant: str  # spherical wrist: "parallel_23" or "meeting_12"; searches: "over_q1", "over_q4"
    h: np.ndarray
    p: np.ndarray
    R_tip0: np.ndarray
    description: str


def chain_6r(kind: str, variant: str, ax: Axes, points: list[np.ndarray], text: str) -> Chain6R:
    p = np.empty((7, 3))
    p[0] = points[0]
    for i in range(1, 6):
        p[i] = points[i] - points[i - 1]
    p[6] = ax.tip_position - points[5]
    h = np.ascontiguousarray(ax.directions)
    return Chain6R(kind, variant, h, p, np.ascontiguousarray(ax.tip_rotation), text)


def not_6r(arm: ArmModel) -> str | None:
    """Why ``arm`` is not a 6R chain, or None."""
    return not_revolute(arm, 6)


def not_revolute(arm: ArmModel, dof: int) -> str | None:
    """Why ``arm`` is not a chain of ``dof`` revolute joints without mimics, or None."""
    if arm.mimics:
        return mimic_reason(arm.mimics)
    if arm.dof != dof:
        return f"the chain has {arm.dof} joints, this class needs {dof}"
    if np.any(arm.prismatic):
        names = [n for n, p in zip(arm.joint_names, arm.prismatic) if p]
        return f"joint {names[0]!r} is prismatic, this class needs {dof} revolute joints"
    return None


@njit(cache=True, no_cfunc_wrapper=True)
def put_row(W, n, q1, q2, q3, q4, q5, q6, flags, code, v0, v1):
    """Write row ``n`` of a kernel's work array ``W`` (the layout above), each angle
    wrapped into (-pi, pi]; returns n + 1."""
    W[n, 0] = wrap(q1)
    W[n, 1] = wrap(q2)
    W[n, 2] = wrap(q3)
    W[n, 3] = wrap(q4)
    W[n, 4] = wrap(q5)
    W[n, 5] = wrap(q6)
    W[n, 6] = flags
    W[n, 8] = code
    W[n, 9] = v0
    W[n, 10] = v1
    return n + 1


@njit(cache=True, no_cfunc_wrapper=True)
def elbow_code(p23, p34, h3, q3, wanted):
    """(reason code, span reached) of an elbow solved in the least-squares sense for the
    span ``wanted``: too far when it asked more than the arm's closest span, else too
    close."""
    got = norm(add(p23, mv(rot(h3, q3), p34)))
    return (TOO_FAR if wanted > got else TOO_CLOSE), got


@njit(cache=True, no_cfunc_wrapper=True)
def nearest_equivalents(Q, n, q0, lower, upper):
    """Shift every angle of the first 6 columns of the first ``n`` rows of ``Q`` by a multiple
    of 2 pi to the value nearest q0 within the limits (``ArmModel.nearest_equivalent``, compiled;
    up to ``SNAP`` outside a limit counts as on it; of two as near to ``TIE``, q0 + pi, not
    q0 - pi); a joint with no such value keeps its value."""
    for r in range(n):
        for j in range(6):
            qi, ri, lo, hi = Q[r, j], q0[j], lower[j], upper[j]
            d = qi - ri
            if -math.pi <= d <= math.pi + TIE and lo <= qi <= hi:
                if d <= -math.pi + TIE and qi + TWO_PI <= hi:  # a tie: ri + pi, as wrap's
                    Q[r, j] = qi + TWO_PI
                continue
            near = qi + TWO_PI * round((ri - qi) / TWO_PI)  # the nearest of all
            if near - ri <= -math.pi + TIE and near + TWO_PI <= hi + SNAP:  # a tie
                near += TWO_PI
            if lo - SNAP <= near <= hi + SNAP:
                Q[r, j] = min(max(near, lo), hi)
                continue
            best = math.nan
            for c in (near - TWO_PI, near + TWO_PI, qi):
                if lo - SNAP <= c <= hi + SNAP:
                    if math.isnan(best) or abs(c - ri) < abs(best - ri):
                        best = c
            if not math.isnan(best):
                Q[r, j] = min(max(best, lo), hi)


@njit(cache=True, no_cfunc_wrapper=True)
def onto_limits(Q, r, lower, upper, put):
    """Whether a joint of row ``r`` of ``Q`` lies up to ``POLISHED_SNAP`` past a limit; with
    ``put``, each such joint is put on it (Newton-polished rows, after nearest_equivalents)."""
    past = False
    for j in range(6):
        v, lo, hi = Q[r, j], lower[j], upper[j]
        if lo - POLISHED_SNAP <= v < lo or hi < v <= hi + POLISHED_SNAP:
            past = True
            if put:
                Q[r, j] = min(max(v, lo), hi)
    return past


@njit(cache=True, no_cfunc_wrapper=True)
def forward(h, p, R_tip0, q):
    """The chain's own forward kinematics (product of exponentials): the tip's rotation
    (9-tuple, row-major) and position (3-tuple). The kernels do not call it (Pinocchio
    verifies their answers); tests/model/test_geometry.py checks a ``Chain6R`` with it."""
    R = rot(vec(h[0]), q[0])
    pos = add(vec(p[0]), mv(R, vec(p[1])))
    for i in range(1, 6):
        R = mm(R, rot(vec(h[i]), q[i]))
        pos = add(pos, mv(R, vec(p[i + 1])))
    return mm(R, mat(R_tip0)), pos


@njit(cache=True, no_cfunc_wrapper=True)
def branch_bits(h, p, q):
    """The branch of configuration ``q``, read from its geometry (bits: 1 shoulder back,
    2 elbow down, 4 wrist flipped), so that a label means the same pose on every target.

    Shoulder S (a point on axis 2), elbow E (on axis 3), wrist W (on axis 4: the wrist
    centre of a spherical wrist), P on axis 5 (the wrist centre, or where axes 5 and 6
    meet). Shoulder "front" when P lies ahead of the arm, along (rot(h1, q1) h2) x h1, as
    it does at q = 0; elbow "up" when E lies on the side of the line S-W that axis 1
    points to (in the plane across axis 3; when axes 2 and 3 are not parallel: when the
    forearm is bent positively about axis 3);
    wrist "no-flip" when axis 6 turns from axis 4 about axis 5 in the positive sense,
    h5 . (h4 x rot(h5, q5) h6) > 0: the two sides of the wrist singularity."""
    h1, h2, h3 = vec(h[0]), vec(h[1]), vec(h[2])
    h4, h5, h6 = vec(h[3]), vec(h[4]), vec(h[5])
    p0, p1, p2, p3 = vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3])
    R1 = rot(h1, q[0])
    R12 = mm(R1, rot(h2, q[1]))
    S = add(p0, mv(R1, p1))
    E = add(S, mv(R12, p2))
    R123 = mm(R12, rot(h3, q[2]))
    W = add(E, mv(R123, p3))
    P = add(W, mv(mm(R123, rot(h4, q[3])), vec(p[4])))  # on axis 5 (W: spherical wrist)
    bits = 0
    ahead0 = dot(cross(h2, h1), add(add(p1, p2), add(p3, vec(p[4]))))
    ahead = dot(cross(mv(R1, h2), h1), sub(P, p0))
    if ahead * ahead0 < 0.0:
        bits |= 1
    if norm(cross(h2, h3)) < 1e-9:  # both elbow branches in one plane, across axis 3
        k = mv(R12, h3)  # axis 3, turned
        a = sub(E, S)
        a = sub(a, scale(k, dot(k, a)))
        b = sub(W, S)
        b = sub(b, scale(k, dot(k, b)))
        nb = norm(b)
        if nb > 0.0:
            b = scale(b, 1.0 / nb)
            a = sub(a, scale(b, dot(a, b)))
        down = dot(a, h1) < 0.0
    else:  # the elbow bent one way or the other about axis 3
        down = dot(h3, cross(p2, mv(rot(h3, q[2]), p3))) < 0.0
    if down:
        bits |= 2
    if dot(h5, cross(h4, mv(rot(h5, q[4]), h6))) < 0.0:
        bits |= 4
    return bits


@njit(cache=True, no_cfunc_wrapper=True)
def _inside(W, r, lower, upper):
    for j in range(6):
        if not lower[j] - LIMIT_TOL <= W[r, j] <= upper[j] + LIMIT_TOL:
            return False
    return True


@njit(cache=True, no_cfunc_wrapper=True)
def _before(W, r, b):
    """Whether row r of ``W`` goes before row b: a key (column 7) smaller by more than
    ``TIE``, or one as small and the smaller value at the first joint where they differ by
    more than ``TIE`` (a sum's rounding, or the C's, does not decide a tie)."""
    if abs(W[r, 7] - W[b, 7]) > TIE:
        return W[r, 7] < W[b, 7]
    for j in range(6):
        if abs(W[r, j] - W[b, j]) > TIE:
            return W[r, j] < W[b, j]
    return False


@njit(cache=True, no_cfunc_wrapper=True)
def pack(W, n, q0, lower, upper, h, p, labelled, out):
    """Copy the kernel's ``n`` rows of ``W`` into ``out`` nearest-first (reached, within
    limits, distance to q0: the order ``solve`` verifies them in; ties by ``_before``);
    returns whether the first row is reached and within the limits (then it is ``solve``'s
    answer if Pinocchio verifies it). Branch labels (column 7) are read for the first
    ``labelled`` rows (every row for ``solve_all``, the first for ``solve``, none for a
    batch); the others' is 0. ``W``'s column 7 is used for the sort key."""
    for r in range(n):
        d2 = 0.0
        for j in range(6):
            d2 += (W[r, j] - q0[j]) ** 2
        outside = not _inside(W, r, lower, upper)
        W[r, 7] = math.sqrt(d2) + (1e4 if outside else 0.0) + (1e8 if int(W[r, 6]) & LS else 0.0)
    first_ok = False
    taken = 0  # bit r: row r copied
    for k in range(n):  # selection sort: at most 16 rows, no allocation
        best = np.int64(-1)  # typed: a literal -1 compiles _inside once more
        for r in range(n):
            if not taken & (1 << r) and (best < 0 or _before(W, r, best)):
                best = r
        taken |= 1 << best
        if k == 0:
            first_ok = not int(W[best, 6]) & LS and _inside(W, best, lower, upper)
        for c in range(11):
            out[k, c] = W[best, c]
        out[k, 7] = 0.0
    for k in range(min(n, labelled)):
        out[k, 7] = branch_bits(h, p, out[k, :6])
    return first_ok


LABELS = tuple(
    "/".join(
        (
            "shoulder-back" if bits & 1 else "shoulder-front",
            "elbow-down" if bits & 2 else "elbow-up",
            "wrist-flip" if bits & 4 else "wrist-no-flip",
        )
    )
    for bits in range(8)
)


def reason(code: int, val: tuple[float, float] | np.ndarray, family: str) -> str:
    a, b = float(val[0]), float(val[1])
    if code == SHOULDER_OFFSET:
        where = "wrist centre" if family == "spherical_wrist" else "wrist point"
        return (
            f"the target's {where} is {a:.6g} m from axis 1 but the shoulder offset is "
            f"{b:.6g} m: it lies inside the cylinder the arm cannot enter; q is the closest "
            "configuration"
        )
    if code in (TOO_FAR, TOO_CLOSE):
        far = code == TOO_FAR
        return (
            f"target too {'far' if far else 'close'}: the elbow must span {a:.6g} m, at "
            f"{'most' if far else 'least'} {b:.6g} m is {'reachable' if far else 'needed'}"
            f"{reasons.by_how_much(a, b, 6)}; q is the closest configuration"
        )
    if code in (WRIST_ORIENTATION, ORIENTATION):
        return (
            "the target orientation is one the arm cannot take at this position; q is the "
            "closest configuration"
        )
    if code == MISSED:
        return (
            f"target out of reach: the closest configuration found misses its wrist point "
            f"by {a:.6g} m; q is that configuration"
        )
    if code == NOT_FOUND:
        return (
            "the one-dimensional search found no solution, which does not show the target "
            "out of reach (a numeric solver may still find one); q is q0"
        )
    return "no exact solution; q is the closest configuration"


def geometry(arm: ArmModel, family: str, classify):
    """``classify(arm)``, kept per arm: a ``Chain6R`` (``swept_7r``: a ``Swept``) or why not."""
    return _GEOMETRY(arm, (family, classify))


def flat(arm: ArmModel, family: str, classify) -> np.ndarray:
    """The family's chain and the arm's limits in one float array, kept per arm: h (18), p
    (21), R_tip0 (9), lower (6), upper (6), variant (1 for ``spherical_wrist``'s meeting
    axes 1, 2 and ``search_zeros.OVER_Q4``, else 0): one array argument on every path
    (views by ``unflatten``), one dispatch and one set of compiled argument types."""
    return _FLAT(arm, (family, classify))


def _flat_of(arm: ArmModel, key: tuple) -> np.ndarray:
    geo = geometry(arm, *key)
    variant = 1.0 if geo.variant in ("meeting_12", "over_q4") else 0.0
    parts = [geo.h, geo.p, geo.R_tip0, arm.lower, arm.upper, [variant]]
    return np.concatenate([np.ravel(np.asarray(x, dtype=float)) for x in parts])


_GEOMETRY = DerivedBy("6R geometry", lambda arm, key: key[1](arm))  # key: (family, classify)
_FLAT = DerivedBy("6R flat chain", _flat_of)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def unflatten(flat):
    """(h, p, R_tip0, lower, upper, variant) of a ``flat`` array, as views (called from
    Python too, as ``unflatten.py_func``)."""
    return (
        flat[0:18].reshape((6, 3)),
        flat[18:39].reshape((7, 3)),
        flat[39:48].reshape((3, 3)),
        flat[48:54],
        flat[54:60],
        int(flat[60]),
    )


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def hand_over(n, reached, labelled, h, p, out):
    """(n, head) for a kernel's packed rows in ``out`` (``pack``, the first ``labelled``
    with their branch); head: the first row's branch bits, + 8 when singular, -1 unless it
    is reached within the limits (so that ``solve`` reads no numpy scalar for the common
    answer). When it is not, every row goes to the general verdict: the rows left
    unlabelled are labelled here."""
    if not reached:
        for r in range(labelled, n):
            out[r, 7] = branch_bits(h, p, out[r, :6])
        return n, -1
    return n, int(out[0, 7]) + (8 if int(out[0, 6]) & SINGULAR else 0)


def applies(arm: ArmModel, target: Target | None, family: str, classify) -> str | None:
    """Why the family does not solve this arm and target, or None; what the options ask
    beyond an exact pose the registry refuses (``SolverSpec.solves``: nothing)."""
    geo = geometry(arm, family, classify)
    if isinstance(geo, str):
        return geo
    if target is not None and target.rotation is None:
        return "a position target leaves the orientation free; the closed form needs a full pose"
    return None


def pose_arrays(target: Target) -> tuple[np.ndarray, np.ndarray]:
    c = np.ascontiguousarray
    return c(target.rotation, dtype=float), c(target.position, dtype=float)


@njit(cache=True, nogil=True, no_cfunc_wrapper=True)
def column(H):
    """The position column of the 4x4 ``H``, a 3-tuple."""
    return (H[0, 3], H[1, 3], H[2, 3])


CONVERGED_CODE = Status.CONVERGED.code
UNREACHABLE_CODE = Status.UNREACHABLE.code
NOT_CONVERGED_CODE = Status.NOT_CONVERGED.code
