"""What ``armik info`` says of the routes an arm's solves take: a 6R arm's family, for a
7R arm the family each held joint leaves (``hold=``), and which solver ``solve`` and
``solve_all`` run and why (the closed form that applies, or the reason none does)."""

from __future__ import annotations

import math

from armik.model.arm_model import ArmModel
from armik.solvers import registry
from armik.solvers.closed_form import families, srs
from armik.solvers.closed_form.sixr import Chain6R
from armik.solvers.closed_form.swept_7r import SPEC as SWEPT
from armik.solvers.registry import SolverSpec


def six_r_family(arm: ArmModel) -> str | None:
    """The family of a 6R arm: the first closed-form family that fits it (the elimination
    fits every arm no Pieper family does), else the first search; None for an arm that is
    not 6R (all revolute)."""
    found = families.classify(arm)
    general = found.get("general_6r")
    if not isinstance(general, Chain6R):  # the reason it does not apply
        return None
    fits = [(n, g) for n, g in found.items() if n != "planar" and not isinstance(g, str)]
    # a closed form before a search, as "auto" chooses for every solution
    name, geo = min(fits, key=lambda f: f[0] in SEARCHES)
    return f"{name} ({getattr(geo, 'description', name)})"


def held_value(arm: ArmModel, k: int) -> float:
    """A value to hold joint ``k`` at that is no special angle (the classes do not change
    with it, but a value such as 0 can line axes up by chance)."""
    lo, hi = float(arm.lower[k]), float(arm.upper[k])
    if math.isfinite(lo) and math.isfinite(hi):
        return lo + 0.37 * (hi - lo)
    return 0.37


def family_lines(arm: ArmModel) -> list[str]:
    """``armik info``'s family lines: a 6R arm's family; for a 7R arm, the family of the
    6R chain left by holding each joint (``hold=``), and which joints make it analytic."""
    family = six_r_family(arm)
    if family is not None:
        return [f"family: {family}"]
    if arm.dof != 7 or any(t == "prismatic" for t in arm.joint_types):
        return []
    lines = ["hold one joint (hold={name: value}) and the other six are:"]
    analytic = []
    for k, name in enumerate(arm.joint_names):
        if k == 6 and not isinstance(families.classify(arm)["swept_7r"], str):
            text = "swept_7r (the swept solver's closed form: joints 6 to 1 read from the tip)"
        else:
            text = six_r_family(arm.with_locked({name: held_value(arm, k)})) or "not a 6R chain"
        if _closed(text):
            analytic.append(name)
        lines.append(f"  {name:<24} {text}")
    which = ", ".join(analytic) if analytic else "none (each leaves a search)"
    lines.append(f"  analytic with one joint held: {which}")
    return lines


# the solvers that search a grid over one or two joints (the elimination and the closed
# forms solve in closed form: polynomial roots)
SEARCHES = ("two_parallel", "two_intersecting", "general_6r", "swept")


def _closed(family: str) -> bool:
    """Whether a held joint's family (``six_r_family``'s words) is solved in closed form,
    not by a search; "not a 6R chain" is no family."""
    return family != "not a 6R chain" and family.split(" ", 1)[0] not in SEARCHES


def _kind(spec: SolverSpec) -> str:
    if spec.kind == "numeric":
        return "numeric"
    return "a search" if spec.name in SEARCHES else "closed form"


def _why(arm: ArmModel, spec: SolverSpec) -> str:
    """Why "auto" runs ``spec`` on ``arm``: its geometry, or why no closed form applies."""
    if spec.name == srs.SPEC.name:
        geo = srs.geometry(arm)
        return "SRS, " + getattr(geo, "description", str(geo))
    if spec.kind == "analytic":
        return spec.summary
    if arm.dof != 7 or any(t == "prismatic" for t in arm.joint_types):
        return "no closed form applies to the whole chain (structure above)"
    swept = SWEPT.why_not(arm, None, None)
    swept_said = (
        f'the swept closed form (joint 7 swept) applies, only when asked: solver="{SWEPT.name}"'
        if swept is None
        else f"not swept_7r: {swept}"
    )
    return f"not SRS: {srs.applies(arm)}; {swept_said}"


def route_lines(arm: ArmModel) -> list[str]:
    """``armik info``'s route lines: what ``solve`` and ``solve_all`` run under "auto" and
    why, and on a 7R arm how to fix its self-motion (``swivel=``, ``hold=``)."""
    one = registry.choose("auto", arm)
    every = registry.choose("auto", arm, every=True)
    lines = ["route:"]
    said = [("solve", one), ("solve_all", every)] if one is not every else [("solve(_all)", one)]
    for label, spec in said:
        lines.append(f"  {label:<11} -> {spec.name} ({_kind(spec)}): {_why(arm, spec)}")
    if arm.dof != 7 or any(t == "prismatic" for t in arm.joint_types):
        return lines
    if srs.applies(arm) is None:
        lines.append(
            "  swivel=PSI  -> srs (closed form): every branch (up to 8) at that elbow swivel "
            "angle (rad); without it, q0's angle, then swept round the circle"
        )
    lines.append("  hold=       -> the six joints left, as listed above, at exactly that value")
    return lines
