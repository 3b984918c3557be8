"""Throughput of solve_batch under TRAC-IK's protocol, workers 1 vs 2, and memory vs N.

    python benchmarks/batch_bench.py --arms panda ur5 -n 20000 --workers 1 2 --rounds 2
    python benchmarks/batch_bench.py --memory 10000 1000000 --arms panda

Targets: ``armik.bench.targets`` (uniform joint samples within the limits, FK, seed 42);
budget 5 ms per target, success 1e-5 m and 1e-5 rad with every joint within its limits; q0
the mid-limit configuration. Each success is checked again here with Pinocchio directly
(independent of armik's verify) to count false successes. Worker counts are interleaved over
``--rounds`` rounds and the best round of each is kept (a noisy machine only slows runs down).
``--peers`` times a sequential loop of the Robotics Toolbox's C++ ik_LM over the first
``--peer-n`` targets through ``armik.peers`` (the same URDF file, its FK checked first).
``--reference`` also times a plain compiled loop on 1 and 2 threads: what the machine gives
two threads at that moment (other processes share the cores).
``--memory`` runs each N in a fresh process and prints its peak resident memory (ru_maxrss).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin

import armik
import armik.targets.batch
from armik.tools import bench

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def targets(arm: armik.Arm, n: int, seed: int = 42) -> np.ndarray:
    return np.array([T.homogeneous for T in bench.targets(arm, n, seed)])


def false_successes(arm: armik.Arm, res, T: np.ndarray, tol: float) -> int:
    bad = 0
    for i in np.flatnonzero(res.success):
        M = arm.fk(res.q[i])
        err = pin.log6(M.actInv(pin.SE3(T[i]))).vector
        ok = np.linalg.norm(T[i, :3, 3] - M.translation) <= tol * (1 + 1e-9)
        ok &= np.linalg.norm(err[3:]) <= tol * (1 + 1e-9)
        ok &= bool(((res.q[i] >= arm.lower - 1e-12) & (res.q[i] <= arm.upper + 1e-12)).all())
        bad += not ok
    return bad


def reference_ratio(seconds: float = 0.25) -> float:
    """Two threads over one on a plain compiled loop (GIL released): the ceiling the machine
    offers at this moment."""
    from concurrent.futures import ThreadPoolExecutor

    from numba import njit

    @njit(nogil=True, cache=False)
    def spin(n):
        s = 0.0
        for i in range(n):
            s += np.sin(i * 1e-3)
        return s

    spin(10)
    n = int(4e7 * seconds)
    t = time.perf_counter()
    spin(n)
    spin(n)
    one = time.perf_counter() - t
    with ThreadPoolExecutor(2) as pool:
        t = time.perf_counter()
        list(pool.map(spin, [n, n]))
        two = time.perf_counter() - t
    return one / two


def run_throughput(args) -> list[dict]:
    rows = []
    opts = dict(timeout=args.budget, tol_position=args.tol, tol_orientation=args.tol)
    for name in args.arms:
        arm = armik.load(name)
        T = targets(arm, args.n)
        arm.solve_batch(T[:64], q0=arm.middle, solver=args.solver, progress=False, **opts)
        best: dict[int, dict] = {}
        for _ in range(args.rounds):
            if args.reference:
                print(json.dumps({"reference_two_thread_ratio": reference_ratio()}), flush=True)
            for w in args.workers:
                t0 = time.perf_counter()
                res = arm.solve_batch(
                    T, q0=arm.middle, solver=args.solver, workers=w, progress=False, **opts
                )
                wall = time.perf_counter() - t0
                row = {
                    "arm": name,
                    "solver": res.solver,
                    "workers": w,
                    "n": len(T),
                    "success_pct": 100.0 * res.success.mean(),
                    "failures": int((~res.success).sum()),
                    "false_successes": false_successes(arm, res, T, args.tol),
                    "seconds": wall,
                    "targets_per_s": len(T) / wall,
                }
                if w not in best or wall < best[w]["seconds"]:
                    best[w] = row
                print(json.dumps(row), flush=True)
        one = best.get(1)
        for _, row in sorted(best.items()):
            row["speedup_vs_1"] = one["seconds"] / row["seconds"] if one else None
            rows.append(row)
        if args.peers:
            rows.append(peer_row(arm, T[: args.peer_n], args))
    return rows


def peer_row(arm: armik.Arm, T: np.ndarray, args) -> dict:
    """A sequential loop of the Robotics Toolbox's C++ ik_LM through ``armik.peers`` (30
    iterations x 100 searches, joint limits on, tolerance set for 1e-5; the same URDF, its
    FK checked against armik's), from the same q0 on the same targets; its successes are
    checked as armik's are. ``seconds`` is the loop's wall time; ``library_seconds`` the sum
    of the library calls alone."""
    from armik.tools import peers

    peer = peers.make("rtb", arm, args.tol)
    q0 = arm.middle
    qs, library = [], 0.0
    t0 = time.perf_counter()
    for M in T:
        qs.append(peer.solve(M, q0))
        library += peer.elapsed
    wall = time.perf_counter() - t0
    ok = 0
    for M, q in zip(T, qs):
        F = arm.fk(q)
        e = pin.log6(F.actInv(pin.SE3(M))).vector
        ok += bool(
            np.linalg.norm(M[:3, 3] - F.translation) <= args.tol
            and np.linalg.norm(e[3:]) <= args.tol
            and arm.within_limits(q)
        )
    return {
        "arm": arm.name,
        "solver": "rtb ik_LM, sequential",
        "workers": 1,
        "n": len(T),
        "success_pct": 100.0 * ok / len(T),
        "seconds": wall,
        "library_seconds": library,
        "targets_per_s": len(T) / wall,
    }


def run_split(args) -> None:
    """Time the compiled solve (GIL released) and the verification (GIL held) apart, chunk
    by chunk as solve_batch runs them: the share that bounds two threads (Amdahl)."""
    from armik.options import Options
    from armik.solvers import registry
    from armik.verify.measure import measure_batch

    opts = Options.from_kwargs(
        dict(timeout=args.budget, tol_position=args.tol, tol_orientation=args.tol)
    )
    spec = registry.get(args.solver)
    for name in args.arms:
        arm = armik.load(name)
        kin = arm.kinematics
        tb = armik.targets.batch.parse_targets(targets(arm, args.n))
        q0 = np.ascontiguousarray(np.broadcast_to(arm.middle, (len(tb), arm.dof)))
        spec.run_batch(kin, tb[:8], q0[:8], opts)
        solve_s = check_s = 0.0
        for s in range(0, len(tb), 256):
            t = time.perf_counter()
            ab = spec.run_batch(kin, tb[s : s + 256], q0[s : s + 256], opts)
            solve_s += time.perf_counter() - t
            t = time.perf_counter()
            measure_batch(kin, ab.q, tb[s : s + 256], opts)
            check_s += time.perf_counter() - t
        share = check_s / (solve_s + check_s)
        print(
            f"{name}: solve {solve_s / len(tb) * 1e6:.1f} us/target, verification "
            f"{check_s / len(tb) * 1e6:.1f} us/target: GIL-held share {share:.3f}, bound for "
            f"two threads {1 / (share + (1 - share) / 2):.2f}x"
        )


def run_memory(args) -> None:
    for n in args.memory:
        code = (
            "import resource, numpy as np, armik, sys\n"
            "sys.path.insert(0, 'benchmarks')\n"
            "from batch_bench import targets\n"
            f"arm = armik.load({args.arms[0]!r})\n"
            "T0 = targets(arm, 10000)\n"
            "base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            f"T = np.resize(T0, ({n}, 4, 4))\n"
            f"res = arm.solve_batch(T, solver={args.solver!r}, timeout={args.budget}, "
            f"tol_position={args.tol}, tol_orientation={args.tol}, progress=False)\n"
            "peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            "data = (T.nbytes + sum(getattr(res, k).nbytes for k in ('q', 'success', "
            "'status_code', 'position_error', 'orientation_error', 'iterations', "
            "'restarts'))) / 1024\n"
            f"print({n}, 'targets: peak RSS', peak // 1024, 'MiB; before the batch', "
            "base // 1024, 'MiB; targets + results arrays', int(data // 1024), 'MiB; rest', "
            "int((peak - base - data) // 1024), 'MiB;', res.summary())\n"
        )
        subprocess.run([sys.executable, "-c", code], check=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--arms", nargs="+", default=["panda", "ur5"])
    p.add_argument("-n", type=int, default=20000)
    p.add_argument("--workers", nargs="+", type=int, default=[1, 2])
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--solver", default="dls")
    p.add_argument("--budget", type=float, default=0.005)
    p.add_argument("--tol", type=float, default=1e-5)
    p.add_argument("--peers", action="store_true", help="also time rtb ik_LM sequentially")
    p.add_argument("--peer-n", type=int, default=20000)
    p.add_argument("--reference", action="store_true", help="also time a plain 2-thread loop")
    p.add_argument("--memory", nargs="+", type=int, help="peak RSS for these N instead")
    p.add_argument("--split", action="store_true", help="solve vs verification time instead")
    args = p.parse_args()
    if args.memory:
        run_memory(args)
        return
    if args.split:
        run_split(args)
        return
    rows = run_throughput(args)
    print("\n| arm | solver | workers | N | success % | false successes | s | targets/s | x1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['arm']} | {r['solver']} | {r['workers']} | {r['n']} | "
            f"{r['success_pct']:.2f} | {r.get('false_successes', '')} | {r['seconds']:.2f} | "
            f"{r['targets_per_s']:,.0f} | {r.get('speedup_vs_1') or '':.3} |"
            if r.get("speedup_vs_1")
            else f"| {r['arm']} | {r['solver']} | {r['workers']} | {r['n']} | "
            f"{r['success_pct']:.2f} | {r.get('false_successes', '')} | {r['seconds']:.2f} | "
            f"{r['targets_per_s']:,.0f} | |"
        )


if __name__ == "__main__":
    resource.getrusage(resource.RUSAGE_SELF)
    main()
