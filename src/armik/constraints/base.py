"""A constraint: what every answer must satisfy besides its tasks (joint limits, a held
joint, keeping clear of collisions).

A constraint gives the step its box rows (``lower <= q <= upper``, where it has any: the
limits, a held joint) and the verify stage its check of N answers (``Check``): whether each
satisfies it, a failure's status and words, and what each answer's result keeps; the
verdict applies it to N answers at once (``armik.verify.verdicts.Verdicts.judge``).
``said`` is the constraint in the options of the compiled path (``hold``, ``obstacles``,
...), which spell it there, so that the old keywords and the objects are one problem
(``armik.options``); a constraint of any other class is also kept as itself
(``Options.checks``), and the verdict of every route runs its check.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from armik.status import Status

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


def _unchanged(i: int, reason: str) -> str:
    return reason


def _nothing(i: int) -> dict:
    return {}


class Check(NamedTuple):
    """A constraint's check of N answers: ``ok[i]``, whether answer i satisfies it; a
    failing answer's ``status`` and ``why(i)``; a success's reason with what was measured
    (``holds(i, reason)``) and what each answer's result keeps in ``extra`` (``extra(i)``).
    The verify stage applies it to the answers' verdicts (``armik.verify.verdicts``)."""

    ok: np.ndarray  # (N,) bool
    status: Status
    why: Callable[[int], str]
    holds: Callable[[int, str], str] = _unchanged
    extra: Callable[[int], dict] = _nothing


class Constraint(ABC):
    """What every answer must satisfy; checked on each answer before it is a success."""

    # whether the check reads the pose alone (the links' placements), which a joint's turn
    # by 2 pi leaves as it is: no turn of a failing answer can pass it
    pose_only: bool = False

    def said(self) -> dict[str, object]:
        """The constraint as the compiled path's options (``Options`` fields); none for a
        constraint that only its own ``check`` says (kept as itself: ``Options.checks``)."""
        return {}

    def at(self, arm: ArmModel, seed: np.ndarray) -> Constraint:
        """The constraint for one solve of ``arm`` from ``seed`` (its values resolved and
        checked against the arm: a joint's name, a value taken from the seed)."""
        return self

    def box(self, arm: ArmModel) -> tuple[np.ndarray, np.ndarray] | None:
        """(lower, upper): the box every step stays in (rad or m), None where it has none."""
        return None

    @abstractmethod
    def check(self, arm: ArmModel, Q: np.ndarray) -> Check:
        """The check of the answers ``Q`` (N, dof)."""


def satisfied(arm: ArmModel, constraints: tuple[Constraint, ...], q: np.ndarray) -> bool:
    """Whether ``q`` satisfies every constraint."""
    Q = q.reshape(1, -1)
    for c in constraints:  # the first broken one ends it
        if not c.check(arm, Q).ok[0]:
            return False
    return True
