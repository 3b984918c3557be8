"""Where each branch of a 7R arm's self-motion lies within the joint limits: for one target,
the intervals of the parameter that fixes the self-motion, branch by branch.

The parameter is one a solver declares: a joint its closed form holds (``Sweep``: the
Panda's joint 7, ``hold=``) or an option (``Parameter``: ``swivel=`` on an SRS arm such as
the KUKA iiwa). At one value the closed form gives every branch (up to 8, each labelled);
a branch is admissible there when the closed form reaches the target exactly on it and
every joint lies within its limits. ``intervals`` samples the parameter's range at
``SAMPLES`` values and refines each edge by bisection to ``EDGE_TOL``: a sampled answer,
not a proof, so a stretch narrower than a sample's width (``Intervals.step``) can be
missed. The answers at any value in an interval come from ``solve_all(T, swivel=value)``
or ``solve_all(T, hold={joint: value})``, each verified by forward kinematics. The swivel
angle is on the circle: a span that ends at pi goes on from -pi.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from armik.errors import JointError, OptionError, listing
from armik.model.arm_model import ArmModel
from armik.solvers import registry
from armik.targets.pose import Target, parsed
from armik.tolerances import LIMIT_TOL

SAMPLES = 720  # values over the range: a step of 0.5 degrees on the full circle
EDGE_TOL = 1e-9  # rad (or m): an edge refined by bisection to this


@dataclass(frozen=True)
class Intervals:
    """Each branch's admissible intervals (``branches``: label -> ((lower, upper), ...),
    in rad or m, sorted) of the parameter ``over`` (an option such as "swivel", or a
    joint's name) over the range [``low``, ``high``] sampled every ``step``; ``solver`` the
    closed form that gave them."""

    over: str
    solver: str
    branches: dict[str, tuple[tuple[float, float], ...]]
    low: float
    high: float
    step: float

    def at(self, value: float) -> list[str]:
        """The branches admissible at ``value``."""
        return [
            b for b, spans in self.branches.items() if any(lo <= value <= hi for lo, hi in spans)
        ]


def intervals(arm: ArmModel, target: object, over: str, q0: object = None) -> Intervals:
    """Every branch's admissible intervals of ``over`` for ``target`` (see the module);
    ``q0`` centres a joint without limits. ``OptionError`` naming what the arm can be
    swept over when no solver of ``over`` applies to it and the target."""
    tgt = parsed(target, arm)
    seed = arm.seed(q0)
    spec, at_value, lo, hi = _parameter(arm, tgt, over, seed)

    def admissible(value: float) -> set[str]:
        answers = at_value(arm, tgt, seed, value)
        inside = ((answers.q >= arm.lower - LIMIT_TOL) & (answers.q <= arm.upper + LIMIT_TOL)).all(
            1
        )
        labels = answers.branch or ()
        return {labels[i] for i in np.flatnonzero(inside) if answers.claimed(int(i))}

    values = np.linspace(lo, hi, SAMPLES + 1)
    found = [admissible(float(v)) for v in values]
    branches: dict[str, list[tuple[float, float]]] = {}
    for label in sorted(set().union(*found)):
        inside = [label in f for f in found]
        spans = []
        k = 0
        while k < len(values):
            if not inside[k]:
                k += 1
                continue
            start = k
            while k + 1 < len(values) and inside[k + 1]:
                k += 1
            a = lo if start == 0 else _edge(admissible, label, values[start - 1], values[start])
            b = hi if k == len(values) - 1 else _edge(admissible, label, values[k + 1], values[k])
            spans.append((a, b))
            k += 1
        branches[label] = spans
    step = (hi - lo) / SAMPLES
    found_spans = {b: tuple(s) for b, s in branches.items()}
    return Intervals(over, spec.name, found_spans, lo, hi, step)


def _edge(admissible: Callable[[float], set[str]], label: str, out: float, inside: float) -> float:
    """The edge between a value where ``label`` is not admissible and one where it is, by
    bisection: the last admissible value found."""
    out, inside = float(out), float(inside)
    while abs(inside - out) > EDGE_TOL:
        middle = 0.5 * (out + inside)
        if label in admissible(middle):
            inside = middle
        else:
            out = middle
    return inside


def _parameter(arm: ArmModel, tgt: Target, over: str, seed: np.ndarray):
    """(spec, at_value, lower, upper): the solver that answers at one value of ``over``
    and the range to sample (``over`` a name: None would match any option)."""
    if not isinstance(over, str):
        raise OptionError(
            f"over must be the name of what to sweep (an option such as 'swivel', or a "
            f"joint's name), got {over!r}",
            option="over",
            value=over,
        )
    for spec in registry.declaring(over):
        if spec.parameter is not None and spec.why_not(arm, tgt, None) is None:
            return spec, spec.parameter.at_value, -math.pi, math.pi
    if over in arm.joint_names:
        k = arm.joint_names.index(over)
        for spec in registry.sweeps(k):
            if spec.sweep is not None and spec.why_not(arm, tgt, None) is None:
                lo, hi = spec.sweep.range(arm, float(seed[k]))
                return spec, spec.sweep.at_value, float(lo), float(hi)
    known = {s.parameter.option for s in registry.declaring()}  # type: ignore[union-attr]
    if over not in arm.joint_names and over not in known:
        raise JointError(
            f"intervals: unknown joint {over!r} of arm {arm.name!r}; its joints: "
            f"{listing(arm.joint_names)}; or an option: {listing(sorted(known)) or 'none'}",
            joint=over,
            candidates=arm.joint_names,
        )
    options = [
        s.parameter.option  # type: ignore[union-attr]
        for s in registry.declaring()
        if s.why_not(arm, tgt, None) is None
    ]
    joints = [
        arm.joint_names[s.sweep.joint]  # type: ignore[union-attr]
        for s in registry.sweeps()
        if s.why_not(arm, tgt, None) is None
    ]
    raise OptionError(
        f"no closed form of arm {arm.name!r} answers at one value of {over!r} for this "
        f"target; it can be swept over: {listing([*options, *joints]) or 'nothing'} "
        "(an SRS arm's swivel, or the joint a swept closed form holds)",
        option="over",
        value=over,
    )
