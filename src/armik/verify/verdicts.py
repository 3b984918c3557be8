"""``Verdicts``: N answers after verification, as arrays. The solver's ``Answers`` with
the verdict's status of each row, its measured errors and its words; each ``IKResult``
is a row of them (``results``), a ``BatchResult`` their columns.

A constraint's ``Check`` of the N rows applies to them at once (``judge``): a success
stays one only where the check holds. A success's words are written when read
(``reason``): they repeat its errors, which a loop of solves rarely reads.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from armik import reasons
from armik.constraints.base import Check, Constraint
from armik.kernel.descent import DUPLICATE_TOL
from armik.model.turns import UNLIMITED_TURNS, combinations, turns
from armik.result import IKResult
from armik.solvers.answers import Answers, one, stacked
from armik.solvers.closed_form.sixr import TIE
from armik.status import _BY_CODE, FAILURE_RANK, Status

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel

_CONVERGED = Status.CONVERGED.code


@dataclass(eq=False)
class Verdicts:
    """N verified answers: the rows of ``answers`` with the verdict's columns."""

    answers: Answers
    status: np.ndarray  # (N,) int8: each row's Status code, the verdict's (writable)
    position_error: np.ndarray  # (N,) m
    orientation_error: np.ndarray  # (N,) rad; NaN throughout where not measured
    rotation: bool  # the orientation is measured
    words: list[str | None]  # each row's reason; None: a success's, written on read
    tol_position: float
    tol_orientation: float
    region: bool = False  # the errors are the distances outside the target's region
    extra: list[dict] | None = None  # per row, what its result keeps (a collision check)
    cone: reasons.Cone | None = None  # the aim's cone, the orientation error outside it
    free: tuple[bool, bool] = (False, False)  # (position, rotation): every component free

    def __len__(self) -> int:
        return len(self.words)

    @property
    def q(self) -> np.ndarray:
        return self.answers.q

    @property
    def success(self) -> np.ndarray:
        """(N,) bool: verified, every check holding."""
        return self.status == _CONVERGED

    def succeeded(self, i: int) -> bool:
        return self.status.item(i) == _CONVERGED

    def measured(self, i: int) -> str:
        """Row i's errors in words."""
        ori = self.orientation_error.item(i) if self.rotation and not self.free[1] else None
        pos = None if self.free[0] else self.position_error.item(i)  # free: its 0 not said
        tol_p, tol_r = self.tol_position, self.tol_orientation
        if self.region:
            return reasons.region(pos, ori, tol_p, tol_r, self.cone)
        return reasons.measured(pos, ori, tol_p, tol_r)

    def reason(self, i: int) -> str:
        """Why row i ended as it did: a failure's words, or a success's claim (the solver's
        words where it claimed it) and errors."""
        text = self.words[i]
        if text is None:
            claimed = self.answers.claimed(i)
            text = reasons.verified(self.answers.reason(i) if claimed else None, self.measured(i))
            self.words[i] = text
        return text

    def judge(self, check: Check, rows: Sequence[int] | None = None) -> Verdicts:
        """These rows with ``check`` applied, in place: a check of every row, or of the
        rows ``rows`` in that order (its k-th answer is row ``rows[k]``). A success stays
        one only where the check holds; what each row keeps goes to its ``extra``."""
        n = len(self)
        if self.extra is None:
            self.extra = [{} for _ in range(n)]
        for k, i in enumerate(range(n) if rows is None else rows):
            more = check.extra(k)
            if more:
                self.extra[i].update(more)
            if not self.succeeded(i):
                continue
            if check.ok[k]:
                self.words[i] = check.holds(k, self.reason(i))
            else:
                self.status[i] = check.status.code
                self.words[i] = check.why(k)
        return self

    def checked(self, arm: ArmModel, constraints: Sequence[Constraint]) -> Verdicts:
        """These rows with every constraint's check of them applied (``judge``). A success
        a check would refuse stands first at its turn by 2 pi (the same pose, errors and
        collisions; ``armik.model.turns``) nearest it that passes them all, where one does:
        a solver's choice of turn (nearest q0) is no reason to refuse the pose."""
        if constraints:
            self._turned_to_pass(arm, constraints)
        for c in constraints:
            self.judge(c.check(arm, self.answers.q))
        return self

    def _turned_to_pass(self, arm: ArmModel, constraints: Sequence[Constraint]) -> None:
        values = [c for c in constraints if not c.pose_only]  # what a turn can change
        if not values:
            return
        Q = self.answers.q
        ok = self.success.copy()
        for c in values:
            ok &= np.asarray(c.check(arm, Q).ok, dtype=bool)
        refused = np.flatnonzero(self.success & ~ok).tolist()
        if not refused:
            return
        moved = np.array(Q, dtype=float)
        # a configuration stands for one answer only (two found 2 pi apart are one): a turn
        # within DUPLICATE_TOL of an answer kept is not taken
        kept = [moved[i] for i in np.flatnonzero(ok).tolist()]
        for i in refused:
            C = combinations(turns(arm, moved[i], unlimited=UNLIMITED_TURNS))[1:]
            if not len(C):  # (the row itself, C's first, is refused)
                continue
            passes = np.ones(len(C), dtype=bool)
            for c in values:
                passes &= np.asarray(c.check(arm, C).ok, dtype=bool)
            C = C[passes]
            for k in np.argsort(np.abs(C - moved[i]).sum(axis=1), kind="stable").tolist():
                if all(np.abs(C[k] - other).max() >= DUPLICATE_TOL for other in kept):
                    moved[i] = C[k]
                    kept.append(moved[i])
                    break
        if not np.array_equal(moved, Q):
            moved.flags.writeable = False
            self.answers = replace(self.answers, q=moved)

    def recounted(self, iterations: int, restarts: int) -> Verdicts:
        """These rows with the counts of the whole search that found them; a numeric
        claim's words, which count its own run's restarts (``reasons.CONVERGED``), count
        the search's, in the solver's words and in the verdict's written from them."""
        n = len(self)
        own = self.answers.restarts.tolist()

        def said(i: int, text: str | None) -> str | None:
            claim = reasons.CONVERGED.format(own[i])
            if text is None or not text.startswith(claim):
                return text
            return reasons.CONVERGED.format(restarts) + text[len(claim) :]

        given = self.answers.reasons
        counts = replace(
            self.answers,
            iterations=np.full(n, iterations, dtype=np.int64),
            restarts=np.full(n, restarts, dtype=np.int64),
            reasons=None
            if given is None
            else tuple([str(said(i, t)) for i, t in enumerate(given)]),
        )
        words = [said(i, t) for i, t in enumerate(self.words)]
        return replace(self, answers=counts, words=words)

    def rank(self, i: int, seed: np.ndarray) -> tuple:
        """Row i's place among the rows: successes first, nearest ``seed``; then failures
        by ``failure_rank``."""
        if self.succeeded(i):
            d = self.answers.q[i] - seed
            return (0, float(np.sqrt(d.dot(d))))
        ori = self.orientation_error.item(i) if self.rotation else None
        status = Status.from_code(self.status.item(i))
        return (1, *failure_rank(status, self.position_error.item(i), ori))

    def fields(self, i: int, branch: str | None = None, lazy: bool = False) -> dict:
        """Row i as the fields of an ``IKResult`` but ``solver`` and ``time`` (``q`` a
        read-only copy; ``branch``: a label in place of the row's own; ``lazy``: a
        success's words written on first read, by ``IKResult``)."""
        a = self.answers
        q = np.array(a.q[i], dtype=float)
        q.flags.writeable = False
        code = self.status.item(i)  # plain Python values: ``item`` reads them directly
        text = self.words[i]
        return {
            "q": q,
            "success": code == _CONVERGED,
            "status": Status.from_code(code),
            **(
                {"_reason": (self.reason, (i,))}
                if lazy and text is None
                else {"reason": self.reason(i)}
            ),
            "iterations": a.iterations.item(i),
            "position_error": self.position_error.item(i),
            "orientation_error": self.orientation_error.item(i) if self.rotation else None,
            "branch": a.label(i) if branch is None else branch,
            "singular": a.is_singular(i),
            "restarts": a.restarts.item(i),
        }

    def results(
        self, rows: Sequence[int], solver: str, time: float, labels: Sequence | None = None
    ) -> list[IKResult]:
        """These rows as results, in this order (``labels``: branch labels in place of the
        rows' own); a success's words are written when its result's ``reason`` is first
        read."""
        # the columns read once, each row built in one loop: a solve_all's cost is per row
        index = list(rows)
        a = self.answers
        codes = self.status[index].tolist()
        its, restarts = a.iterations[index].tolist(), a.restarts[index].tolist()
        pos = self.position_error[index].tolist()
        ori = self.orientation_error[index].tolist() if self.rotation else [None] * len(index)
        if labels is None:
            labels = [None] * len(index) if a.branch is None else [a.branch[i] for i in index]
        flags = [False] * len(index) if a.singular is None else a.singular[index].tolist()
        words, extra, reason, status_of = self.words, self.extra, self.reason, _BY_CODE
        out = []
        for k, i in enumerate(index):
            q = np.array(a.q[i], dtype=float)
            q.flags.writeable = False
            code, text = codes[k], words[i]
            fields = {
                "q": q,
                "success": code == _CONVERGED,
                "status": status_of[code],
                **({"_reason": (reason, (i,))} if text is None else {"reason": text}),
                "iterations": its[k],
                "position_error": pos[k],
                "orientation_error": ori[k],
                "branch": labels[k],
                "singular": bool(flags[k]),
                "restarts": restarts[k],
                "solver": solver,
                "time": time,
            }
            r = IKResult._from_fields(fields)
            if extra is not None and extra[i]:
                r.__dict__["extra"] = dict(extra[i])
            out.append(r)
        return out

    def order(self, seed: np.ndarray) -> list[int]:
        """The rows in ``rank``'s order, their keys computed in one pass (as ``rank``
        computes each); successes as near the seed to ``sixr.TIE`` in the solver's order
        (``tied``)."""
        ok = (self.status == _CONVERGED).tolist()
        pos, ori = self.position_error.tolist(), self.orientation_error.tolist()
        keys: list[tuple] = []
        for i, (q, good) in enumerate(zip(self.answers.q, ok)):
            if good:
                d = q - seed
                keys.append((0, float(np.sqrt(d.dot(d)))))
            else:
                status = _BY_CODE[self.status.item(i)]
                keys.append((1, *failure_rank(status, pos[i], ori[i] if self.rotation else None)))
        order = sorted(range(len(keys)), key=keys.__getitem__)
        verified = sum(ok)  # first: the successes, nearest the seed first (ties: ``tied``)
        return tied(order[:verified], keys, self.answers.q.shape[1]) + order[verified:]

    def once(self, order: list[int]) -> list[int]:
        """``order`` without a success within ``DUPLICATE_TOL`` of one before it in every
        joint: the same solution, which a closed form can find twice at a double root (two
        rows 1e-8 apart at a singular target), listed once."""
        good = (self.status == _CONVERGED).tolist()  # one pass, no call a row
        ok = [i for i in order if good[i]]
        if len(ok) < 2:
            return order
        S = self.answers.q[ok]
        # the rows as near in joint 1 (a numeric solve_all keeps up to 10000: no m x m array)
        first = S[:, 0]
        by = np.argsort(first, kind="stable")
        ranked = first[by]
        lo = np.searchsorted(ranked, first - DUPLICATE_TOL, side="right")
        hi = np.searchsorted(ranked, first + DUPLICATE_TOL, side="left")
        if np.all(hi - lo <= 1):  # each row alone within DUPLICATE_TOL in joint 1
            return order
        kept = np.zeros(len(ok), dtype=bool)
        twice = set()
        for a in range(len(ok)):
            near = [b for b in by[lo[a] : hi[a]].tolist() if b < a and kept[b]]
            if near and np.any(np.abs(S[near] - S[a]).max(axis=1) < DUPLICATE_TOL):
                twice.add(ok[a])
            else:
                kept[a] = True
        return [i for i in order if i not in twice] if twice else order

    def result(self, i: int, solver: str, time: float) -> IKResult:
        """Row i as a result."""
        return self.results((i,), solver, time)[0]

    def take(self, rows: Sequence[int]) -> Verdicts:
        """These rows, in this order."""
        index = list(rows)
        return replace(
            self,
            answers=self.answers.take(index),
            status=self.status[index],
            position_error=self.position_error[index],
            orientation_error=self.orientation_error[index],
            words=[self.words[k] for k in index],
            extra=None if self.extra is None else [self.extra[k] for k in index],
        )

    @classmethod
    def of_result(cls, r: IKResult, tol_position: float, tol_orientation: float) -> Verdicts:
        """A result's row again (its status the claim), for a search that goes on from it:
        its verdict's measure (``r.measured`` where it measured apart, else its errors)."""
        answers = one(
            np.array(r.q, dtype=float),
            r.status,
            r.reason,
            iterations=r.iterations,
            restarts=r.restarts,
            branch=r.branch,
            singular=r.singular,
        )
        pos, ori = r.position_error, r.orientation_error
        apart = r.extra.get("measured") if r.extra else None
        if apart is not None:  # the distances are said again after the search
            pos, ori = apart
        extra = {k: v for k, v in r.extra.items() if k != "measured"} if r.extra else None
        return cls(
            answers=answers,
            status=np.array([r.status.code], dtype=np.int8),
            position_error=np.array([np.nan if pos is None else pos]),
            orientation_error=np.array([np.nan if ori is None else ori]),
            rotation=ori is not None,
            words=[r.reason],
            tol_position=tol_position,
            tol_orientation=tol_orientation,
            extra=[extra] if extra else None,
        )


def tied(order: list[int], keys: Sequence[tuple], dof: int) -> list[int]:
    """``order`` (rows sorted by ``keys``, whose last item is a distance to the seed) with
    each run of rows whose keys agree but for distances within ``sixr.TIE`` of the one before
    put back in the solver's order (their indices): a closed form lists its rows nearest q0
    first, rows as near to ``TIE`` by the first joint whose values differ (``sixr._before``,
    the exported C's ``before``), so that a sum's rounding decides no tie. Rows of two
    joints keep ``order``: ``planar2r`` leaves its ties to the exact distance
    (``planar2r_kernel.TIE``, ``planar2r._farther``)."""
    if dof <= 2 or len(order) < 2:
        return order
    runs = [[order[0]]]
    for a, b in zip(order, order[1:]):
        ka, kb = keys[a], keys[b]
        if kb[:-1] == ka[:-1] and kb[-1] - ka[-1] <= TIE:
            runs[-1].append(b)
        else:
            runs.append([b])
    if len(runs) == len(order):  # no ties: the usual case
        return order
    return [i for run in runs for i in sorted(run)]


def failure_rank(status: Status, position_error: float, orientation_error) -> tuple:
    """How failed results are ranked among themselves: by status, then by their errors."""
    return (FAILURE_RANK[status], position_error + (orientation_error or 0.0))


def joined(parts: Sequence[Verdicts], dof: int) -> Verdicts:
    """The rows of ``parts`` (at least one, measured alike), in their order."""
    if len(parts) == 1:
        return parts[0]
    first = parts[0]
    extra = None
    if any(p.extra is not None for p in parts):
        extra = [e for p in parts for e in (p.extra or [{} for _ in range(len(p))])]
    return replace(
        first,
        answers=stacked([p.answers for p in parts], dof),
        status=np.concatenate([p.status for p in parts]),
        position_error=np.concatenate([p.position_error for p in parts]),
        orientation_error=np.concatenate([p.orientation_error for p in parts]),
        words=[w for p in parts for w in p.words],
        extra=extra,
    )
