"""``Request``: one solve as every stage reads it, built once from what the user passed.

The facade (``Arm``, ``Arms``, the CLI, the Dask runner) reads the keyword options once
(``armik.solve.read``) into a ``Request``; below it no module takes keyword options: each
stage reads the request and hands on a changed copy (``Request.but``: another target, start
or solver, one answer or every one), never a dict of options to validate again.

- ``target``: the target as given when it is a plain pose the prepared plan takes as it
  is (a ``pinocchio.SE3``, a 4x4 or 3-vector float array), else parsed (a ``Target``); a
  stage that reads it parses it once with ``armik.targets.pose.parsed``, which passes a
  ``Target`` through.
- ``q0``: the start as given (None: the middle of the limits); ``ArmModel.seed`` reads it.
- ``solver``: the name asked for ("auto", or a registered solver).
- ``opts``: the validated settings (``armik.options.Options``), shared by every call with
  the same options: they may carry another call's seed, and ``seed`` is this call's
  (``settings`` puts it in).
- ``key``: what the kept plans and choices of these settings are kept under (None: not
  kept, settings that hold arrays).
- ``every``: every solution (``solve_all``) rather than the best one.
- ``t0``: when the call began (``time.perf_counter``): each result's ``time``.
- ``score``: a preference (``prefer=``) to rank the answers by, or None.
- ``problem``: a task list with no compiled form (``armik.problem.problem.Problem``), for the task
  solver, or None.
- ``rows``: a batch's rows as requests of their own, where the compiled batch has no form
  for them (task lists that do not lower together, a preference to rank each by), else
  None; a batch's or a path's ``target`` holds its targets as given.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple

from armik.constraints.base import at_start
from armik.frozen import frozen
from armik.options import Options

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


class Request(NamedTuple):
    target: object
    q0: object
    solver: str
    opts: Options
    key: tuple | None
    seed: int | None
    every: bool = False
    t0: float = 0.0
    score: Any = None
    problem: Any = None
    rows: tuple[Request, ...] | None = None
    sweep_from: float | None = None  # where the solver's sweep starts (``registry.swept_from``)

    def but(self, **changes: Any) -> Request:
        """This request with ``changes`` (fields by name)."""
        return self._replace(**changes)

    def narrowed(self, **changes: object) -> Request:
        """This request with some of its options changed (``changes``: values of
        ``Options``' own fields, of their type), kept apart from its own: its plans and
        choices."""
        key = None if self.key is None else (self.key, tuple(changes.items()))
        return self._replace(opts=but_options(self.opts, **changes), key=key)

    def lowered(self, target: object, said: dict, **changes: object) -> Request:
        """This request for a lowered task list (``armik.problem.problem.lower``): its
        ``target``, the options it says (``said``, validated here as options) and
        ``changes`` (as ``narrowed``), kept apart by those and by the target's aim."""
        given = Options.from_kwargs(said)
        values = {name: getattr(given, name) for name in said}
        values.update(changes)
        aim = getattr(target, "aim", None)
        shape = None if aim is None else aim.shape
        key = None if self.key is None else (self.key, tuple(values.items()), shape)
        return self._replace(target=target, opts=but_options(self.opts, **values), key=key)

    @property
    def settings(self) -> Options:
        """``opts`` with this call's seed in them."""
        return with_seed(self.opts, self.seed)


def with_seed(opts: Options, seed: int | None) -> Options:
    """``opts`` with this seed (a copy, built without the frozen ``__init__``)."""
    if opts.seed == seed and type(opts.seed) is type(seed):
        return opts
    return frozen(Options, **{**opts.__dict__, "seed": seed})


def but_options(opts: Options, **changes: object) -> Options:
    """``opts`` with ``changes``, which are values of ``Options``' own fields, already of
    their type (a copy, built without the frozen ``__init__``)."""
    return frozen(Options, **{**opts.__dict__, **changes})


def resolved(opts: Options, arm: ArmModel, q0: object, rows: bool = False) -> Options:
    """``opts`` with a user's own constraints resolved for this call from its start ``q0``
    (``armik.constraints.base.at_start``): ``opts`` itself where none has an ``at``."""
    checks = at_start(opts.checks, arm, q0, rows)
    return opts if checks is opts.checks else but_options(opts, checks=checks)
