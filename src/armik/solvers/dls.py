"""Damped least squares (Levenberg-Marquardt) IK for any chain.

Step: (A^T A + lambda I) dq = A^T e with lambda = E + 1e-9, E = |e|^2 / 2 (see
``numeric.dls_step``), bounded to ``numeric.MAX_STEP``, then projected into the joint
limits by clipping. Restarts from random configurations escape local minima.
"""

from __future__ import annotations

import numpy as np

from ..arm import Arm
from ..options import Options
from ..targets import Target
from .base import Attempt
from .numeric import Problem, State, bound_step, dls_step, run_numeric
from .registry import SolverSpec, register


def step(pb: Problem, s: State) -> np.ndarray:
    return bound_step(dls_step(pb, s))


def applies(arm: Arm, target: Target | None = None, opts: Options | None = None) -> str | None:
    return None


def run(arm: Arm, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
        ) -> list[Attempt]:
    return run_numeric(arm, target, q0, opts, all_solutions, step)


SPEC = register(SolverSpec(
    name="dls", kind="numeric", enforces_limits=True, priority=50, check=applies, run=run,
    summary="damped least squares (Levenberg-Marquardt), limits by projection, restarts"))
