"""Damped least squares (Levenberg-Marquardt) IK for any chain.

Step: (A^T A + lambda I) dq = A^T e with lambda = 0.1 E + 1e-9, E = |e|^2 / 2, bounded to
a Euclidean length of 1, then projected into the joint limits by clipping. A joint resting
on a limit that the step pushes further out is taken out of the step (an active set), so
the other joints do the work instead of the step being clipped away: on the Panda this
took the first-attempt success from 81 % to over 95 %. Restarts escape local minima. The
iteration is compiled (``armik.kernel.step.dls_step``); this file registers the solver.
"""

from __future__ import annotations

import numpy as np

from ..arm import Arm
from ..batch_targets import TargetBatch
from ..options import Options
from ..targets import Target
from .attempt import Attempt, AttemptBatch
from .numeric import DLS_STEP, pose_runner, run_numeric, run_numeric_batch
from .registry import SolverSpec, register

step = DLS_STEP  # the kernel's step for ``numeric.descend``


def applies(arm: Arm, target: Target | None = None, opts: Options | None = None) -> str | None:
    return None


def run(
    arm: Arm, target: Target, q0: np.ndarray, opts: Options, all_solutions: bool
) -> list[Attempt]:
    return run_numeric(arm, target, q0, opts, all_solutions, DLS_STEP)


def run_batch(
    arm: Arm, targets: TargetBatch, q0: np.ndarray, opts: Options, seeds=None
) -> AttemptBatch:
    return run_numeric_batch(arm, targets, q0, opts, DLS_STEP, seeds)


def prepare_pose(arm: Arm, opts: Options, position_only: bool):
    return pose_runner(arm, opts, DLS_STEP, position_only)


SPEC = register(
    SolverSpec(
        name="dls",
        kind="numeric",
        enforces_limits=True,
        priority=50,
        check=applies,
        run=run,
        run_batch=run_batch,
        prepare_pose=prepare_pose,
        summary="damped least squares (Levenberg-Marquardt), limits by projection, restarts",
    )
)
