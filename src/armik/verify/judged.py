"""``solve_all``'s results from a closed form's rows judged in the call that solved them.

The compiled call (``armik.solvers.closed_form.sixr_judged``) has measured every row by
the compiled FK, written its status by the verdict's ``RULE`` and put the rows in their
order; here they become ``Solutions`` whose results are built on the first access of any,
each the result the general verdict gives that row (tests/solve/test_prepared.py): the
rows made whole then, in one compiled call (the rows claimed outside the limits measured,
the order, the branch labels, numbered in order when one is met twice,
``verdict.numbered``), a success's reason written on its first read, as the prepared
solves write theirs.
"""

from __future__ import annotations

from collections.abc import Callable
from threading import Lock

import numpy as np

from armik.model.arm_model import ArmModel
from armik.result import IKResult
from armik.solutions import Solutions
from armik.status import _BY_CODE, Status
from armik.verify.verdict import limits_reason, numbered, success_reason

_new = object.__new__
_CONVERGED, _JOINT_LIMITS = Status.CONVERGED, Status.JOINT_LIMITS


class Judged:
    """What the judged rows of one plan's targets share (the arm, the family's call that
    makes a target's judged rows whole and its words of packed rows, the solver's name, the
    tolerances, whether the orientation is measured), kept by the plan; ``solutions``
    makes one target's rows its results."""

    __slots__ = ("arm", "finish", "words", "solver", "tol_p", "tol_r", "rot", "lock")

    def __init__(
        self,
        arm: ArmModel,
        finish: Callable[[np.ndarray, int], None],
        words: Callable[[list], list],
        solver: str,
        tol_p: float,
        tol_r: float,
        rot: bool,
    ) -> None:
        self.arm, self.finish, self.words, self.solver = arm, finish, words, solver
        self.tol_p, self.tol_r, self.rot = tol_p, tol_r, rot
        self.lock = Lock()  # one thread makes a target's rows whole, then read-only

    def solutions(self, rows: np.ndarray, n: int, elapsed: float) -> Solutions:
        """The ``Solutions`` of one target's first ``n`` judged ``rows`` (``rows``: the
        compiled call's whole array), each result's ``time`` ``elapsed`` (s)."""
        return Solutions._lazy(n, self._results, (rows, n, elapsed))

    def _results(self, whole: np.ndarray, n: int, elapsed: float) -> list[IKResult]:
        """Every row's result, in one pass over plain values."""
        with self.lock:  # the first access: measured, ordered, labelled (``finish``)
            if whole.flags.writeable:
                self.finish(whole, n)
                whole.setflags(write=False)  # the results' q are its rows
        rows = whole[:n]
        values = rows.tolist()
        said = self.words(values)
        if len({v[7] for v in values}) < n:  # a label met twice: every label numbered
            labels = numbered([label for _, _, label, _ in said])
            said = [(c, t, label, s) for (c, t, _, s), label in zip(said, labels)]
        arm, tol_p, tol_r, rot = self.arm, self.tol_p, self.tol_r, self.rot
        shared = {"success": True, "status": _CONVERGED, "solver": self.solver,
                  "iterations": 0, "restarts": 0, "time": elapsed}  # fmt: skip
        out = []
        for q, v, (_, text, label, singular) in zip(rows[:, :6], values, said):
            pos, status = v[11], _BY_CODE[int(v[14])]
            ori = v[12] if rot else None
            r = _new(IKResult)
            d = r.__dict__
            d.update(shared)  # what every row shares, then its own
            d["q"], d["position_error"], d["orientation_error"] = q, pos, ori
            d["branch"], d["singular"], d["extra"] = label, singular, {}
            if status is _CONVERGED:
                d["_reason"] = (success_reason, (text, None, pos, ori, tol_p, tol_r))
            else:
                d["success"], d["status"] = False, status
                if status is _JOINT_LIMITS:
                    d["_reason"] = (limits_reason, (arm, q))
                else:  # not reached: its claim's words
                    d["reason"] = text
            out.append(r)
        return out
