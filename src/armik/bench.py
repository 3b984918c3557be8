"""The IK benchmark, following TRAC-IK's protocol.

For each arm: N joint configurations sampled uniformly within the limits (fixed seed),
their FK poses as targets, every solve seeded from the mid-limit configuration, a time
budget per solve (5 ms), success = position error <= 1e-5 m and orientation error <= 1e-5
rad with every joint inside its limits, as verified by armik's FK check. The Pinocchio CLIK
loop (solver "clik") runs in the same process as a baseline. One untimed solve per arm and
solver comes first, so that first-call costs do not land on the first target.

``repeats`` solves the same targets again with other solver seeds (pass k uses seeds
k N .. k N + N - 1): the restarts are random, and a rate of 99.9 % on 2000 targets rests on
two failures, so one pass cannot tell 99.9 % from 99.95 %.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from .arm import Arm, load
from .errors import OptionError
from .robots import SPATIAL_ARMS

DEFAULT_SOLVERS = ("dls", "qp", "clik")


@dataclass(frozen=True)
class BenchRow:
    arm: str
    solver: str
    n: int
    success_rate: float  # %
    failures: int
    mean_ms: float
    median_ms: float
    p95_ms: float
    max_ms: float
    mean_iterations: float
    limit_violations: int

    def as_dict(self) -> dict:
        return asdict(self)


def targets(arm: Arm, n: int, seed: int) -> list:
    rng = np.random.default_rng(seed)
    return [arm.fk(arm.random_q(rng)) for _ in range(n)]


def bench_arm(
    arm: Arm,
    solver: str,
    poses: Sequence,
    *,
    budget: float = 0.005,
    tol: float = 1e-5,
    repeats: int = 1,
    progress=None,
) -> BenchRow:
    q0 = arm.middle
    # One untimed solve first: first-call costs (imports, caches) are not per-solve costs.
    if len(poses):
        arm.solve(poses[0], q0=q0, solver=solver, timeout=budget)
    times, iters, ok, violations = [], [], 0, 0
    for k in range(repeats):
        for i, pose in enumerate(poses):
            t = time.perf_counter()
            res = arm.solve(
                pose,
                q0=q0,
                solver=solver,
                timeout=budget,
                tol_position=tol,
                tol_orientation=tol,
                seed=k * len(poses) + i,
            )
            times.append(time.perf_counter() - t)
            iters.append(res.iterations)
            ok += res.success
            violations += not arm.within_limits(np.asarray(res.q))
            if progress is not None:
                progress(len(times))
    ms = np.array(times) * 1e3
    return BenchRow(
        arm.name,
        solver,
        len(times),
        100.0 * ok / len(times),
        len(times) - ok,
        float(ms.mean()),
        float(np.median(ms)),
        float(np.percentile(ms, 95)),
        float(ms.max()),
        float(np.mean(iters)),
        violations,
    )


def run(
    arms: Iterable[str] = SPATIAL_ARMS,
    solvers: Iterable[str] = DEFAULT_SOLVERS,
    n: int = 2000,
    budget: float = 0.005,
    seed: int = 42,
    tol: float = 1e-5,
    repeats: int = 1,
    show_progress: bool = False,
) -> list[BenchRow]:
    """Run the benchmark; returns one row per (arm, solver), N = n x repeats solves."""
    _check(n >= 1, "n", n, "the number of targets per arm must be at least 1")
    _check(repeats >= 1, "repeats", repeats, "the number of passes must be at least 1")
    _check(budget > 0, "budget", budget, "the time budget per solve must be > 0 seconds")
    _check(tol > 0, "tol", tol, "the success tolerance must be > 0 (m and rad)")
    rows = []
    solvers = list(solvers)
    for name in arms:
        arm = load(name)
        poses = targets(arm, n, seed)
        for solver in solvers:
            bar = _Progress(f"{name}/{solver}", n * repeats) if show_progress else None
            rows.append(
                bench_arm(
                    arm,
                    solver,
                    poses,
                    budget=budget,
                    tol=tol,
                    repeats=repeats,
                    progress=bar.update if bar else None,
                )
            )
            if bar:
                bar.close()
    return rows


def _check(ok: bool, option: str, value: object, what: str) -> None:
    if not ok:
        raise OptionError(f"{what}; got {option} = {value!r}", option=option, value=value)


def table(rows: Sequence[BenchRow]) -> str:
    head = (
        "| arm | solver | N | success % | failures | mean ms | median ms | p95 ms | max ms | "
        "mean iters | limit violations |"
    )
    lines = [head, "|" + "---|" * 11]
    for r in rows:
        lines.append(
            f"| {r.arm} | {r.solver} | {r.n} | {r.success_rate:.2f} | {r.failures} "
            f"| {r.mean_ms:.3f} | {r.median_ms:.3f} | {r.p95_ms:.3f} | {r.max_ms:.2f} | "
            f"{r.mean_iterations:.1f} | {r.limit_violations} |"
        )
    return "\n".join(lines)


class _Progress:
    """A one-line progress bar on stderr (only when stderr is a terminal)."""

    def __init__(self, label: str, total: int) -> None:
        self.label, self.total = label, total
        self.active = sys.stderr.isatty()
        self.step = max(total // 50, 1)

    def update(self, done: int) -> None:
        if self.active and (done % self.step == 0 or done == self.total):
            filled = int(30 * done / self.total)
            sys.stderr.write(
                f"\r{self.label:<20} [{'#' * filled}{'.' * (30 - filled)}] {done}/{self.total}"
            )
            sys.stderr.flush()

    def close(self) -> None:
        if self.active:
            sys.stderr.write("\n")
