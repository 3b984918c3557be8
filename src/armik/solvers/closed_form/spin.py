"""A closed form over a free or bounded spin: the target's bounds hold its position and two
of its rotation components exactly and free the third (a suction cup, a drill: the spin
about the tool axis does not matter), so the arm's closed form solves each pose of a sweep
of that angle, and the admissible answer nearest q0 over the whole swept range is kept, not
the nearest local one as a numeric solver would.

A sweep, not a proof: an admissible window narrower than its grid (5 degrees) can be
missed, so ``auto`` takes it only for every solution (``solve_all``); ``solver="spin"``
asks for it for one answer. ``solve`` returns the answer nearest q0 over the range (the
grid's best, refined by Brent's method); ``solve_all`` returns, for each branch of the
closed form, that branch's answer nearest q0 over the range (a label the closed form gives
twice at one spin is two branches: its nearest answer and the other).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin

from armik.errors import SolverError
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings, spin_of
from armik.solvers import registry
from armik.solvers.answers import Answers, one, stacked
from armik.status import Status
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target

STEP = math.radians(5.0)  # rad between samples of the spin
XATOL = 1e-10  # rad: Brent's tolerance on the refined angle
AXES = "xyz"
FAR = 1e6  # the refined distance where a spin has no admissible answer (Brent's needs finite)


def nearest_spin(R: np.ndarray, near: np.ndarray, k: int) -> tuple[np.ndarray, float]:
    """(``R`` turned about its own axis ``k``, the angle): the rotation nearest ``near``
    over that spin (the angle maximises the trace of ``near^T R R_k``)."""
    M = R.T @ near  # ``near`` in R's frame
    i, j = (k + 1) % 3, (k + 2) % 3
    theta = math.atan2(M[j, i] - M[i, j], M[i, i] + M[j, j])
    return np.asarray(R @ pin.exp3(theta * np.eye(3)[k])), theta


def family(arm: ArmModel, target: Target | None) -> registry.SolverSpec | str:
    """The complete closed form that solves the arm's exact poses, or why there is none."""
    try:
        spec = registry.choose("auto", arm, target, None)
    except SolverError as error:
        return str(error)
    if spec.kind != "analytic" or not spec.complete:
        return f"no complete closed form solves this arm's poses ('auto' takes {spec.name!r})"
    return spec


def applies(arm: ArmModel, target: Target | None = None, _opts: object = None) -> str | None:
    if target is not None and target.rotation is None:
        return "a position target has no spin to sweep: the sweep needs a full pose"
    spec = family(arm, target)
    return spec if isinstance(spec, str) else None


def _turned(target: Target, k: int, thetas: np.ndarray) -> TargetBatch:
    """The target turned by each angle about its own axis k."""
    axis = np.zeros(3)
    axis[k] = 1.0
    R = np.array([target.rotation @ pin.exp3(axis * t) for t in thetas])
    return TargetBatch(np.tile(target.position, (len(thetas), 1)), R)


def run(
    arm: ArmModel, target: Target, q0: np.ndarray, opts: SolverSettings, all_solutions: bool
) -> Answers:
    k, half = spin_of(opts.bounds)  # type: ignore[misc]  # applies() checked it
    spec = family(arm, target)
    assert not isinstance(spec, str)  # applies() checked it
    plain = dataclasses.replace(opts, bounds=None)
    n = max(3, math.ceil(2.0 * half / STEP) + 1)
    thetas = np.linspace(-half, half, n, endpoint=half < math.pi)
    if all_solutions:
        return _every_branch(arm, spec, target, q0, plain, k, half, thetas)
    return _nearest(arm, spec, target, q0, plain, k, half, thetas)


def _distances(arm: ArmModel, spec, target: Target, q0: np.ndarray, opts, k, thetas):
    """(answers, distances): the closed form's answer nearest q0 at each angle and its
    distance to q0 (inf where it is not exact within the limits)."""
    q0s = np.ascontiguousarray(np.broadcast_to(q0, (len(thetas), arm.dof)))
    got = spec.run_batch(arm, _turned(target, k, thetas), q0s, opts)
    d = np.linalg.norm(got.q - q0, axis=1)
    admissible = (got.claim == Status.CONVERGED.code) & np.array(
        [arm.within_limits(q) for q in got.q]
    )
    return got.q, np.where(admissible, d, np.inf)


def _bracket(thetas: np.ndarray, i: int, half: float) -> tuple[float, float]:
    """The interval around sample i to refine in (a full turn wraps around)."""
    step = thetas[1] - thetas[0]
    lo, hi = thetas[i] - step, thetas[i] + step
    return (lo, hi) if half >= math.pi else (max(lo, -half), min(hi, half))


def _nearest(arm, spec, target, q0, opts, k, half, thetas) -> Answers:
    Q, d = _distances(arm, spec, target, q0, opts, k, thetas)
    i = int(np.argmin(d))
    if not math.isfinite(d[i]):
        return _missed(q0, k, len(thetas))

    def f(t: float) -> float:
        return min(float(_distances(arm, spec, target, q0, opts, k, np.array([t]))[1][0]), FAR)

    best = _brent(f, _bracket(thetas, i, half))
    theta = float(best.x) if best.fun < d[i] else float(thetas[i])
    Q1, d1 = _distances(arm, spec, target, q0, opts, k, np.array([theta]))
    return _found(Q1[0], k, theta, spec.name)


def _every_branch(arm, spec, target, q0, opts, k, half, thetas) -> Answers:
    """Each branch's answer nearest q0 over the range (branches by the closed form's
    labels; a label given twice at one spin, as the 16-solution families do, is two
    branches: ``_keyed``)."""
    samples: dict[tuple[str | None, int], list[tuple[float, float]]] = {}
    for t in thetas.tolist():
        for key, qk in _keyed(_exact(arm, spec, target, q0, opts, k, t), q0).items():
            samples.setdefault(key, []).append((float(np.linalg.norm(qk - q0)), t))
    if not samples:
        return _missed(q0, k, len(thetas))
    result = []
    for key, found in samples.items():
        d0, t0 = min(found)

        def f(t: float, key: tuple[str | None, int] = key) -> float:
            q = _of_branch(_exact(arm, spec, target, q0, opts, k, t), key, q0)
            return float(np.linalg.norm(q - q0)) if q is not None else FAR

        i = int(np.argmin(np.abs(thetas - t0)))
        best = _brent(f, _bracket(thetas, i, half))
        theta = float(best.x) if best.fun < d0 else t0
        q = _of_branch(_exact(arm, spec, target, q0, opts, k, theta), key, q0)
        result.append(_found(q, k, theta, spec.name, key[0]))  # type: ignore[arg-type]
    return stacked(result, arm.dof)


def _brent(f, bounds: tuple[float, float]):
    """Brent's bounded minimum of ``f`` to ``XATOL`` (scipy's ``minimize_scalar``), imported
    at the first spin refined: scipy.optimize costs a quarter of a second, a third of
    ``import armik``."""
    from scipy.optimize import minimize_scalar

    return minimize_scalar(f, bounds=bounds, method="bounded", options={"xatol": XATOL})


def _keyed(got: Answers, q0: np.ndarray) -> dict[tuple[str | None, int], np.ndarray]:
    """``got``'s answers by (label, rank): the rank among the answers of that label by
    distance to q0, so that two answers one label names (the 16-solution families give a
    label twice) are two branches, not one."""
    order = sorted(range(len(got)), key=lambda i: float(np.linalg.norm(got.q[i] - q0)))
    seen: dict[str | None, int] = {}
    keyed = {}
    for i in order:
        label = got.label(i)
        rank = seen[label] = seen.get(label, -1) + 1
        keyed[(label, rank)] = got.q[i]
    return keyed


def _of_branch(got: Answers, key: tuple[str | None, int], q0: np.ndarray) -> np.ndarray | None:
    """The answer of branch ``key`` (``_keyed``) among ``got``, None where it has none."""
    return _keyed(got, q0).get(key)


def _exact(arm, spec, target, q0, opts, k, t: float) -> Answers:
    """The closed form's exact answers within the limits at spin t."""
    turned = _turned(target, k, np.array([t])).target(0)
    got = spec.run(arm, turned, q0, opts, True)
    keep = [i for i in range(len(got)) if got.claimed(i) and arm.within_limits(got.q[i])]
    return got.take(keep)


def _found(q: np.ndarray, k: int, theta: float, name: str, label: str | None = None) -> Answers:
    return one(
        np.array(q, dtype=float),
        Status.CONVERGED,
        f"{name} over the spin about the target's {AXES[k]} axis, at {theta:.6g} rad "
        "(nearest q0 over the swept range)",
        branch=label,
    )


def _missed(q0: np.ndarray, k: int, n: int) -> Answers:
    return one(
        np.array(q0, dtype=float),
        Status.NOT_CONVERGED,
        f"none of {n} spins about the target's {AXES[k]} axis gave an exact answer "
        "within the limits (a sweep: a narrower window may still hold one); q is q0",
    )


SPEC = registry.register(
    registry.SolverSpec(
        name="spin",
        kind="analytic",
        enforces_limits=True,
        priority=85,
        why_not=applies,
        solves=frozenset({"spin"}),
        needs=frozenset({"spin"}),
        run=run,
        summary="a 6R closed form over a free or bounded spin (bounds freeing one rotation)",
        complete=False,
    )
)
