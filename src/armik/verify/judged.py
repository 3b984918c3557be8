"""``solve_all``'s results from a closed form's rows judged in the call that solved them.

The compiled call (``armik.solvers.closed_form.sixr_judged``) has measured every row by
the compiled FK, written its status by the verdict's ``RULE`` and put the rows in their
order; here they become ``Solutions`` whose results are built on first access, each the
result the general verdict gives that row (tests/solve/test_prepared.py): a success's
reason written on its first read, as the prepared solves write theirs.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from armik.model.arm_model import ArmModel
from armik.result import IKResult
from armik.solutions import Solutions
from armik.status import _BY_CODE, Status
from armik.verify.verdict import limits_reason, numbered, success_reason

_new = object.__new__
_CONVERGED, _JOINT_LIMITS = Status.CONVERGED, Status.JOINT_LIMITS


class JudgedRows:
    """A closed form's judged ``rows`` (n, ``sixr_judged.WIDTH``, read-only) for one target,
    and what their results share."""

    __slots__ = ("arm", "rows", "words", "solver", "tol_p", "tol_r", "rot", "time", "labels")

    def __init__(
        self,
        arm: ArmModel,
        rows: np.ndarray,
        words: Callable[[list], list],
        solver: str,
        tol_p: float,
        tol_r: float,
        rot: bool,
        elapsed: float,
        repeated: bool,
    ) -> None:
        self.arm, self.rows, self.words, self.solver = arm, rows, words, solver
        self.tol_p, self.tol_r, self.rot, self.time = tol_p, tol_r, rot, elapsed
        # a branch label met twice: every label numbered in order (``verdict.numbered``)
        self.labels = self._numbered() if repeated else None

    def _numbered(self) -> list:
        keys = self.rows[:, 6:11].tolist()
        return numbered([label for _, _, label, _ in self.words(keys)])

    def result(self, i: int) -> IKResult:
        """Row ``i``'s result."""
        row = self.rows[i]
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
        d["position_error"], d["orientation_error"], d["time"] = pos, ori, self.time
        d["branch"] = label if self.labels is None else self.labels[i]
        d["singular"], d["extra"] = singular, {}
        return r


def judged_solutions(
    arm: ArmModel,
    rows: np.ndarray,
    words: Callable[[list], list],
    solver: str,
    tol_p: float,
    tol_r: float,
    rot: bool,
    elapsed: float,
    repeated: bool,
) -> Solutions:
    """The ``Solutions`` of judged ``rows`` (read-only); see ``JudgedRows``."""
    record = JudgedRows(arm, rows, words, solver, tol_p, tol_r, rot, elapsed, repeated)
    return Solutions._lazy(len(rows), record.result)
