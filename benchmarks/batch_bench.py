"""Throughput of solve_batch under TRAC-IK's protocol, workers 1 vs 2, and memory vs N.

    python benchmarks/batch_bench.py --arms panda ur5 -n 20000 --workers 1 2 --rounds 2
    python benchmarks/batch_bench.py --memory 10000 1000000 --arms panda

Targets: ``armik.bench.targets`` (uniform joint samples within the limits, FK, seed 42);
budget 5 ms per target, success 1e-5 m and 1e-5 rad with every joint within its limits; q0
the mid-limit configuration. Each success is checked again here with Pinocchio directly
(independent of armik's verify) to count false successes. Worker counts are interleaved over
``--rounds`` rounds and the best round of each is kept (a noisy machine only slows runs down).
``--peers rtb`` times a sequential loop of the Robotics Toolbox's C++ ik_LM over the first
``--peer-n`` targets through ``armik.peers`` when that module and the toolbox are installed.
``--memory`` runs each N in a fresh process and prints its peak resident memory (ru_maxrss).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin

import armik
from armik import bench


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


def run_throughput(args) -> list[dict]:
    rows = []
    opts = dict(timeout=args.budget, tol_position=args.tol, tol_orientation=args.tol)
    for name in args.arms:
        arm = armik.load(name)
        T = targets(arm, args.n)
        arm.solve_batch(T[:64], q0=arm.middle, solver=args.solver, progress=False, **opts)
        best: dict[int, dict] = {}
        for _ in range(args.rounds):
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
    from armik import peers  # the benchmark's peer wrappers

    peer = peers.make("rtb", arm, tol=args.tol)
    q0 = arm.middle
    ok, t0 = 0, time.perf_counter()
    for M in T:
        q = peer.solve(pin.SE3(M), q0)
        ok += q is not None
    wall = time.perf_counter() - t0
    return {
        "arm": arm.name,
        "solver": "rtb ik_LM (sequential)",
        "workers": 1,
        "n": len(T),
        "success_pct": 100.0 * ok / len(T),
        "seconds": wall,
        "targets_per_s": len(T) / wall,
    }


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
    p.add_argument("--memory", nargs="+", type=int, help="peak RSS for these N instead")
    args = p.parse_args()
    if args.memory:
        run_memory(args)
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
