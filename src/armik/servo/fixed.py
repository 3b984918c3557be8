"""The directions in which an arm never moves or turns its tip, at any joint values: a
planar arm's tip never leaves its plane (the normal) nor tilts out of it (the two axes in
the plane), so a task's row along them is zero at every q and not one the arm can follow.

The servo's singular value counts every row the task asks for, zero at this q or not (a
stretched arm's row along its line is the singularity itself), but these
(``armik.servo.tick``'s ``stack``): else a planar arm asked for a position would read as
singular everywhere. Found once, when a servo starts, from the base-frame Jacobian at a
few joint values spread over the limits: the directions no column of any of them reaches.
"""

from __future__ import annotations

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.derived import Derived

SAMPLES = 16  # joint values (besides the middle): a direction reached at one q is at most
RELATIVE = 1e-9  # a singular value of the stacked columns below this share of the largest


def never_moved(arm: ArmModel) -> np.ndarray:
    """(2, 3, 3): the projectors onto the base frame's directions in which ``arm`` never
    moves its tip (linear) and never turns it (angular), zero for a spatial arm."""
    return _FOUND(arm)[0].copy()


def structural_ranks(arm: ArmModel) -> np.ndarray:
    """(3,) floats: the ranks of the tip's base-frame Jacobian at joint values where it is
    of full rank (the largest over the same samples as ``never_moved``): of its linear
    rows, its angular rows and the six. A tip on a joint's axis never moves along it:
    the Panda's ``panda_link4`` moves on a sphere around the shoulder, its position rows of
    rank 2 at every q, so the smallest of three singular values is always zero and a
    singularity is read off the rank-th (``armik.servo.tick.rank_bound``)."""
    return _FOUND(arm)[1].copy()


def _found(arm: ArmModel) -> tuple[np.ndarray, np.ndarray]:
    """(``never_moved``, ``structural_ranks``), from one sampling of the tip's Jacobian,
    kept with the arm (each servo started on it reads them)."""
    qs = [arm.middle, *arm.random_q(np.random.default_rng(0), SAMPLES)]
    Js = [arm.jacobian(q, "base") for q in qs]
    J = np.hstack(Js)
    fixed = np.stack([_left_null(J[:3]), _left_null(J[3:])])
    ranks = np.zeros(3)
    for Jq in Js:
        for i, M in enumerate((Jq[:3], Jq[3:], Jq)):
            ranks[i] = max(ranks[i], _rank(M))
    return fixed, ranks


_FOUND: Derived[tuple] = Derived(
    "the directions a tip never moves in, its Jacobian's ranks", _found
)


def _left_null(M: np.ndarray) -> np.ndarray:
    """The projector onto the directions that no column of M reaches."""
    U, s, _ = np.linalg.svd(M, full_matrices=True)
    top = s.max() if s.size else 0.0
    rank = int((s > RELATIVE * max(top, 1.0)).sum())
    N = U[:, rank:]
    return N @ N.T


def _rank(M: np.ndarray) -> int:
    """M's rank: its singular values above ``RELATIVE`` of the largest (or of 1)."""
    s = np.linalg.svd(M, compute_uv=False)
    top = s.max() if s.size else 0.0
    return int((s > RELATIVE * max(top, 1.0)).sum())
