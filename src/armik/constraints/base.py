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

import functools
from abc import ABC, abstractmethod
from collections.abc import Callable
from types import FunctionType
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from armik import reasons
from armik.errors import ArmikError, OptionError
from armik.status import Status
from armik.tolerances import LIMIT_TOL

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

    def __init_subclass__(cls, **kwargs: object) -> None:
        """A class of the user's own: its ``check``, ``box`` and ``at`` read through
        ``_checked``, ``_boxed`` and ``_resolved``, whichever route calls them (armik's own
        constraints are read as they are: no call added)."""
        super().__init_subclass__(**kwargs)
        if cls.__module__.startswith("armik."):
            return
        for name, read in (("check", _checked), ("box", _boxed), ("at", _resolved)):
            own = cls.__dict__.get(name)
            if isinstance(own, FunctionType) and not getattr(own, "_armik_checked", False):
                setattr(cls, name, read(own))


def _refused(name: str, what: str) -> OptionError:
    """What is wrong with a user's constraint class ``name``, as an ``OptionError``."""
    return OptionError(f"constraint {name}: {what}", option="constraints", value=name)


def _called(name: str, what: str, fn: Callable[..., Any], *args: object, said: str = "") -> Any:
    """``fn(*args)``, a member of the user's constraint class ``name``: an armik error passes,
    another it raises is an ``OptionError`` saying ``its {what} raised ...`` (then ``said``)."""
    try:
        return fn(*args)
    except ArmikError:
        raise
    except Exception as exc:
        raise _refused(name, f"its {what} raised {type(exc).__name__}: {exc}{said}") from exc


def _checked(own: Callable[..., object]) -> Callable[..., Check]:
    """A user's ``check``, its result read as a ``Check`` of the answers given: an error it
    raises, or a result of another shape, an ``OptionError`` naming its class."""

    @functools.wraps(own)
    def check(self: Constraint, arm: ArmModel, Q: np.ndarray) -> Check:
        on = f" (on {len(Q)} answer(s), Q of shape {np.shape(Q)})"
        # a copy: a check that writes into its Q (wraps an angle in place) leaves the
        # answers the verdict measured as they are
        got = _called(type(self).__name__, "check", own, self, arm, np.array(Q), said=on)
        if type(got) is Check:
            ok = got.ok
            if type(ok) is np.ndarray and ok.dtype == np.bool_ and ok.shape == (len(Q),):
                if isinstance(got.status, Status) and got.status is not Status.CONVERGED:
                    return _in_box(self, arm, Q, _said(self, got))  # its shape as it should be
        return _in_box(self, arm, Q, _said(self, _read(self, got, len(Q))))

    check._armik_checked = True  # type: ignore[attr-defined]
    return check


def _boxed(own: Callable[..., object]) -> Callable[..., tuple[np.ndarray, np.ndarray] | None]:
    """A user's ``box``, its result read as None or (lower, upper), one number per joint
    each or one for all (rad or m, +-inf for none), lower <= upper: an error it raises, or
    a result of another shape, an ``OptionError`` naming its class and what is wrong."""

    @functools.wraps(own)
    def box(self: Constraint, arm: ArmModel) -> tuple[np.ndarray, np.ndarray] | None:
        name = type(self).__name__
        got = _called(name, "box", own, self, arm)
        if got is None:
            return None
        n = arm.dof
        say = f"(lower, upper), {n} numbers each (one per joint, rad or m; +-inf for none)"
        try:  # a number stands for every joint
            lower, upper = (np.array(b, dtype=float) for b in got)  # type: ignore[attr-defined]
            if lower.ndim == 0:
                lower = np.full(n, lower)
            if upper.ndim == 0:
                upper = np.full(n, upper)
        except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
            raise _refused(name, f"its box must return None or {say}, got {got!r}") from None
        if lower.shape != (n,) or upper.shape != (n,):
            raise _refused(
                name,
                f"its box must return None or {say}, got shapes {lower.shape} and {upper.shape}",
            )
        if np.isnan(lower).any() or np.isnan(upper).any() or (lower > upper).any():
            j = int(np.flatnonzero(~(lower <= upper))[0])
            raise _refused(
                name,
                f"its box must give lower <= upper, numbers, at every joint; at joint {j} "
                f"({arm.joint_names[j]}) it gave [{lower[j]}, {upper[j]}]",
            )
        return lower, upper

    box._armik_checked = True  # type: ignore[attr-defined]
    return box


def _in_box(constraint: Constraint, arm: ArmModel, Q: np.ndarray, got: Check) -> Check:
    """``got``, with the answers outside the constraint's own box (a user's class with a
    ``box``) failing too, in its status: the task solver steps within the box, the other
    routes never read it, and an answer they found outside it was a success."""
    if not getattr(type(constraint).box, "_armik_checked", False):
        return got
    box = constraint.box(arm)
    if box is None:
        return got
    lower, upper = box
    Q = np.asarray(Q, dtype=float)
    inside = np.asarray(((Q >= lower - LIMIT_TOL) & (Q <= upper + LIMIT_TOL)).all(axis=1))
    if inside.all():
        return got
    name, why = type(constraint).__name__, got.why

    def outside(i: int) -> str:
        if inside[i]:
            return why(i)
        q = Q[i]
        j = int(np.flatnonzero(~((q >= lower - LIMIT_TOL) & (q <= upper + LIMIT_TOL)))[0])
        return reasons.outside_own_box(
            name, arm.joint_names[j], float(q[j]), float(lower[j]), float(upper[j])
        )

    return got._replace(ok=got.ok & inside, why=outside)


def _resolved(own: Callable[..., object]) -> Callable[..., Constraint]:
    """A user's ``at``, its result read as a ``Constraint``: an error it raises, or another
    result, an ``OptionError`` naming its class."""

    @functools.wraps(own)
    def at(self: Constraint, arm: ArmModel, seed: np.ndarray) -> Constraint:
        name = type(self).__name__
        got = _called(name, "at", own, self, arm, np.array(seed))  # a copy, as ``check``'s Q
        if not isinstance(got, Constraint):
            raise _refused(
                name,
                f"its at(arm, seed) must return the constraint resolved for that solve (a "
                f"Constraint: self where nothing changes), got {got!r}",
            )
        return got

    at._armik_checked = True  # type: ignore[attr-defined]
    return at


_SAY = "a check returns armik.constraints.base.Check(ok, status, why)"


def _read(constraint: Constraint, got: object, n: int) -> Check:
    """``got``, a user's check of ``n`` answers, as a ``Check`` with ``ok`` of shape (n,)
    (one bool, or (1, 1), read as the one answer's); an ``OptionError`` naming the
    constraint's class and what is wrong otherwise."""
    name = type(constraint).__name__

    def refused(what: str) -> OptionError:
        return _refused(name, what)

    if not isinstance(got, Check):
        raise refused(f"its check returned {type(got).__name__}, not a Check: {_SAY}")
    try:
        ok = np.asarray(got.ok)
    except Exception:  # an object numpy cannot read
        ok = np.asarray(None)
    if ok.dtype == np.bool_ and ok.shape != (n,) and n == 1 and ok.size == 1:
        ok = ok.reshape(1)  # one bool for the one answer
    if ok.dtype != np.bool_ or ok.shape != (n,):
        given = f"{got.ok!r}" if ok.ndim == 0 else f"shape {ok.shape}, dtype {ok.dtype}"
        hint = " (a column: give ok[:, 0])" if ok.shape == (n, 1) else ""
        raise refused(
            f"Check.ok must hold one bool per answer checked, shape ({n},) here, got {given}{hint}"
        )
    status = got.status
    if not isinstance(status, Status) or status is Status.CONVERGED:
        word = isinstance(status, str) and not isinstance(status, Status) and status in _WORDS
        named = f" (a str): give armik.Status.{Status(status).name}" if word else ""
        raise refused(
            f"Check.status must be the armik.Status of a failing answer (e.g. armik.Status."
            f"JOINT_LIMITS), got {status!r}{named}"
        )
    for field in ("why", "holds", "extra"):
        if not callable(getattr(got, field)):
            raise refused(f"Check.{field} must be a function, got {getattr(got, field)!r}")
    return got._replace(ok=ok)


def _said(constraint: Constraint, got: Check) -> Check:
    """``got`` with its words and extras (``why``, ``holds``, ``extra``: the user's
    functions, called when the verdict reads a row) read through a check of each call: an
    error raised, or a result other than a str (a dict for ``extra``), an ``OptionError``
    naming the constraint's class."""
    name = type(constraint).__name__

    def read(field: str, fn: Callable[..., object], kind: type) -> Callable[..., Any]:
        def call(i: int, *more: object) -> Any:
            out = _called(name, f"Check.{field} of answer {i}", fn, i, *more)
            if not isinstance(out, kind):
                raise _refused(
                    name,
                    f"its Check.{field} of answer {i} must return a {kind.__name__}, got {out!r}",
                )
            return out

        return call

    return got._replace(
        why=read("why", got.why, str),
        holds=got.holds if got.holds is _unchanged else read("holds", got.holds, str),
        extra=got.extra if got.extra is _nothing else read("extra", got.extra, dict),
    )


_WORDS = {s.value for s in Status if s is not Status.CONVERGED}


def satisfied(arm: ArmModel, constraints: tuple[Constraint, ...], q: np.ndarray) -> bool:
    """Whether ``q`` satisfies every constraint."""
    Q = q.reshape(1, -1)
    for c in constraints:  # the first broken one ends it
        if not c.check(arm, Q).ok[0]:
            return False
    return True


def at_start(
    checks: tuple[Constraint, ...], arm: ArmModel, q0: object, rows: bool = False
) -> tuple[Constraint, ...]:
    """``checks`` resolved for one call from its start ``q0`` (None: the middle of the
    limits; ``rows``: a batch's, one row for every target, or one per row that are all the
    same), each by its own ``at``; ``checks`` itself where none has one. A batch with
    different starts per row has no one start to resolve them from: an ``OptionError``
    naming the constraint; a q0 that is no configuration, ``ArmModel.check_q``'s."""
    own = [c for c in checks if type(c).at is not Constraint.at]  # the base's: itself
    if not own:
        return _boxes_read(checks, arm)
    q = arm.middle if q0 is None else q0
    if rows and q0 is not None:
        try:
            Q = np.asarray(q0, dtype=float)
        except (TypeError, ValueError, OverflowError):  # not numbers: ``check_q`` names it
            Q = np.zeros(0)
        if Q.ndim == 2 and len(Q) > 1 and not np.array_equal(Q, Q[[0] * len(Q)], equal_nan=True):
            raise OptionError(
                f"constraint {type(own[0]).__name__} is resolved from the start (its at(arm, "
                f"seed)), and this batch gives a different q0 per row: give one q0 for every "
                f"row, or solve the rows one by one",
                option="constraints",
                value=own[0],
            )
        q = Q[0] if Q.ndim == 2 and len(Q) else q
    seed = np.clip(arm.check_q(q, "q0"), arm.lower, arm.upper)  # as the seed will be
    at = tuple([c if type(c).at is Constraint.at else c.at(arm, seed) for c in checks])
    return _boxes_read(at, arm)


def _boxes_read(checks: tuple[Constraint, ...], arm: ArmModel) -> tuple[Constraint, ...]:
    """``checks``, each box of a user's class read once (``_boxed``: a malformed one, its
    shape, order or a NaN, an ``OptionError`` naming the class) on every route, as the task
    solver, which steps within it, reads it: a route that never steps within it refuses it
    all the same, where it took it silently."""
    for c in checks:
        if getattr(type(c).box, "_armik_checked", False):
            c.box(arm)
    return checks


def own(c: object) -> bool:
    """Whether ``c`` is a constraint of a user's own class with its own ``at`` (read through
    this module's wrappers): resolved from the call's start where the call is read
    (``at_start``), never again below (``solve/tasks.py`` tests it inline)."""
    return bool(getattr(getattr(type(c), "at", None), "_armik_checked", False))
