"""Random 6R arms of every family for the tests: the generator is
``armik.model.random_arms`` (the benchmarks use it too); this module loads them and holds
the checks the family tests share."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik
from armik.model.random_arms import KINDS, random_axes, random_urdf, urdf_text

__all__ = ["KINDS", "random_axes", "random_urdf", "urdf_text", "random_arm", "load_arm"]


def random_arm(kind: str, rng: np.random.Generator):
    """Axis lines (points, directions) of a random arm of ``kind``."""
    return random_axes(kind, rng)


def load_arm(kind: str, rng: np.random.Generator, c=None, h=None) -> armik.Arm:
    """A random arm of ``kind`` loaded from its URDF (``c``, ``h``: given axis lines)."""
    text = random_urdf(kind, rng) if c is None else urdf_text(c, h, rng)
    return armik.load_string(text, base="world", tip="tool")


def wrapped_distance(a: np.ndarray, b: np.ndarray) -> float:
    """The largest joint difference of ``a`` and ``b`` modulo 2 pi (rad)."""
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def check_round_trips(arm: armik.Arm, solver: str, rng, n: int, misses: list | None = None) -> int:
    """Solve ``n`` targets of random configurations with ``solve_all``: every success is
    within the limits and reaches the target (Pinocchio's FK); the generating configuration
    is among them unless an answer is singular (or, with a list ``misses``, the
    configurations not found are appended to it instead). Returns how many were checked
    completely."""
    checked = 0
    for _ in range(n):
        q = arm.random_q(rng)
        T = arm.fk(q)
        results = arm.solve_all(T, solver=solver)
        assert results and results[0].solver == solver
        for r in results:
            if r.success:
                err = pin.log6(arm.fk(r.q).inverse() * T).vector
                assert np.linalg.norm(err) < 1e-9
                assert np.all(r.q >= arm.lower - 1e-12) and np.all(r.q <= arm.upper + 1e-12)
        if any(r.singular for r in results):
            continue
        best = min((wrapped_distance(r.q, q) for r in results if r.success), default=np.inf)
        if misses is not None and best >= 1e-6:
            misses.append(q)
            continue
        assert best < 1e-6, (solver, q.tolist())
        checked += 1
    return checked
