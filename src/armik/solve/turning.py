"""What a request lets a 2 pi turn of an answer change.

Turning a revolute joint by 2 pi leaves the pose, hence the forward-kinematics check and
the collisions, as they were; the preferences, the global path and a followed path turn
their answers so. A joint's value does change: a held joint must not turn, and a user's own
constraint may read joint values (``q[0] >= 0``). ``Turning`` holds both: the joints no turn
may move, and the value checks a turned answer must pass again before it stands for the
verified one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armik.constraints.base import Constraint
from armik.constraints.hold import Hold
from armik.model.arm_model import ArmModel
from armik.model.turns import UNLIMITED_TURNS, combinations, turns


@dataclass(frozen=True)
class Turning:
    fixed: tuple[int, ...] = ()  # joints no turn moves: the held ones
    checks: tuple[Constraint, ...] = ()  # held joints' checks and a user's own constraints

    def free(self, dof: int) -> np.ndarray:
        """(dof,) bool: the joints a turn may move, as far as the request goes."""
        out = np.ones(dof, dtype=bool)
        out[list(self.fixed)] = False
        return out

    def keeps(self, arm: ArmModel, Q: np.ndarray) -> np.ndarray:
        """(N,) bool: whether each row of ``Q`` passes every check."""
        ok = np.ones(len(Q), dtype=bool)
        for c in self.checks:
            ok &= np.asarray(c.check(arm, Q).ok, dtype=bool)
        return ok

    def kept(self, arm: ArmModel, turned: np.ndarray, q: np.ndarray) -> np.ndarray:
        """``turned`` (a turn of the verified ``q``) where it passes every check, else ``q``."""
        if not self.checks or turned is q or self.keeps(arm, turned.reshape(1, -1))[0]:
            return turned
        return q


ANY = Turning()  # a request with no held joint and no check of its own: every turn stands


def turning(arm: ArmModel, opts, seed: np.ndarray) -> Turning:
    """What ``opts`` (``armik.options.Options``: its ``hold`` and its ``checks``) let a turn
    change, the held joints' values read from ``seed`` where given as None."""
    holds = [Hold(j, v).at(arm, seed) for j, v in (getattr(opts, "hold", None) or ())]
    checks = tuple(getattr(opts, "checks", ()) or ())
    if not holds and not checks:
        return ANY
    fixed = tuple(h.index(arm) for h in holds)
    return Turning(fixed, (*holds, *checks))


def refuse_broken(arm: ArmModel, out, turn: Turning) -> None:
    """Each success of ``out`` (a ``BatchResult``) that fails one of ``turn``'s checks made
    a failure with that check's status and words, in place: where a plan turned an answer
    past a constraint, the row says so rather than claim a success."""
    rows = np.flatnonzero(out.success) if turn.checks else np.zeros(0, dtype=np.int64)
    if not len(rows):
        return
    Q = np.asarray(out.q, dtype=float)[rows]
    for c in turn.checks:
        got = c.check(arm, Q)
        for k in np.flatnonzero(~np.asarray(got.ok, dtype=bool)).tolist():
            i = int(rows[k])
            if out.success[i]:
                out.success[i] = False
                out.status_code[i] = got.status.code
                out.reasons[i] = got.why(k)


def best_kept(
    arm: ArmModel, q: np.ndarray, score, q0: np.ndarray, turn: Turning, first=None
) -> np.ndarray:
    """``first`` (a turn of the verified ``q``: each joint's best) where given and it passes
    ``turn``'s checks; else the variant of ``q`` by turns of 2 pi (its combinations within
    the limits on the joints ``turn`` lets turn, at most ``MAX_TURNS``, ``q``'s own first)
    that ``score`` (``armik.problem.scores.Score``) ranks first among those that pass: a
    check on one joint's value (``q[0] >= 0``) keeps the other joints' turns."""
    if first is not None and turn.kept(arm, first, q) is first:
        return first  # type: ignore[no-any-return]
    Q = combinations(turns(arm, q, turn.free(arm.dof), UNLIMITED_TURNS))
    allowed = Q[turn.keeps(arm, Q)] if turn.checks else Q  # q itself, the first, passes
    return min(allowed, key=lambda x: score(arm, x, q0), default=q)
