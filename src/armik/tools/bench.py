"""The IK benchmark, following TRAC-IK's protocol.

For each arm: N joint configurations sampled uniformly within the limits (fixed seed),
their FK poses as targets, every solve seeded from the mid-limit configuration, a time
budget per solve (5 ms), success = position error <= 1e-5 m and orientation error <= 1e-5
rad with every joint inside its limits, as verified by armik's FK check. The Pinocchio CLIK
loop (solver "clik") runs in the same process as a baseline; with ``peers`` the Robotics
Toolbox's C++ ``ik_LM`` and EAIK (see ``armik.tools.peers``) run on the same targets, interleaved
target by target with armik's solvers. One untimed solve per arm and solver comes first, so
that first-call costs do not land on the first target.

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

from armik.arm import Arm
from armik.errors import OptionError
from armik.kernel.tier import compiling
from armik.loading import load
from armik.model.catalogue import SPATIAL_ARMS
from armik.problem.settings import SolverSettings
from armik.targets.pose import parse_target
from armik.tools.peers import PEERS, PeerUnavailable
from armik.tools.peers import make as make_peer
from armik.verify.measure import measure

DEFAULT_SOLVERS = ("dls", "qp", "clik")
# clik runs as in Pinocchio's example: up to 1000 iterations (within the budget).
SOLVER_OPTIONS = {"clik": {"max_iterations": 1000}}


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
    """One solver on one arm's targets (see ``bench_interleaved`` for several)."""
    return bench_interleaved(
        arm, [solver], poses, budget=budget, tol=tol, repeats=repeats, progress=progress
    )[0]


def bench_interleaved(
    arm: Arm,
    solvers: Sequence[str],
    poses: Sequence,
    *,
    peers: Sequence = (),
    budget: float = 0.005,
    tol: float = 1e-5,
    repeats: int = 1,
    progress=None,
) -> list[BenchRow]:
    """Every armik solver and every peer (``armik.tools.peers.Peer``) on the same targets,
    interleaved target by target, so that a busy moment of the machine lands on all of them
    alike (the order turns by one per target). Peers are timed on their library call only and
    judged by armik's FK check, with the same tolerance and limits; armik's times include
    parsing and verification."""
    q0 = arm.middle
    # One untimed solve first: first-call costs (imports, caches) are not per-solve costs.
    if len(poses):
        for solver in solvers:
            arm.solve(poses[0], q0=q0, solver=solver, timeout=budget)
        for peer in peers:
            peer.solve(poses[0].homogeneous, q0)
            peer.iterations.clear()
    names = list(solvers) + [p.name for p in peers]
    times: dict[str, list[float]] = {name: [] for name in names}
    iters: dict[str, list[int]] = {name: [] for name in names}
    ok = dict.fromkeys(names, 0)
    violations = dict.fromkeys(names, 0)
    opts = SolverSettings(tol_position=tol, tol_orientation=tol)
    done = 0
    # Each target runs every contender; the order turns by one per target, so that none
    # always runs first (after the others have cooled its caches) or last.
    contenders = [(s, None) for s in solvers] + [(p.name, p) for p in peers]
    for k in range(repeats):
        for i, pose in enumerate(poses):
            if peers:
                target = parse_target(pose)
                T = pose.homogeneous
            turn = done % len(contenders)
            for name, peer in contenders[turn:] + contenders[:turn]:
                if peer is None:
                    t = time.perf_counter()
                    res = arm.solve(
                        pose,
                        q0=q0,
                        solver=name,
                        timeout=budget,
                        tol_position=tol,
                        tol_orientation=tol,
                        seed=k * len(poses) + i,
                        **SOLVER_OPTIONS.get(name, {}),
                    )
                    times[name].append(time.perf_counter() - t)
                    iters[name].append(res.iterations)
                    ok[name] += res.success
                    violations[name] += not arm.within_limits(np.asarray(res.q))
                else:
                    t = time.perf_counter()
                    peer.elapsed = None
                    q = peer.solve(T, q0)
                    spent = time.perf_counter() - t
                    times[name].append(spent if peer.elapsed is None else peer.elapsed)
                    c = measure(arm.kinematics, q, target, opts)
                    ok[name] += c.ok
                    violations[name] += bool(c.violations)
            done += 1
            if progress is not None:
                progress(done)
    for peer in peers:
        iters[peer.name] = peer.iterations
    rows = []
    for name in names:
        ms = np.array(times[name]) * 1e3
        rows.append(
            BenchRow(
                arm.name,
                name,
                len(ms),
                100.0 * ok[name] / len(ms),
                len(ms) - ok[name],
                float(ms.mean()),
                float(np.median(ms)),
                float(np.percentile(ms, 95)),
                float(ms.max()),
                float(np.mean(iters[name])) if len(iters[name]) else 0.0,
                violations[name],
            )
        )
    return rows


@compiling()  # times compiled code: a first call compiles, not run as Python
def run(
    arms: Iterable[str] = SPATIAL_ARMS,
    solvers: Iterable[str] = DEFAULT_SOLVERS,
    n: int = 2000,
    budget: float = 0.005,
    seed: int = 42,
    tol: float = 1e-5,
    repeats: int = 1,
    show_progress: bool = False,
    peers: Iterable[str] = (),
    notes: list[str] | None = None,
    tip: str | None = None,
) -> list[BenchRow]:
    """Run the benchmark; returns one row per (arm, solver or peer), N = n x repeats solves.
    A peer that is not installed or does not apply to an arm is skipped, with the reason
    appended to ``notes``. ``tip``: the tip frame of every arm (a URDF file's chain end)."""
    _check(n >= 1, "n", n, "the number of targets per arm must be at least 1")
    _check(repeats >= 1, "repeats", repeats, "the number of passes must be at least 1")
    _check(budget > 0, "budget", budget, "the time budget per solve must be > 0 seconds")
    _check(tol > 0, "tol", tol, "the success tolerance must be > 0 (m and rad)")
    peers = list(peers)
    for name in peers:
        _check(name in PEERS, "peers", name, f"peers are {', '.join(PEERS)}")
    rows = []
    solvers, arms = list(solvers), list(arms)
    _check(bool(arms), "arms", arms, "give at least one arm (a bundled name or a URDF path)")
    _check(bool(solvers or peers), "solvers", solvers, "give at least one solver or peer")
    for name in arms:
        arm = load(name) if tip is None else load(name, tip=tip)
        poses = targets(arm, n, seed)
        active = []
        for peer in peers:
            try:
                active.append(make_peer(peer, arm, tol))
            except PeerUnavailable as exc:
                if notes is not None:
                    notes.append(f"{peer} skipped on {name}: {exc}")
        bar = _Progress(name, n * repeats) if show_progress else None
        rows += bench_interleaved(
            arm,
            solvers,
            poses,
            peers=active,
            budget=budget,
            tol=tol,
            repeats=repeats,
            progress=bar.update if bar else None,
        )
        if bar:
            bar.close()
    return rows


def ratios(rows: Sequence[BenchRow]) -> list[str]:
    """Lines "arm: solver / peer = r" (ratio of mean times, same run) for every arm with
    peers."""
    lines = []
    by_arm: dict[str, dict[str, BenchRow]] = {}
    for r in rows:
        by_arm.setdefault(r.arm, {})[r.solver] = r
    for arm, row in by_arm.items():
        ours = [s for s in row if s not in PEERS]
        for peer in (p for p in PEERS if p in row):
            parts = [f"{s} / {peer} = {row[s].mean_ms / row[peer].mean_ms:.2f}" for s in ours]
            if parts:
                lines.append(f"{arm}: mean time ratio " + ", ".join(parts))
    return lines


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
