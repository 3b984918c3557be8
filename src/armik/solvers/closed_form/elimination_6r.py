"""Every solution of a 6R arm no Pieper family fits, by elimination: the classifier (which
cut of the loop to eliminate on) and the solver's registration. The algebra is in
``elimination``.

``classify`` tries the ``elimination.CUTS`` cuts on ``TRIALS`` targets made from seeded
random configurations and keeps the first ``GOOD`` one, else the one, of those that find
every trial's configuration, whose matrices are furthest from singular (a cut through parallel or
meeting axes can make M(x3) singular for every x3: the JACO 2's axes 2 and 3 rule out
most). ``run`` asks the search its arm had before (``SEARCHES``: the first that applies) too
when the elimination is not sure of a target, and adds the answers it finds that the
elimination lacks: a leading matrix no phase makes regular, eliminated products nearly
dependent, a real root that gave no new answer (two solutions about to merge); and it
answers alone where the elimination found nothing (its words then say why, as before).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, axis_lines
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers, stacked
from armik.solvers.closed_form import (
    elimination,
    elimination_roots,
    general_6r,
    sixr,
    sixr_answers,
    spherical_general,
    spherical_shoulder,
    three_parallel_general,
)
from armik.solvers.registry import SolverSpec, get, register
from armik.targets.pose import Target

FAMILY = "elimination_6r"
CLOSED_FORM = "elimination (Raghavan-Roth): every real root polished by Newton steps"
PRIORITY = 65  # above the searches it stands in front of (60, 55), below the Pieper families
SEARCHES = ("two_parallel", "two_intersecting", "general_6r")
TRIALS = 8  # seeded targets a cut must solve completely to be chosen
GOOD = 1e-3  # a cut this far from singular on every trial is taken at once
RANK = 1e-8  # the eliminated products' matrix: smallest |R_kk| over largest, at least
SEED = 53


@dataclass(frozen=True)
class Plan:
    """An arm's elimination: its chain (``sixr.Chain6R``, for the Newton steps too), the cut,
    the arm's joint at each place of the cut's loop and the loop's sense (+1 or -1)."""

    chain: sixr.Chain6R
    cut: np.int64
    places: np.ndarray
    sign: np.int64
    description: str


def plan_of(chain: sixr.Chain6R, cut: int, text: str = "") -> Plan:
    places, sign = elimination.cut_joints(cut)
    return Plan(chain, np.int64(cut), places, np.int64(sign), text)


def _rows(plan: Plan, R, pos, q0, lower, upper, out) -> tuple[int, bool, float]:
    """(n, sure, regular): the elimination's rows for one target in ``out`` (n = 0 when not
    sure before its eigenvalues); regular: how far its matrices are from singular."""
    K, state = np.empty((24, 24)), np.empty(elimination.SIZE)
    chain = plan.chain
    pivot, rank = elimination.companion(chain.h, chain.p, chain.R_tip0, R, pos, plan.cut, K, state)
    regular = min(pivot, rank)
    if pivot < elimination.REGULAR or rank < RANK:
        return 0, False, regular
    roots = np.linalg.eigvals(K)
    if not np.all(np.isfinite(roots)):
        return 0, False, regular
    args = (chain.h, chain.p, chain.R_tip0, R, pos, state, roots)
    rest = (plan.places, plan.sign, q0, lower, upper, out)
    n, sure, lost = elimination_roots.solutions(*args, elimination_roots.NO_SEEDS, *rest)
    if lost:  # a multiple root: its solutions read off M(x3)'s null space too
        seeds = elimination_roots.seeds(state, roots)
        if len(seeds):  # as sure as before: some of a multiple root's can be complex
            n, _, _ = elimination_roots.solutions(*args, seeds, *rest)
    return n, sure, regular


def _score(chain: sixr.Chain6R, cut: int, trials: list) -> float:
    """How far from singular cut ``cut`` stays over the trial targets (0: not usable)."""
    out = np.empty((elimination_roots.ROWS, 11))
    wide = np.full(6, 10.0)
    worst = np.inf
    plan = plan_of(chain, cut)
    for q, R, pos in trials:
        n, sure, regular = _rows(plan, R, pos, np.zeros(6), -wide, wide, out)
        d = np.abs(np.angle(np.exp(1j * (out[:n, :6] - q))))
        if not sure or n == 0 or not np.any(np.all(d < general_6r.SAME, axis=1)):
            return 0.0
        worst = min(worst, regular)
    return float(worst)


def classify(arm: ArmModel, ax: Axes | None = None) -> Plan | str:
    """The arm's plan (its chain and the best cut), or why the elimination does not apply."""
    why = sixr.not_6r(arm)
    if why:
        return why
    ax = ax or axis_lines(arm)
    # Pieper's: in closed form
    for family in (spherical_general, three_parallel_general, spherical_shoulder):
        if not isinstance(family.classify(arm, ax), str):
            return f"{family.FAMILY} solves this arm in closed form"
    chain = sixr.chain_6r(FAMILY, "", ax, [ax.points[i] for i in range(6)], "")
    rng = np.random.default_rng(SEED)
    trials = []
    for _ in range(TRIALS):
        q = rng.uniform(-np.pi, np.pi, 6)
        R, pos = sixr.forward(chain.h, chain.p, chain.R_tip0, q)
        trials.append((q, np.array(R).reshape(3, 3), np.array(pos)))
    scores = []
    for cut in range(elimination.CUTS):
        scores.append(_score(chain, cut, trials))
        if scores[-1] >= GOOD:  # far enough from singular: the others are not tried
            break
    best = int(np.argmax(scores))
    if scores[best] <= 0.0:
        return (
            "no cut of the loop eliminates regularly on this arm (every one left M(x3) "
            f"singular or missed a solution on {TRIALS} trial targets)"
        )
    dropped = int(elimination.cut_joints(best)[0][5]) + 1
    way = "backwards" if best >= 6 else "forwards"
    text = f"elimination with joint {dropped} dropped, the loop read {way}"
    return plan_of(chain, best, text)


def _classify(arm: ArmModel):
    return classify(arm)


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    return sixr.applies(arm, target, FAMILY, _classify)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    plan = sixr.geometry(arm, FAMILY, _classify)
    R, pos = sixr.pose_arrays(target)
    out = np.empty((elimination_roots.ROWS, 11))
    # fresh writable copies: read-only arrays (a frozen target, a result's q) are another
    # numba type and would compile the kernels again
    R, pos, q0 = np.array(R), np.array(pos), np.array(q0, dtype=float)
    lower, upper = np.array(arm.lower, dtype=float), np.array(arm.upper, dtype=float)
    n, sure, _ = _rows(plan, R, pos, q0, lower, upper, out)
    ours = general_6r.rank_lost(arm, sixr_answers.of_rows(out[:n], FAMILY, CLOSED_FORM))
    if sure and n > 0:
        return ours
    # not sure, or nothing found: the search the arm had before, and what it adds
    name = next((s for s in SEARCHES if get(s).why_not(arm, target, opts) is None), SEARCHES[-1])
    found = get(name).run(arm, target, q0, opts, all_solutions)
    if n == 0:
        return found  # its words for a target it finds nothing for
    new = [i for i in range(len(found)) if found.claimed(i) and not _among(found.q[i], ours.q)]
    return stacked([ours, found.take(new)], 6) if new else ours


def _among(q: np.ndarray, rows: np.ndarray) -> bool:
    """Whether ``q`` is one of ``rows`` (each joint within ``SAME``, modulo 2 pi)."""
    d = np.abs(np.angle(np.exp(1j * (rows - q))))
    return bool(np.any(np.all(d < general_6r.SAME, axis=1)))


SPEC = register(
    SolverSpec(
        name=FAMILY,
        kind="analytic",
        enforces_limits=True,
        priority=PRIORITY,
        why_not=applies,
        solves=frozenset(),
        run=run,
        summary="6R arms no Pieper family fits: Raghavan-Roth elimination, up to 16 solutions",
        complete=False,
    )
)
