"""The solver "auto" chooses for a batch or a path, kept per arm (``chosen``), and the
target of the kind and aim that choice reads (``kind_of``): what every target of a plan
(``armik.solve.prepared``), a batch or a path has in common."""

from __future__ import annotations

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.solvers import registry
from armik.targets.aim import Aim
from armik.targets.pose import Target


def chosen(arm: ArmModel, solver: str, key: tuple | None, opts, position: bool | None, aim=None):
    """The solver ``registry.choose`` gives for ``opts`` (all but ``seed``; ``key``: their
    request's, which holds the shape of an aim) and a target of that kind (``position``;
    None: no target) with ``aim``, "auto"'s kept per arm under ``key`` as a plan is (None:
    chosen every time): a batch's or a path's."""
    kind = None if position is None else _KIND[position] if aim is None else kind_of(position, aim)
    if key is None or solver != "auto":  # a solver named: looked up by its name
        return registry.choose(solver, arm, kind, opts)
    kept = arm._derived.get(_CHOSEN)  # read as a dict, not through a call: every batch
    if kept is None or kept["generation"] != registry.generation:
        kept = arm._derived[_CHOSEN] = {"generation": registry.generation}
    spec = kept.get((key, position))
    if spec is None:
        spec = registry.choose(solver, arm, kind, opts)
        if len(kept) > 64:
            kept = arm._derived[_CHOSEN] = {"generation": registry.generation}
        kept[(key, position)] = spec
    return spec


_CHOSEN: Derived[dict] = Derived("auto's choices", lambda _: {})
# a target of each kind (True: a position) without an aim: what the registry's choice reads
_KIND = {True: Target(np.zeros(3)), False: Target(np.zeros(3), np.eye(3))}


def kind_of(position: bool, aim: Aim | None = None) -> Target:
    """A target of the kind and aim every target of a plan or a batch has."""
    return Target(np.zeros(3), None if position else np.eye(3), aim=aim)
