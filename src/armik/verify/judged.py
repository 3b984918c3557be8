"""``solve_all``'s results from a closed form's rows judged in the call that solved them.

The compiled call (``armik.solvers.closed_form.sixr_judged``) has measured every row by
the compiled FK, written its status by the verdict's ``RULE`` and put the rows in their
order; here they become ``Solutions`` whose results are built on first access, each the
result the general verdict gives that row (tests/solve/test_prepared.py): a success's
reason written on its first read, as the prepared solves write theirs.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np

from armik.model.arm_model import ArmModel
from armik.result import IKResult
from armik.solutions import Solutions
from armik.status import _BY_CODE, Status
from armik.verify.verdict import limits_reason, numbered, success_reason

_new = object.__new__
_CONVERGED, _JOINT_LIMITS = Status.CONVERGED, Status.JOINT_LIMITS


class Judged:
    """What the judged rows of one plan's targets share (the arm, the family's words of a
    packed row, the solver's name, the tolerances, whether the orientation is measured),
    kept by the plan; ``solutions`` makes one target's rows its results."""

    __slots__ = ("arm", "words", "solver", "tol_p", "tol_r", "rot")

    def __init__(
        self,
        arm: ArmModel,
        words: Callable[[list], list],
        solver: str,
        tol_p: float,
        tol_r: float,
        rot: bool,
    ) -> None:
        self.arm, self.words, self.solver = arm, words, solver
        self.tol_p, self.tol_r, self.rot = tol_p, tol_r, rot

    def solutions(self, rows: np.ndarray, elapsed: float, repeated: bool) -> Solutions:
        """The ``Solutions`` of one target's judged ``rows``, each result's ``time``
        ``elapsed`` (s); ``repeated``: a branch label is met twice, so every label is
        numbered in order (``verdict.numbered``)."""
        labels = None
        if repeated:
            labels = numbered([said[2] for said in self.words(rows[:, 6:11].tolist())])
        return Solutions._lazy(len(rows), partial(self._result, rows, elapsed, labels))

    def _result(self, rows: np.ndarray, elapsed: float, labels, i: int) -> IKResult:
        """Row ``i``'s result."""
        if rows.flags.writeable:  # the results' q are its rows
            rows.setflags(write=False)
        row = rows[i]
        values = row.tolist()
        (_, text, label, singular) = self.words([values[6:11]])[0]
        pos = values[11]
        ori = values[12] if self.rot else None
        status = _BY_CODE[int(values[14])]
        q = row[:6]
        r = _new(IKResult)
        d = r.__dict__
        d["q"], d["success"], d["status"] = q, status is _CONVERGED, status
        if status is _CONVERGED:
            d["_reason"] = (success_reason, (text, None, pos, ori, self.tol_p, self.tol_r))
        elif status is _JOINT_LIMITS:
            d["_reason"] = (limits_reason, (self.arm, q))
        else:  # not reached: its claim's words
            d["reason"] = text
        d["solver"], d["iterations"], d["restarts"] = self.solver, 0, 0
        d["position_error"], d["orientation_error"], d["time"] = pos, ori, elapsed
        d["branch"] = label if labels is None else labels[i]
        d["singular"], d["extra"] = singular, {}
        return r
