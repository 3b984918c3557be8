"""7R arms by one swept joint: joint 7 held, joints 1 to 6 in closed form.

Held at theta, joint 7 turns the tip about its axis, so joints 1-6 (with the tip at its
q = 0 pose M0, a geometry that does not change with theta) must reach
T6 = T_target G(theta), G(theta) the turn by -theta about joint 7's axis line in the tip
frame. Read from the tip back to the base, joints 6, 5, ..., 1 form a 6R chain that reaches
T6^-1 (joint j becomes joint 7 - j, its axis negated, its angle the same). When that chain
is in the spherical-wrist class (its last three axes meet: joints 3, 2, 1, a spherical
shoulder; and its first two meet: joints 6 and 5), as on the Franka Panda, its closed form
(``spherical.kernel``) gives every branch exactly.

``solve`` holds joint 7 at q0's value first, then at ``SWEEP`` values over its range,
nearest q0's first, and stops at the first value with an exact answer within the limits:
the answer keeps joint 7 as near q0 as the target allows. Where none is, an interval
narrower than the values' spacing is sought where the branches' limit violation dips
between them (``_narrow``). ``solve_all`` returns every
branch of that value of joint 7 (a redundant arm has infinitely many solutions: these are
the ones with joint 7 there). Every answer is verified by Pinocchio FK as always. Not
chosen by ``solver="auto"``; ask for it with ``solver="swept"``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import cast

import numpy as np
from numba import njit

from armik.kernel.measure import split_pose
from armik.kernel.single import plain_pose, plain_seed
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers
from armik.solvers.claims import claim
from armik.solvers.closed_form import sixr, sixr_answers
from armik.solvers.closed_form import spherical_wrist as spherical
from armik.solvers.closed_form import subproblems as sp
from armik.solvers.closed_form.line_split import split_at
from armik.solvers.closed_form.subproblems import mat, rot, vec
from armik.solvers.closed_form.swept_dips import DIP_STEPS as DIP_STEPS
from armik.solvers.closed_form.swept_dips import narrow
from armik.solvers.closed_form.swept_geometry import Swept as Swept
from armik.solvers.closed_form.swept_geometry import classify as classify
from armik.solvers.registry import SolverSpec, Sweep, register
from armik.status import Status
from armik.targets.pose import Target
from armik.tolerances import ANGLE_TOL, LIMIT_TOL

SWEEP = 128  # values of joint 7 tried after q0's, spread over its range
FAMILY = "swept_7r"


def geometry(arm: ArmModel) -> Swept | str:
    return sixr.geometry(arm, FAMILY, classify)


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    return sixr.applies(arm, target, FAMILY, classify)


def sweep_range(arm: ArmModel, q7: float) -> tuple[float, float]:
    """The range joint 7 is swept over: its limits ([q7 - pi, q7 + pi] when it has none)."""
    lo, hi = float(arm.lower[6]), float(arm.upper[6])
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return q7 - math.pi, q7 + math.pi
    return lo, hi


@njit(cache=True, no_cfunc_wrapper=True)
def sweep_values(q7, lo, hi):
    """The values of joint 7 tried, in order: q7, then the ``SWEEP`` cell centres of
    [lo, hi], nearest q7 first (taken alternately from either side of q7's cell)."""
    out = np.empty(SWEEP + 1)
    out[0] = q7
    width = (hi - lo) / SWEEP
    left = min(max(int((q7 - lo) / width), 0), SWEEP - 1)  # q7's cell: the nearest centre
    right = left + 1
    for k in range(1, SWEEP + 1):
        if right >= SWEEP or (
            left >= 0 and q7 - (lo + (left + 0.5) * width) <= lo + (right + 0.5) * width - q7
        ):
            out[k] = lo + (left + 0.5) * width
            left -= 1
        else:
            out[k] = lo + (right + 0.5) * width
            right += 1
    return out


@njit(cache=True, no_cfunc_wrapper=True)
def held_target(c, u, R, pos, theta):
    """The target of the reversed chain with joint 7 at ``theta``: T6^-1, T6 = T_target
    G(theta), G the turn by -theta about the line through ``c`` along ``u`` (tip frame)."""
    Rg = mat_array(rot(vec(u), -theta))
    R6 = R @ Rg
    p6 = R @ (c - Rg @ c) + pos
    R_inv = np.ascontiguousarray(R6.T)
    return R_inv, -(R_inv @ p6)


@njit(cache=True, no_cfunc_wrapper=True)
def mat_array(M):
    """A 9-tuple (row-major) as a 3x3 array."""
    A = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            A[i, j] = M[3 * i + j]
    return A


@njit(cache=True, no_cfunc_wrapper=True)
def first_held(h, p, R_tip0, variant, c, u, R, pos, q0r, lower, upper, q7, lo, hi):
    """The first value of joint 7 (``sweep_values``) at which joints 6 to 1 (reversed: ``q0r``,
    ``lower``, ``upper`` in their order) reach the target exactly within their limits: that
    value and its rows (``sixr.pack``'s, nearest q0 first); (q7, its rows, False) when no
    value does."""
    first = np.empty((8, 11))  # the rows at q7
    out = np.empty((8, 11))  # the rows at the other values
    n_first = 0
    thetas = sweep_values(q7, lo, hi)
    unlabelled = np.int64(0)  # rows' branches unused (not a literal 0: one compile of kernel)
    for k in range(thetas.shape[0]):
        theta = thetas[k]
        R_inv, p_inv = held_target(c, u, R, pos, theta)
        rows = first if k == 0 else out
        n, _ = spherical.kernel(
            h, p, R_tip0, mat(R_inv), vec(p_inv), q0r, lower, upper, variant, unlabelled, rows
        )
        n = in_line(h, p, q0r, lower, upper, unlabelled, rows, n)
        if k == 0:
            n_first = n
        if n > 0 and not int(rows[0, 6]) & sixr.LS:
            inside = True  # row 0 is within the limits if any exact row is (pack's order)
            for j in range(6):
                if not lower[j] - sixr.LIMIT_TOL <= rows[0, j] <= upper[j] + sixr.LIMIT_TOL:
                    inside = False
            if inside:
                return theta, rows[:n], True
    return q7, first[:n_first], False


# sin of the angle between two axes, and m between their lines: in line (the structure's
# tolerance); up to ``sp2``'s SINGLE its split of the two is noise (rounding's square root)
IN_LINE = ANGLE_TOL


@njit(cache=True, no_cfunc_wrapper=True)
def in_line(h, p, q0, lower, upper, labelled, out, n):
    """The kernel's ``n`` rows of the reversed chain (``h``, ``p``) in ``out`` where two axes
    one joint apart lie in one line (the Panda's joints 3 and 5 at joint 4 = 0): only their
    sum turns the tip, split by the closed form's rounding (``IN_LINE``; near it by noise,
    ``SINGLE``: a row it leaves outside the limits). The first (in the reversed chain's
    order) is kept at q0's value, or the nearest that keeps both within their limits, the
    other takes the rest, the row singular; the rows packed again (``sixr.pack``), a row the
    same as one before it dropped. Returns the count. A row the kernel calls singular is
    split too (the iiwa's stretched elbow is at joint 4 = 0); axes 4 and 6 are its wrist."""
    moved = False
    for r in range(n):
        if int(out[r, 6]) & sixr.LS:
            continue  # not reached: no split makes it so
        for i in range(3):  # axes (1, 3), (2, 4), (3, 5); (4, 6) is the kernel's wrist
            j = i + 2  # their angle turns with joint i + 1 alone: read cheaply first
            turned = sp.mv(rot(vec(h[i + 1]), out[r, i + 1]), vec(h[j]))
            if sp.norm(sp.cross(vec(h[i]), turned)) > sp.SINGLE:
                continue
            (Pi, Di), (Pj, Dj), T = _line(h, p, out[r], i), _line(h, p, out[r], j), LIMIT_TOL
            c, far = sp.norm(sp.cross(Di, Dj)), sp.norm(sp.cross(sp.sub(Pj, Pi), Di))
            outside = not lower[i] - T <= out[r, i] <= upper[i] + T
            outside = outside or not lower[j] - T <= out[r, j] <= upper[j] + T
            if c > sp.SINGLE or far > sp.SINGLE or not outside and (c > IN_LINE or far > IN_LINE):
                continue
            s = 1.0 if sp.dot(Di, Dj) > 0.0 else -1.0
            t = split_at(out[r, i], out[r, j], s, q0[i], lower, upper, i, j)
            out[r, j] = out[r, j] + s * (out[r, i] - t)
            out[r, i] = t
            out[r, 6] = float(int(out[r, 6]) | sixr.SINGULAR)
            moved = True
    if not moved:
        return n
    sixr.nearest_equivalents(out, n, q0, lower, upper)
    W = out[:n].copy()
    sixr.pack(W, n, q0, lower, upper, h, p, labelled, out)
    m = 0
    for r in range(n):
        same = False
        for k in range(m):
            gap = 0.0
            for col in range(6):
                gap = max(gap, abs(out[r, col] - out[k, col]))
            same = same or (gap <= 1e-9 and out[r, 6] == out[k, 6])
        if not same:
            for col in range(out.shape[1]):  # a loop: no shape-mismatch error to compile
                out[m, col] = out[r, col]
            m += 1
    return m


@njit(cache=True, no_cfunc_wrapper=True)
def _line(h, p, q, k):
    """A point on and the direction of the chain's axis ``k`` at ``q``."""
    R, o = rot(vec(h[0]), 0.0), vec(p[0])
    for m in range(k):
        R = sp.mm(R, rot(vec(h[m]), q[m]))
        o = sp.add(o, sp.mv(R, vec(p[m + 1])))
    return o, sp.mv(R, vec(h[k]))


def held_reason(theta: float, singular: bool) -> str:
    text = f"closed form with joint 7 held at {theta:.6g} rad (joints 6 to 1 as a spherical wrist)"
    return sixr_answers.claim_reason(text, singular)


def _answers(
    sw: Swept, rows: np.ndarray, theta: float, swept: bool = True, beyond: str | None = None
) -> Answers:
    """The answers of ``rows``; ``swept``: joint 7 took a few values of its range, so a
    row the closed form could not reach shows nothing about the values not tried (not
    converged) unless the target lies beyond the reach bound (``beyond``:
    ``sixr_answers.beyond_reach``'s reason); held at one value (``hold=``), the closed form's
    verdict is a proof."""
    claims, texts, flags_of = [], [], []
    held: dict[bool, str] = {}  # a claim's words by its singular flag: the same for every row
    for row in rows:
        flags = int(row[7])
        singular = bool(flags & sixr.SINGULAR)
        if flags & sixr.LS:
            reason = sixr.reason(int(row[9]), row[10:12], spherical.FAMILY)
            claim = Status.UNREACHABLE
            if swept and beyond is not None:
                reason = f"{beyond}; joint 7 at {theta:.6g} rad: {reason}"
            elif swept:
                claim = Status.NOT_CONVERGED
                reason = (
                    f"no value of joint 7 swept gave an exact solution; at {theta:.6g} rad: "
                    f"{reason}"
                )
            else:  # held: out of reach with joint 7 there, not beyond the arm's reach
                reason = f"with joint 7 held at {theta:.6g} rad: {reason}"
        else:
            reason = held.get(singular) or held.setdefault(singular, held_reason(theta, singular))
            claim = Status.CONVERGED
        claims.append(claim)
        texts.append(reason)
        flags_of.append(singular)
    h, p = sw.geo.h, sw.geo.p  # each row's ``branch``, inline: one call for the rows
    labels = [_HELD_LABELS[sixr.branch_bits(h, p, row[5::-1].copy())] for row in rows]
    Q = np.asarray(rows, dtype=float)[:, :7]
    return Answers.of(Q, claims, texts, 7, branch=labels, singular=flags_of)


# The 6R chain the closed form solves is joints 6 to 1 read from the tip: its "shoulder"
# is the arm's wrist (joints 6, 5, 4) and its "wrist" the arm's shoulder (joints 3, 2, 1).
_HELD_LABELS = tuple(
    "/".join(
        (
            "wrist-back" if bits & 1 else "wrist-front",
            "elbow-down" if bits & 2 else "elbow-up",
            "shoulder-flip" if bits & 4 else "shoulder-no-flip",
        )
    )
    for bits in range(8)
)


def branch(sw: Swept, q: np.ndarray) -> str:
    """The branch of a 7R answer ``q`` with joint 7 held: the closed form's label of its
    joints 6 to 1, named after the arm's own wrist, elbow and shoulder."""
    reversed_q = np.ascontiguousarray(q[5::-1], dtype=float)
    return _HELD_LABELS[sixr.branch_bits(sw.geo.h, sw.geo.p, reversed_q)]


@njit(cache=True, no_cfunc_wrapper=True)
def held_rows(h, p, R_tip0, variant, c, u, R, pos, q0, lower, upper, lo7, hi7):
    """``first_held`` on the 7R chain's own joint order: (theta, rows (n, 12): q (7), flags,
    branch, code, values, found)."""
    q0r, lor, hir = np.empty(6), np.empty(6), np.empty(6)
    for j in range(6):
        q0r[j], lor[j], hir[j] = q0[5 - j], lower[5 - j], upper[5 - j]
    theta, out, found = first_held(
        h, p, R_tip0, variant, c, u, R, pos, q0r, lor, hir, q0[6], lo7, hi7
    )
    rows = np.empty((out.shape[0], 12))
    for r in range(out.shape[0]):
        for j in range(6):
            rows[r, j] = out[r, 5 - j]  # joints 1 to 6 again
        rows[r, 6] = theta
        for j in range(5):
            rows[r, 7 + j] = out[r, 6 + j]
    return theta, rows, found


def _held(arm: ArmModel, sw, R, pos, q0: np.ndarray):
    lo7, hi7 = sweep_range(arm, float(q0[6]))
    return held_rows(
        sw.geo.h, sw.geo.p, sw.geo.R_tip0, sw.variant, sw.c, sw.u, R, pos, q0,
        np.ascontiguousarray(arm.lower, dtype=float), np.ascontiguousarray(arm.upper, dtype=float),
        lo7, hi7,
    )  # fmt: skip


def at_value(arm: ArmModel, target: Target, q0: np.ndarray, theta: float) -> Answers:
    """Every branch with joint 7 held at exactly ``theta`` (rad), nearest q0 first: joints
    6 to 1 by the spherical closed form, no sweep (``hold=`` on joint 7; ``applies`` must
    hold)."""
    sw = cast(Swept, geometry(arm))  # ``applies`` holds: the geometry, no reason
    return _answers(sw, _rows_at(sw, target, q0, arm)(theta), theta, swept=False)


def exact_at(arm: ArmModel, target: Target, q0: np.ndarray) -> Callable[[float], np.ndarray]:
    """For a search over joint 7: a function of its value giving the configurations
    ``at_value`` claims there (the exact rows, nearest q0 first), without their words: one
    kernel call a value (``applies`` must hold)."""
    sw = cast(Swept, geometry(arm))
    rows_at = _rows_at(sw, target, q0, arm)

    def exact(theta: float) -> np.ndarray:
        rows = rows_at(theta)
        return rows[(rows[:, 7].astype(np.int64) & sixr.LS) == 0, :7]

    labelled_at = _rows_at(sw, target, q0, arm, _EVERY_LABEL)

    def branches(theta: float) -> tuple[np.ndarray, list[int]]:
        """``exact``'s configurations and each one's branch (``sixr.branch_bits`` of joints
        6 to 1, read by the kernel): a branch moves continuously with joint 7, so a search
        can follow each one."""
        rows = labelled_at(theta)
        exact = (rows[:, 7].astype(np.int64) & sixr.LS) == 0
        return rows[exact, :7], rows[exact, 8].astype(np.int64).tolist()

    exact.branches = branches  # type: ignore[attr-defined]
    return exact


_NO_LABEL = np.int64(0)  # the kernel labels no row (typed, as every count it takes: one compile)
_EVERY_LABEL = np.int64(8)  # the kernel labels every row with its branch


def _rows_at(
    sw: Swept, target: Target, q0: np.ndarray, arm: ArmModel, labelled: np.int64 = _NO_LABEL
):
    """theta -> the closed form's rows (n, 12) with joint 7 at theta: q (7), flags, branch
    (read for the first ``labelled`` rows, else 0), code, values; the target's arrays and
    the reversed chain's read once."""
    R, pos = sixr.pose_arrays(target)
    return _rows_at_pose(sw, R, pos, q0, arm, labelled)


def _rows_at_pose(sw: Swept, R, pos, q0: np.ndarray, arm: ArmModel, labelled: np.int64 = _NO_LABEL):
    """``_rows_at`` of the target's rotation ``R`` and position ``pos``."""
    R, pos = np.array(R), np.array(pos)  # writable: one signature
    q0r = np.array(q0[5::-1], dtype=float)  # the reversed chain's order
    lor = np.array(arm.lower[5::-1], dtype=float)
    hir = np.array(arm.upper[5::-1], dtype=float)
    out = np.empty((8, 11))

    def rows_at(theta: float) -> np.ndarray:
        R_inv, p_inv = held_target(sw.c, sw.u, R, pos, float(theta))
        n, _ = spherical.kernel(
            sw.geo.h, sw.geo.p, sw.geo.R_tip0, mat(R_inv), vec(p_inv), q0r, lor, hir,
            sw.variant, labelled, out,
        )  # fmt: skip
        n = in_line(sw.geo.h, sw.geo.p, q0r, lor, hir, labelled, out, n)
        rows = np.empty((n, 12))
        rows[:, :6] = out[:n, 5::-1]  # joints 1 to 6 again
        rows[:, 6] = theta
        rows[:, 7:] = out[:n, 6:11]
        return rows

    return rows_at


GOLDEN = 0.6180339887498949


def golden_search(
    a: float, b: float, steps: int, tried: list[tuple[float, float]], until: float = -math.inf
) -> Iterator[float]:
    """The values a golden-section search for the least of a function on [a, b] tries
    (``steps`` after its first two), each read back as ``tried[-1]`` ((value, x), which
    its caller appends); it stops once one is ``until``, after its first two. The caller
    evaluates the function, so that the search calls none of a module above it."""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    yield c
    fc = tried[-1][0]
    yield d
    fd = tried[-1][0]
    for _ in range(steps):
        if min(fc, fd) <= until:
            return
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            yield c
            fc = tried[-1][0]
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            yield d
            fd = tried[-1][0]


def _narrow(arm: ArmModel, sw: Swept, R, pos, q0: np.ndarray):
    """Where no swept value of joint 7 gave a row within the limits: (theta, rows, True) at
    a value where one is, in an interval narrower than the sweep's cells, else None: the
    dips of the exact rows' least limit violation searched (``swept_dips.narrow``)."""
    lo7, hi7 = sweep_range(arm, float(q0[6]))
    rows_at = _rows_at_pose(sw, R, pos, q0, arm)
    near = float(q0[6])
    theta = narrow(rows_at, lo7, hi7, arm.lower, arm.upper, SWEEP, near, golden_search)
    return None if theta is None else (theta, rows_at(theta), True)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    R, pos = sixr.pose_arrays(target)
    sw = cast(Swept, geometry(arm))  # ``applies`` holds: the geometry, no reason
    q0 = np.ascontiguousarray(q0, float)
    theta, rows, found = _held(arm, sw, R, pos, q0)
    if not found:  # a narrow interval of joint 7 the sweep's cells stepped over
        theta, rows, found = _narrow(arm, sw, R, pos, q0) or (theta, rows, found)
    if all_solutions:
        exact = [r for r in rows if not int(r[7]) & sixr.LS]
        rows = np.array(exact) if exact and found else rows
    rows = rows if all_solutions else rows[:1]
    return _answers(sw, rows, theta, True, _beyond(arm, pos, rows))


def _beyond(arm: ArmModel, position, rows: np.ndarray) -> str | None:
    """``sixr_answers.beyond_reach`` where a row is not reached (the reason is then needed)."""
    if all(not int(r[7]) & sixr.LS for r in rows):
        return None
    return sixr_answers.beyond_reach(arm, position)


def prepare_pose(arm: ArmModel, opts: SolverSettings, position_only: bool):
    """``run_pose`` for ``armik.solve.prepared`` (see
    ``armik.solvers.numeric.driver.pose_runner``); position_only is always False
    (``applies`` refuses position targets), ``solve_all`` takes the general path."""
    sw = cast(Swept, geometry(arm))  # ``applies`` holds: the geometry, no reason
    lower = np.ascontiguousarray(arm.lower, dtype=float)
    upper = np.ascontiguousarray(arm.upper, dtype=float)

    def run_pose(H: np.ndarray, q0: np.ndarray, seed: int, every: bool = False):
        if every or not plain_pose(H) or not plain_seed(q0, lower, upper):
            return None
        R, pos = split_pose(H)
        theta, rows, found = _held(arm, sw, R, pos, q0)
        if not found:  # a narrow interval of joint 7 the sweep's cells stepped over
            theta, rows, found = _narrow(arm, sw, R, pos, q0) or (theta, rows, found)
        if not found:
            return _answers(sw, rows[:1], theta, True, _beyond(arm, pos, rows[:1]))
        singular = bool(int(rows[0, 7]) & sixr.SINGULAR)
        q = rows[0, :7]
        return claim((q, 0, 0, branch(sw, q), singular, held_reason, (theta, singular)))

    return run_pose


SPEC = register(
    SolverSpec(
        name="swept",
        kind="analytic",
        enforces_limits=True,
        priority=80,
        why_not=applies,
        solves=frozenset(),
        run=run,
        summary="7R arms: joint 7 held (swept from q0's value), joints 6 to 1 in closed form",
        auto=False,
        prepare_pose=prepare_pose,
        complete=False,
        sweep=Sweep(joint=6, at_value=at_value, range=sweep_range, exact=exact_at),
    )
)
