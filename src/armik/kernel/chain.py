"""The kernel's view of an arm: plain arrays read once from the reduced Pinocchio model.

Joint values are the user's (one per joint: rad or m); a continuous joint is one angle,
not Pinocchio's (cos, sin) pair. The chain has N physical joints and n <= N driving ones,
the joint values q (n,): physical joint i takes the value
``multiplier[i] * q[driver[i]] + offset[i]`` (a URDF mimic joint follows its driver; every
other joint is its own driver with multiplier 1 and offset 0, which gives q[i] exactly).
Frames: physical joint i is placed in joint i - 1 by
``joint_R[i], joint_p[i]`` (joint 0 in the arm's base frame: the base transform is folded
in), turns about or slides along ``axis[i]`` (unit, in its own frame), and the tip frame is
placed in the last joint by ``tip_R, tip_p``. The kernel's FK is therefore ``T_base_tip``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import NamedTuple

import numpy as np
from numba import njit

REVOLUTE, PRISMATIC, CONTINUOUS = 0, 1, 2
HALTON_POINTS = 512  # restart seeds cycle through this many points of the sequence
_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)


class Chain(NamedTuple):
    """Plain arrays describing a serial chain (see the module docstring)."""

    joint_R: np.ndarray  # (N, 3, 3)
    joint_p: np.ndarray  # (N, 3) m
    axis: np.ndarray  # (N, 3) unit
    kind: np.ndarray  # (n,) int64: REVOLUTE, PRISMATIC or CONTINUOUS per driving joint (a
    # driver of mimic joints: PRISMATIC, never shifted by 2 pi; see ``armik.model.chain_arrays``)
    tip_R: np.ndarray  # (3, 3)
    tip_p: np.ndarray  # (3,) m
    lower: np.ndarray  # (n,) rad or m, -inf where unlimited
    upper: np.ndarray  # (n,)
    sample_lo: np.ndarray  # (n,) the restart box: the limits, [-pi, pi] where unlimited
    sample_span: np.ndarray  # (n,)
    halton: np.ndarray  # (HALTON_POINTS, n) in [0, 1)
    origin: np.ndarray  # (3,) first joint's origin in the base frame (m)
    reach: float  # upper bound on the distance from ``origin`` to the tip (m)
    base_R: np.ndarray  # (3, 3) T_base_world: the base frame's placement inverted
    base_p: np.ndarray  # (3,) m
    joint_kind: np.ndarray  # (N,) int64: the kind of each physical joint
    driver: np.ndarray  # (N,) int64: the index in q of the joint that drives it
    multiplier: np.ndarray  # (N,)
    offset: np.ndarray  # (N,) rad or m


@dataclass(frozen=True, eq=False)
class KernelChain:
    """An arm's ``Chain`` (for Python readers) and its ``Flat`` form (for compiled code;
    compiled entries take the flat arrays one by one, because numba unboxes a tuple argument
    from Python ten times slower than a few arrays)."""

    chain: Chain
    flat: Flat

    @property
    def packed(self) -> np.ndarray:
        return self.flat.packed

    @property
    def kind(self) -> np.ndarray:
        """The driving joints' kinds (n,)."""
        return self.chain.kind

    @property
    def halton(self) -> np.ndarray:
        return self.flat.halton


def flatten(ch: Chain) -> np.ndarray:
    """The float fields of ``ch`` in one array, in ``unpack``'s order."""
    parts = [ch.joint_R, ch.joint_p, ch.axis, ch.tip_R, ch.tip_p, ch.lower, ch.upper]
    parts += [ch.sample_lo, ch.sample_span, ch.origin, np.array([ch.reach]), ch.base_R, ch.base_p]
    parts += [ch.multiplier, ch.offset]
    return np.concatenate([np.ravel(x) for x in parts]).astype(np.float64)


def flat_kinds(ch: Chain) -> np.ndarray:
    """``Flat.kind``: the driving joints' kinds (n), the physical joints' (N), their
    drivers (N)."""
    return np.concatenate([ch.kind, ch.joint_kind, ch.driver]).astype(np.int64)


class Flat(NamedTuple):
    """The chain as compiled code sees it: ``flatten``'s array, ``flat_kinds``' array and
    the restart table (n columns: the number of driving joints). Three arrays: numba's
    compile time grows with the arrays a tuple argument holds."""

    packed: np.ndarray
    kind: np.ndarray
    halton: np.ndarray


@njit(cache=True, nogil=True, inline="always")
def dof(ch):
    """n, the number of driving joints (joint values)."""
    return ch.halton.shape[1]


@njit(cache=True, nogil=True, inline="always")
def joints(ch):
    """N, the number of physical joints."""
    return (ch.kind.shape[0] - ch.halton.shape[1]) // 2


# Offsets into ``packed`` for a chain of N physical joints (see ``flatten``).
@njit(cache=True, nogil=True, inline="always")
def off_joint_p(N):
    return 9 * N


@njit(cache=True, nogil=True, inline="always")
def off_axis(N):
    return 12 * N


@njit(cache=True, nogil=True, inline="always")
def off_tip(N):
    return 15 * N


@njit(cache=True, nogil=True, inline="always")
def off_mimic(N, n):
    """Where the multipliers start (N of them, then N offsets)."""
    return 15 * N + 4 * n + 28


@njit(cache=True, nogil=True, inline="always")
def lower(ch):
    n, o = dof(ch), 15 * joints(ch) + 12
    return ch.packed[o : o + n]


@njit(cache=True, nogil=True, inline="always")
def upper(ch):
    n, o = dof(ch), 15 * joints(ch) + 12
    return ch.packed[o + n : o + 2 * n]


@njit(cache=True, nogil=True, inline="always")
def sample_box(ch):
    """(lower corner, span) of the restart box."""
    n, o = dof(ch), 15 * joints(ch) + 12
    return ch.packed[o + 2 * n : o + 3 * n], ch.packed[o + 3 * n : o + 4 * n]


@njit(cache=True, nogil=True, inline="always")
def reach(ch):
    """(first joint's origin in the base frame, reach bound) (m)."""
    o = 15 * joints(ch) + 12 + 4 * dof(ch)
    return ch.packed[o : o + 3], ch.packed[o + 3]


@cache
def halton(dim: int, n: int = HALTON_POINTS) -> np.ndarray:
    """The first n points of the dim-dimensional Halton sequence, in [0, 1)^dim (beyond 12
    dimensions: fixed pseudo-random points)."""
    if dim > len(_PRIMES):
        table = np.random.default_rng(0).random((n, dim))
    else:
        table = np.zeros((n, dim))
        for j, base in enumerate(_PRIMES[:dim]):
            k = np.arange(1, n + 1)
            f = 1.0
            while k.any():  # radical inverse, one digit of all n indices at a time
                f /= base
                table[:, j] += f * (k % base)
                k //= base
    table.setflags(write=False)
    return table
