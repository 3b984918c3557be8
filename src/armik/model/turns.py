"""A configuration's turns: each revolute joint's value and the values 2 pi away from it
within its limits. Every turn of an answer reaches the same pose; which one stands for it
is the caller's choice (nearest q0, a preference's best, one that passes a check)."""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel

TWO_PI = 2.0 * math.pi
MAX_TURNS = 256  # combinations of the joints' turns at most, the configuration itself first
UNLIMITED_TURNS = 2  # a continuous joint's turns tried (for a check, a score): up to 2 each way


def turns(
    arm: ArmModel, q: np.ndarray, free: np.ndarray | None = None, unlimited: int = 0
) -> list[list[float]]:
    """Per joint: its value and the values 2 pi turns away within its limits, on the
    revolute joints whose limits span more than one turn (``free``: only those joints);
    a joint without limits (continuous) turned by up to ``unlimited`` turns each way."""
    lower, upper, no_period = arm._limit_lists  # no period: prismatic, or a mimic's driver
    may = [True] * arm.dof if free is None else free.tolist()
    choices = []
    for qi, lo, hi, linear, m in zip(q.tolist(), lower, upper, no_period, may):
        values = [qi]
        if m and not linear and math.isfinite(lo) and math.isfinite(hi) and hi - lo > TWO_PI:
            k_lo, k_hi = math.ceil((lo - qi) / TWO_PI), math.floor((hi - qi) / TWO_PI)
            values += [qi + k * TWO_PI for k in range(k_lo, k_hi + 1) if k != 0]
        elif m and not linear and unlimited and lo == -math.inf and hi == math.inf:
            values += [qi + k * TWO_PI for k in range(-unlimited, unlimited + 1) if k != 0]
        choices.append(values)
    return choices


def combinations(choices: list[list[float]]) -> np.ndarray:
    """(M, dof): the combinations of the joints' ``choices``, the first of each first (the
    configuration itself), at most ``MAX_TURNS``."""
    return np.array(list(itertools.islice(itertools.product(*choices), MAX_TURNS)))
