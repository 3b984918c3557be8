"""7R arms with a spherical shoulder, an elbow and a spherical wrist (SRS: the KUKA LBR
iiwa 7 and 14, and arms like them) in closed form by the elbow's swivel angle.

The class is read from the axis lines at q = 0, not from a name: axes 1, 2, 3 meet in one
point (the shoulder S), axes 5, 6, 7 in another (the wrist W), and axis 4 passes through
neither, so that bending the elbow changes the span S-W. Consecutive axes of each triple
must cross (not parallel). The target fixes W and the span |S-W|, so the elbow angle (2
roots); what is left is the elbow's turn about the line S-W, the swivel angle psi
(``srs_kernel``'s convention: 0 with the elbow on axis 1's side). At one swivel angle the
shoulder and the wrist are each three axes meeting in a point, 2 roots each: up to 8
branches, every one exact (``srs_kernel.at_swivel``).

- ``solve_all(T, swivel=psi)`` (``armik.solve.parameter``): every branch at psi.
- ``solve`` and ``solve_all`` without it: q0's swivel angle first (either side of a
  stretched or folded elbow, ``srs_kernel.sides_of``), then ``SWEEP`` more
  round the circle nearest q0's first, and the branches of the first angle with one
  within the limits. A target whose span no elbow angle makes, or only one beyond joint
  4's limits, is unreachable (a proof: no swivel angle changes the span or joint 4);
  where no angle tried keeps a branch within the limits, ``dls`` tries from q0 and its
  answer is returned, the miss in its reason.

Every answer is verified by Pinocchio FK as always. Chosen by ``solver="auto"`` on SRS
arms given a full pose.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, angle_between, axis_lines, fmt, meeting_point
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers
from armik.solvers.closed_form import sixr, sixr_answers
from armik.solvers.closed_form import srs_kernel as kernel
from armik.solvers.closed_form.subproblems import mat, vec
from armik.solvers.registry import Parameter, SolverSpec, get, register
from armik.status import Status
from armik.targets.pose import Target
from armik.tolerances import ANGLE_TOL, DISTANCE_TOL

FAMILY = "srs"
CLOSED_FORM = "closed form (SRS: spherical shoulder, elbow, spherical wrist)"


@dataclass(frozen=True)
class Srs:
    """An SRS arm's geometry at q = 0 (base frame, m): the shoulder, the wrist, the elbow
    (the point of axis 4 nearest the shoulder) and ``geo``, the kernel's flat array."""

    shoulder: np.ndarray
    wrist: np.ndarray
    elbow: np.ndarray
    geo: np.ndarray

    @property
    def description(self) -> str:
        se = float(np.linalg.norm(self.elbow - self.shoulder))
        ew = float(np.linalg.norm(self.wrist - self.elbow))
        return (
            f"axes 1-3 meet at {np.round(self.shoulder, 6).tolist()} m, axes 5-7 at "
            f"{np.round(self.wrist, 6).tolist()} m, elbow (axis 4) {se:.6g} m from the "
            f"shoulder and {ew:.6g} m from the wrist: every branch at one swivel angle"
        )


def classify(arm: ArmModel, ax: Axes | None = None) -> Srs | str:
    """The SRS geometry of ``arm`` (see the module), or the measured reason it is not one."""
    why = sixr.not_revolute(arm, 7)
    if why is not None:
        return why
    ax = ax or axis_lines(arm)
    P, H = ax.points, ax.directions
    for i, j in ((0, 1), (1, 2), (4, 5), (5, 6)):
        if angle_between(H[i], H[j]) < ANGLE_TOL:
            return f"axes {i + 1} and {j + 1} are parallel: no spherical joint there"
    S, miss_s = meeting_point(P[:3], H[:3])
    if miss_s > DISTANCE_TOL:
        return (
            f"axes 1, 2, 3 do not meet in one point (no spherical shoulder): they miss by "
            f"{fmt(miss_s)} m (tolerance {DISTANCE_TOL:g} m)"
        )
    W, miss_w = meeting_point(P[4:], H[4:])
    if miss_w > DISTANCE_TOL:
        return (
            f"axes 5, 6, 7 do not meet in one point (no spherical wrist): they miss by "
            f"{fmt(miss_w)} m (tolerance {DISTANCE_TOL:g} m)"
        )
    h4 = H[3]
    for name, X in (("shoulder", S), ("wrist", W)):
        off = X - P[3]
        if np.linalg.norm(off - (off @ h4) * h4) <= DISTANCE_TOL:
            return f"axis 4 passes through the {name}: the elbow cannot change the span"
    E = P[3] + ((S - P[3]) @ h4) * h4
    Rt = ax.tip_rotation
    parts = [
        H,
        S,
        W,
        E,
        Rt.T @ (W - ax.tip_position),
        Rt,
        arm.lower,
        arm.upper,
        H[0],
    ]
    geo = np.concatenate([np.ravel(np.asarray(x, dtype=float)) for x in parts])
    return Srs(S, W, E, geo)


def geometry(arm: ArmModel) -> Srs | str:
    return cast("Srs | str", sixr.geometry(arm, FAMILY, classify))


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    return sixr.applies(arm, target, FAMILY, classify)


def swivel_of(arm: ArmModel, q) -> float:
    """The swivel angle (rad) of configuration ``q`` of an SRS arm (``srs_kernel``'s
    convention); ``ValueError`` on an arm that is not one."""
    geo = geometry(arm)
    if isinstance(geo, str):
        raise ValueError(f"arm {arm.name!r} is not an SRS arm: {geo}")
    return float(kernel.swivel_of(geo.geo, np.ascontiguousarray(q, dtype=float)))


LABELS = tuple(
    "/".join(
        f"{part}-{'neg' if bits & (1 << k) else 'pos'}"
        for k, part in enumerate(("shoulder", "elbow", "wrist"))
    )
    for bits in range(8)
)


def _rows(arm: ArmModel, target: Target, q0: np.ndarray, psi: float | None):
    """(psi, rows (n, ``COLUMNS``), found): at ``psi``, or swept from q0's (None)."""
    geo = cast(Srs, geometry(arm)).geo
    R, pos = sixr.pose_arrays(target)
    q0 = np.ascontiguousarray(q0, dtype=float)
    out = np.empty((kernel.ROWS, kernel.COLUMNS))
    if psi is None:
        psi, n, found = kernel.swept(geo, mat(R), vec(pos), q0, out)
    else:
        n, found = kernel.solve_at(geo, mat(R), vec(pos), float(psi), q0, out)
    return float(psi), out[:n], found


def said(psi: float, swept: bool, row: np.ndarray, beyond) -> tuple[Status, str]:
    """The claim and words of one row at swivel angle ``psi``: a proof at one angle, and
    when ``swept`` for the span only (the other reasons may change with the angle)."""
    at = f"swivel angle {psi:.6g} rad"
    flags, code = int(row[7]), int(row[9])
    if not flags & sixr.LS:
        return Status.CONVERGED, sixr_answers.claim_reason(
            f"{CLOSED_FORM} at {at}", bool(flags & sixr.SINGULAR)
        )
    text = sixr.reason(code, row[10:12], "spherical_wrist")
    if code in (sixr.TOO_FAR, sixr.TOO_CLOSE):
        why = beyond()
        text = text.replace("the elbow must span", "the shoulder to wrist span is")
        return Status.UNREACHABLE, text if why is None else f"{why}; {text}"
    if swept:
        return Status.NOT_CONVERGED, f"at {at} (q0's): {text}"
    return Status.UNREACHABLE, f"at {at}: {text}"


def answers(arm: ArmModel, rows: np.ndarray, psi: float, swept: bool, position) -> Answers:
    """The ``Answers`` of the kernel's ``rows`` at swivel angle ``psi``."""

    def beyond():
        return sixr_answers.beyond_reach(arm, position)

    words = [said(psi, swept, row, beyond) for row in rows]
    q = rows[:, :7].copy()
    missed = np.array([w[0] is not Status.CONVERGED for w in words], dtype=bool)
    if missed.any():  # a failure's closest configuration, within the limits
        q[missed] = np.clip(q[missed], arm.lower, arm.upper)
    return Answers.of(
        q,
        [w[0] for w in words],
        [w[1] for w in words],
        7,
        branch=[LABELS[int(r[8])] for r in rows],
        singular=[bool(int(r[7]) & sixr.SINGULAR) for r in rows],
    )


def at_swivel(arm: ArmModel, target: Target, q0: np.ndarray, psi: float) -> Answers:
    """Every branch at swivel angle ``psi`` (rad), nearest q0 first (``applies`` must
    hold): what ``solve_all(T, swivel=psi)`` verifies."""
    _, rows, _ = _rows(arm, target, q0, psi)
    return answers(arm, rows, psi, False, target.position)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    psi, rows, found = _rows(arm, target, q0, None)
    reached = len(rows) > 0 and not int(rows[0, 7]) & sixr.LS
    if not found and reached:
        if not kernel.elbow_inside(rows, len(rows), arm.lower, arm.upper):
            return _elbow_limited(arm, rows, psi, all_solutions)
        return _numeric(arm, target, q0, opts, all_solutions, psi)  # another angle may do
    if found and all_solutions:
        rows = rows[[not int(r[7]) & sixr.LS for r in rows]]
    got = answers(arm, rows, psi, True, target.position)
    return got if all_solutions else got.take([0])


def _elbow_limited(arm: ArmModel, rows: np.ndarray, psi: float, all_solutions: bool) -> Answers:
    """The rows at q0's swivel angle, unreachable: joint 4's values (the same at every
    swivel angle) lie beyond its limits."""
    values = ", ".join(f"{v:.6g}" for v in sorted(set(np.round(rows[:, 3], 9))))
    name, lo, hi = arm.joint_names[3], arm.lower[3], arm.upper[3]
    text = (
        f"{CLOSED_FORM}: the elbow ({name}) must turn to {values} rad to span the shoulder "
        f"to the wrist, outside its limits [{lo:.6g}, {hi:.6g}] rad at every swivel angle; "
        f"q is a branch at swivel angle {psi:.6g} rad"
    )
    n = len(rows) if all_solutions else 1
    return Answers.of(
        rows[:n, :7],
        [Status.UNREACHABLE] * n,
        [text] * n,
        7,
        branch=[LABELS[int(r[8])] for r in rows[:n]],
        singular=[bool(int(r[7]) & sixr.SINGULAR) for r in rows[:n]],
    )


def _numeric(arm, target, q0, opts: SolverSettings, all_solutions: bool, psi: float) -> Answers:
    """``dls``'s answers from q0 where no swivel angle tried kept a branch within the
    limits, with that in their reasons."""
    found = get("dls").run(arm, target, q0, opts, all_solutions)
    miss = (
        f"{CLOSED_FORM}: no branch within the limits at q0's swivel angle ({psi:.6g} rad) "
        f"or {kernel.SWEEP - 1} more round the circle"
    )
    texts = [f"{miss}; dls: {found.reason(i)}" for i in range(len(found))]
    return Answers(
        q=found.q,
        claim=found.claim,
        iterations=found.iterations,
        restarts=found.restarts,
        branch=found.branch,
        singular=found.singular,
        reasons=tuple(texts),
    )


SPEC = register(
    SolverSpec(
        name="srs",
        kind="analytic",
        enforces_limits=True,
        priority=85,
        why_not=applies,
        solves=frozenset(),
        run=run,
        summary="7R SRS arms (KUKA iiwa): every branch (up to 8) at one elbow swivel angle "
        "(swivel=, else q0's, swept round the circle until a branch is within the limits)",
        parameter=Parameter("swivel", "an SRS arm's elbow swivel angle (rad)", at_swivel),
    )
)
