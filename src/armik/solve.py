"""The one path from user input to verified results, shared by every solver."""

from __future__ import annotations

import time

from .arm import Arm
from .ik import registry
from .options import Options
from .plan import plan_for
from .result import IKResult
from .targets import parse_target
from .verdict import finish


def solve(
    arm: Arm,
    target: object,
    *,
    q0: object = None,
    solver: str = "auto",
    all_solutions: bool = False,
    **options: object,
) -> list[IKResult]:
    """Parse, choose a solver, run it, verify every answer, rank: best first."""
    t0 = time.perf_counter()
    opts, key = _options(options)
    if key is not None:
        plan = plan_for(arm, solver, key, opts)
        if plan is not None:
            if all_solutions:
                results = plan.solve_all(target, q0, opts, t0)
                if results is not None:
                    return results
            else:
                result = plan.solve(target, q0, opts, t0)
                if result is not None:
                    return [result]
    tgt = parse_target(target, arm)
    seed = arm.seed(q0)
    spec = registry.choose(solver, arm, tgt, opts)
    attempts = spec.run(arm, tgt, seed, opts, all_solutions)
    return finish(arm, spec.name, attempts, tgt, opts, seed, all_solutions, t0)


_OPTIONS: dict[tuple, Options] = {}


def _options(kwargs: dict) -> tuple[Options, tuple | None]:
    """``Options.from_kwargs`` and the key it is remembered under (None: not remembered),
    for hashable option values other than ``seed`` (validation costs a few us, and a loop
    of solves passes the same options, often with a new seed each time)."""
    if not kwargs:
        return _DEFAULT, ()
    seed = kwargs.get("seed", 0)
    try:
        # with the types: 1 == True, but validation may accept one and refuse the other
        key = tuple((k, type(v), v) for k, v in kwargs.items() if k != "seed")
        opts = _OPTIONS.get(key)
    except TypeError:  # an unhashable value (a list of weights): validate every time
        return Options.from_kwargs(kwargs), None
    if opts is None:
        opts = Options.from_kwargs(kwargs)
        if len(_OPTIONS) > 256:
            _OPTIONS.clear()
        _OPTIONS[key] = opts
    elif opts.seed != seed or type(opts.seed) is not type(seed):
        # the seed's own validation, as Options.from_kwargs does it; then a copy of the
        # remembered options with that seed (copy.copy and the frozen __init__ cost us)
        if type(seed) is int and seed >= 0:
            checked = seed  # what the validation returns for a plain int
        else:
            checked = None if seed is None else Options.from_kwargs({"seed": seed}).seed
        fields = opts.__dict__.copy()
        fields["seed"] = checked
        opts = object.__new__(Options)
        opts.__dict__.update(fields)
    return opts, key


_DEFAULT = Options()  # frozen: shared by every call without options
