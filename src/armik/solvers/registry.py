"""The solver registry: register once, look up by name, choose with "auto".

A solver is one file that builds a ``SolverSpec`` and calls ``register``. ``why_not`` returns
None when the solver applies to an arm and target, else the reason it does not.

Constraints, one rule: a solver declares whether its own steps keep the joint limits
(``SolverSpec.enforces_limits``) and the constraint classes they keep beyond them
(``SolverSpec.enforces``), and "auto" takes, among the solvers that apply, one that keeps
every class a request holds before the others, and then, on an arm with a limited joint,
one that keeps the limits before one that does not (``choose``); the
verdict (``armik.verify``) checks every constraint of the request that no stage keeps by
construction (the joint limits by its rule, ``Hold`` and ``Collisions`` by their stages),
on every route, whatever the solver declares: a declaration never makes a broken answer a
success.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, NamedTuple

import numpy as np

from armik.errors import SolverError, did_you_mean, listing
from armik.model.derived import Derived
from armik.problem.settings import (
    SolverSettings,
)  # the choices are kept per options: hashed, compared

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.solvers.answers import Answers
    from armik.targets.batch import TargetBatch
    from armik.targets.pose import Target

WhyNot = Callable[["ArmModel", "Target | None", "SolverSettings | None"], "str | None"]
Run = Callable[["ArmModel", "Target", "np.ndarray", "SolverSettings", bool], "Answers"]
# Many targets, one best attempt each: (arm, targets, q0 (N, dof), options) -> arrays.
RunBatch = Callable[["ArmModel", "TargetBatch", "np.ndarray", "SolverSettings"], "Answers"]
# One plain 4x4 pose at a time, prepared once per arm, options and target kind (see
# ``armik.solve.prepared``): (arm, options, position_only) -> run_pose(H, q0, seed), or None
# where the solver has no runner for that input (the general path then); a solver that
# solves a cone ("cone" in ``solves``) takes the targets' aim too, as a fourth argument.
PreparePose = Callable[..., "Callable | None"]


# (arm, target, seed, value, opts, every) -> answers: a sweep started at ``value`` (``Sweep``)
FromValue = Callable[["ArmModel", "Target", "np.ndarray", float, "SolverSettings", bool], "Answers"]


class Sweep(NamedTuple):
    """What a solver whose answers lie at one value of a joint can do (a 7R arm's joint 7
    held, the rest in closed form): the stages that hold that joint (``hold=``), search it
    for a preference or plan a path over its values ask the registry for it, not for a
    solver by name."""

    joint: int  # the index of the joint it holds
    # (arm, target, seed, value) -> every answer with the joint at exactly ``value``
    at_value: Callable[[ArmModel, Target, np.ndarray, float], Answers]
    # (arm, value) -> (lower, upper): the values worth sweeping from ``value``
    range: Callable[[ArmModel, float], tuple[float, float]]
    # (arm, target, seed) -> value -> the configurations ``at_value`` claims there (k, dof),
    # without their words: a search over the values (a preference's) calls it many times
    exact: Callable[[ArmModel, Target, np.ndarray], Callable[[float], np.ndarray]]
    # (arm, target, seed, value, opts, every) -> its answers swept from ``value`` on (that
    # value first, then the others in its own order), as ``run`` gives them: a global path's
    # rungs (``swept_from``); None: ``run`` from the seed with the joint at ``value``
    from_value: FromValue | None = None


class Parameter(NamedTuple):
    """A parameter of a redundant arm's self-motion that a solver answers at any one value
    of, fixed by the option it is named for (an SRS arm's ``swivel=``): the stage that fixes
    it asks the registry which solver declares that option, not for a solver by name."""

    option: str  # the keyword that gives the value
    words: str  # what the value is, for a refusal: "an SRS arm's elbow swivel angle (rad)"
    # (arm, target, seed, value) -> every answer at exactly ``value``
    at_value: Callable[[ArmModel, Target, np.ndarray, float], Answers]


# What a request may ask beyond an exact full pose (``Options.forms``; "cone": a target's
# aim), each form's words in
# a refusal, and what a solver needing one asks for
FORMS = ("position_only", "weights", "bounds", "spin", "cone")
_ASKED = {
    "position_only": "position_only",
    "weights": "per-axis weights",
    "bounds": "bounds",
    "spin": "bounds that free one rotation component",
    "cone": "a cone around an axis",
}
_NEEDED = {
    "spin": "bounds that free one rotation component and hold the rest at 0 (bounds (0, 0, 0, "
    "0, 0, inf) frees the spin about the target's z axis)",
}


@dataclass(frozen=True)
class SolverSpec:
    """One registered solver. Higher ``priority`` wins under ``solver="auto"``, among the
    solvers that keep the joint limits (``enforces_limits``) first on an arm with a limited
    joint (``choose``)."""

    name: str
    kind: Literal["analytic", "numeric"]
    # True when its own steps keep every answer it claims within the joint limits (a
    # projection, a clip, a 2 pi turn into them, a branch beyond them claimed as such):
    # "auto" takes it, on an arm with a limited joint, before any solver that applies and
    # does not (whatever their priorities); the verdict checks the limits all the same
    enforces_limits: bool
    priority: int
    why_not: WhyNot  # None when the solver applies to the arm and target, else why not
    run: Run
    summary: str
    auto: bool = True  # False keeps a solver (a baseline) out of "auto"
    # False for a search (a grid over one or two joints): it may miss solutions, so a
    # target it finds nothing for is not shown out of reach. "auto" takes such a solver only
    # for every solution (``solve_all``), where its branches are the point; for one answer
    # (``solve``, batches, paths) a numeric solver is faster and misses nothing it could find.
    complete: bool = True
    # Optional: solves many targets without a Python call per target (GIL released).
    # Solvers without it are batched by calling ``run`` per target.
    run_batch: RunBatch | None = None
    # Optional: a runner for one plain pose with everything that does not depend on the
    # target decided once (``armik.solve.prepared``); solvers without it take the general path.
    # Only for solvers whose ``check`` gives one answer for every full pose: the plan is
    # chosen once per arm, name and options, on a representative pose.
    prepare_pose: PreparePose | None = None
    # Optional: its answers at any one value of a joint, and the range to sweep (``Sweep``)
    sweep: Sweep | None = None
    # Optional: its answers at any one value of a parameter an option fixes (``Parameter``)
    parameter: Parameter | None = None
    # The forms of a request beyond an exact full pose it solves (``FORMS``; a closed form:
    # none), and those it needs (the spin sweep: "spin"): the registry refuses the others
    # by name, so ``why_not`` reads the arm and the target only
    solves: frozenset[str] = frozenset(FORMS)
    needs: frozenset[str] = frozenset()
    # The constraint classes beyond the joint limits its own steps keep (a ``Constraint``'s
    # ``box`` rows): "auto" prefers it for a request holding them; the verdict checks them
    # all the same (the module's rule)
    enforces: frozenset[type] = frozenset()

    def keeps(self, kinds: frozenset[type]) -> bool:
        """Whether its own steps keep every constraint class of ``kinds``."""
        return kinds <= self.enforces

    def declines(
        self,
        opts: SolverSettings | None,
        asked: frozenset[str] | None = None,
        target: Target | None = None,
    ) -> str | None:
        """Why this solver does not take these options and this target, by the forms they
        ask (``asked``: ``opts.forms(aimed)``, given where many solvers are asked; else read
        from ``opts`` and whether ``target`` has an aim) against what it declares; else
        None. Whether it applies is this, then its own ``why_not(arm, target, opts)``."""
        if opts is not None:
            if asked is None:
                asked = opts.forms(target is not None and target.aim is not None)
            if not self.needs <= asked:
                return f"{self.name} needs {_needed(min(self.needs - asked))}"
            if not asked <= self.solves:
                form = next(f for f in FORMS if f in asked and f not in self.solves)
                return f"{_ASKED[form]} {_are(form)} for {_solving(form)}"
        elif self.needs:
            return f"{self.name} needs {_needed(min(self.needs))}"
        return None


_REGISTRY: dict[str, SolverSpec] = {}


_BY_PRIORITY: list[SolverSpec] = []
# "auto"'s order on an arm with a limited joint: the solvers keeping the limits first
_LIMITS_KEPT_FIRST: list[SolverSpec] = []
# (position target, options, every, generation) -> spec; read as a key, not called: each solve
_AUTO: Derived[dict] = Derived("auto's choices", lambda _: {})
_NONE: dict = {}  # no choice kept yet (never written: a new dict replaces it)
generation = 0  # counts registrations and removals: what was chosen before may not be now


def register(spec: SolverSpec) -> SolverSpec:
    """Add ``spec`` under its name; ``SolverError`` naming the field for a spec whose fields
    are not what ``SolverSpec`` declares (nothing is registered then), or a name taken."""
    global generation
    _check(spec)
    if spec.name in _REGISTRY or spec.name == "auto":
        raise SolverError(
            f"solver name {spec.name!r} is taken: register it under another name, or "
            "unregister the one there first",
            solver=spec.name,
            candidates=list(_REGISTRY),
        )
    _REGISTRY[spec.name] = spec
    generation += 1
    _order()
    return spec


def _check(spec: object) -> None:
    """``SolverError`` naming the first field of ``spec`` that is not what a ``SolverSpec``
    declares, its value and what it takes: checked before anything is registered."""
    if not isinstance(spec, SolverSpec):
        raise SolverError(
            f"register takes a SolverSpec, got {spec!r}", solver=str(spec), candidates=solvers()
        )
    name = spec.name if isinstance(spec.name, str) else repr(spec.name)
    wrong = _wrong_field(spec)
    if wrong is not None:
        field, takes = wrong
        raise SolverError(
            f"solver {name!r}: SolverSpec.{field} must be {takes}, got "
            f"{getattr(spec, field)!r}; nothing was registered",
            solver=name,
            candidates=solvers(),
        )


def _wrong_field(spec: SolverSpec) -> tuple[str, str] | None:
    """(field, what it takes) of the first field ``spec`` gives wrong, else None."""
    forms = f"a frozenset of {', '.join(map(repr, FORMS))}"
    checks = (
        ("name", "a non-empty str", isinstance(spec.name, str) and spec.name != ""),
        ("kind", "'analytic' or 'numeric'", spec.kind in ("analytic", "numeric")),
        ("enforces_limits", "True or False", isinstance(spec.enforces_limits, bool)),
        ("priority", "an int (higher wins)", _is_int(spec.priority)),
        ("why_not", "a function (arm, target, opts) -> None or why not", callable(spec.why_not)),
        ("run", "a function (arm, target, q0, opts, every) -> Answers", callable(spec.run)),
        ("summary", "a str", isinstance(spec.summary, str)),
        ("auto", "True or False", isinstance(spec.auto, bool)),
        ("complete", "True or False", isinstance(spec.complete, bool)),
        ("run_batch", "None or a function", spec.run_batch is None or callable(spec.run_batch)),
        ("prepare_pose", "None or a function", _optional(spec.prepare_pose)),
        ("solves", forms, _forms(spec.solves)),
        ("needs", forms, _forms(spec.needs)),
        ("enforces", "a frozenset of Constraint classes", _classes(spec.enforces)),
        ("sweep", "None or a registry.Sweep", spec.sweep is None or isinstance(spec.sweep, Sweep)),
        ("parameter", "None or a registry.Parameter", _optional_of(spec.parameter, Parameter)),
    )
    return next(((field, takes) for field, takes, ok in checks if not ok), None)


def _is_int(value: object) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _optional(value: object) -> bool:
    return value is None or callable(value)


def _optional_of(value: object, kind: type) -> bool:
    return value is None or isinstance(value, kind)


def _forms(value: object) -> bool:
    return isinstance(value, frozenset) and all(f in FORMS for f in value)


def _classes(value: object) -> bool:
    return isinstance(value, frozenset) and all(isinstance(c, type) for c in value)


def _order() -> None:
    _BY_PRIORITY[:] = sorted(_REGISTRY.values(), key=lambda s: -s.priority)
    _LIMITS_KEPT_FIRST[:] = sorted(_BY_PRIORITY, key=lambda s: not s.enforces_limits)


def unregister(name: str) -> SolverSpec:
    """Remove solver ``name`` (one a test or a user registered) and return its spec. Counts
    as a registration (``generation``): what "auto" chose and the prepared plans kept
    before are dropped. ``SolverError`` for a name not registered."""
    global generation
    spec = get(name)
    del _REGISTRY[name]
    generation += 1
    _order()
    return spec


def solvers() -> list[str]:
    """Registered solver names, highest priority first."""
    return [s.name for s in _BY_PRIORITY]


def validate_name(name: object) -> None:
    """Raise ``SolverError`` unless ``name`` is a str (a list or None is not a name)."""
    if not isinstance(name, str):
        raise SolverError(
            f"solver must be one name (a str), got {name!r}; registered: "
            f"{listing(solvers())} or 'auto'",
            solver=str(name),
            candidates=solvers(),
        )


def get(name: str) -> SolverSpec:
    """The solver registered as ``name``; ``SolverError`` for an unknown name or a name
    that is not a str (a list of names, None, ...)."""
    validate_name(name)
    try:
        return _REGISTRY[name]
    except KeyError:
        raise SolverError(
            f"unknown solver {name!r}; {did_you_mean(name, solvers())}registered: "
            f"{listing(solvers())} or 'auto'",
            solver=name,
            candidates=solvers(),
        ) from None


def _keeping_first(checks: tuple | None, limited: bool) -> list[SolverSpec]:
    """The solvers in ``choose``'s order for a request holding the constraints ``checks``
    on an arm with a limited joint or not (``limited``): those that keep every class of
    them (``SolverSpec.enforces``) first, then (``limited``) those that keep the joint
    limits (``SolverSpec.enforces_limits``), by priority."""
    order = _LIMITS_KEPT_FIRST if limited else _BY_PRIORITY
    if not checks:
        return order
    kinds = frozenset(type(c) for c in checks)
    return sorted(order, key=lambda s: not s.keeps(kinds))  # stable: the order kept


def why_not(
    name: str, arm: ArmModel, target: Target | None = None, opts: SolverSettings | None = None
) -> str | None:
    """None if solver ``name`` applies, else the check that failed."""
    spec = get(name)
    return spec.declines(opts, target=target) or spec.why_not(arm, target, opts)


def refuse_on_none(name: str, arms: Mapping[str, ArmModel]) -> None:
    """A ``SolverError`` unless solver ``name`` applies to at least one of ``arms`` (by
    name: several chains' starts, where one that takes none of them would be skipped
    without a word); an unknown name too."""
    why = {tip: why_not(name, arm) for tip, arm in arms.items()}
    if why and all(why.values()):
        said = "; ".join(f"{tip}: {w}" for tip, w in why.items())
        raise SolverError(
            f"solver {name!r} applies to no chain of these tips ({said}): it names the "
            "solver each chain starts from; give one that applies to a chain, or 'auto'",
            solver=name,
            candidates=solvers(),
        )


def _needed(form: str) -> str:
    return _NEEDED.get(form, _ASKED.get(form, repr(form)))


def _are(form: str) -> str:
    return "is" if form in ("position_only", "cone") else "are"


def _solving(form: str) -> str:
    """Who solves ``form``: "the numeric solvers (dls, qp)", the others by name before."""
    named = [s.name for s in _BY_PRIORITY if s.auto and form in s.solves]
    numeric = [s.name for s in _BY_PRIORITY if s.auto and form in s.solves and s.kind == "numeric"]
    words = [f"the numeric solvers ({', '.join(numeric)})"] if numeric else []
    words += [n for n in named if n not in numeric]
    return ", ".join(words) if words else "no registered solver"


def sweeps(joint: int = -1) -> list[SolverSpec]:
    """The solvers with a ``Sweep`` (that holds ``joint``, where one is given), highest
    priority first: the caller asks each whether it applies."""
    return [s for s in _BY_PRIORITY if s.sweep is not None and joint in (-1, s.sweep.joint)]


def swept_from(spec: SolverSpec, value: float) -> SolverSpec:
    """``spec`` with its sweep started at ``value`` (a global path's rung; the value an
    argument, never a seed the caller wrote): its ``Sweep.from_value``, or where it declares
    none, its ``run`` from the seed with the joint at ``value``. ``SolverError`` for a
    solver that sweeps no joint."""
    sweep = spec.sweep
    if sweep is None:
        raise SolverError(
            f"solver {spec.name!r} sweeps no joint: a value to sweep from is for "
            f"{listing([s.name for s in sweeps()])}",
            solver=spec.name,
            candidates=solvers(),
        )

    def run(arm: ArmModel, target: Target, seed: np.ndarray, opts: SolverSettings, every: bool):
        if sweep.from_value is not None:
            return sweep.from_value(arm, target, seed, value, opts, every)
        start = np.array(seed, dtype=float)
        start[sweep.joint] = value  # a ``run``'s sweep starts at its seed's value
        return spec.run(arm, target, start, opts, every)

    return dataclasses.replace(spec, run=run)


def declaring(option: str | None = None) -> list[SolverSpec]:
    """The solvers whose ``Parameter`` the option ``option`` fixes (None: any option),
    highest priority first."""
    return [
        s for s in _BY_PRIORITY if s.parameter is not None and option in (None, s.parameter.option)
    ]


def choose(
    name: str,
    arm: ArmModel,
    target: Target | None = None,
    opts: SolverSettings | None = None,
    every: bool = False,
) -> SolverSpec:
    """The solver to run: ``name`` itself (if it applies) or the best one for "auto":
    the applicable solver of highest priority, where a search (``complete=False``) counts
    only with ``every`` (every solution, ``solve_all``), where the options hold
    constraints of the user's own, one that keeps them all (``enforces``) before any other,
    and on an arm with a limited joint, one that keeps the joint limits
    (``enforces_limits``) before one that does not.
    ``SolverError`` when ``name`` is not a registered name (or not a str)."""
    spec: SolverSpec | None
    if not isinstance(name, str) or name != "auto":
        spec = get(name)
        reason = spec.declines(opts, target=target) or spec.why_not(arm, target, opts)
        if reason is not None:
            raise SolverError(
                f"solver {name!r} does not apply to arm {arm.name!r}: {reason}",
                solver=name,
                candidates=solvers(),
            )
        return spec
    # remembered per arm: applicability reads the target only for whether it is a position
    # and has an aim (a cone: a form)
    aimed = target is not None and target.aim is not None
    key: tuple[bool, bool, SolverSettings | None, bool, int] | None
    key = (target is not None and target.rotation is None, aimed, opts, every, generation)
    chosen = arm._derived.get(_AUTO, _NONE)
    try:
        spec = chosen.get(key)
    except TypeError:  # options holding arrays (obstacle shapes): not remembered
        key = spec = None
    if spec is not None:
        return spec
    asked = None if opts is None else opts.forms(aimed)
    checks = None if opts is None else opts.checks
    limited = len(getattr(arm, "bounded", ())) > 0  # a joint with a finite limit
    for spec in _keeping_first(checks, limited):
        if (
            spec.auto
            and (every or spec.complete)
            and spec.declines(opts, asked) is None
            and spec.why_not(arm, target, opts) is None
        ):
            if key is not None:
                if len(chosen) > 64:
                    chosen = {}
                arm._derived[_AUTO] = {**chosen, key: spec}
            return spec
    raise SolverError(
        f"no registered solver applies to arm {arm.name!r}", solver="auto", candidates=solvers()
    )
