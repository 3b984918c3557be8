"""The KUKA iiwa 14 at one elbow swivel angle: armik's ``srs`` against ssik's SRS solver,
interleaved, on the same targets.

For each of N seeded random configurations q within the limits, the target T = fk(q) and
q's swivel angle psi; per target, in turn (the order rotating): armik's
``solve_all(T, swivel=psi)`` (every branch, each verified by Pinocchio FK and the limits,
as ``IKResult``s), armik's closed form alone (``srs.at_swivel``: the kernel's rows as
``Answers``, before the verdict), and ssik's ``seven_r.srs.solve`` at that one swivel angle
(its FK-closure check, no limits). Each call timed ``REPEATS`` times, the median kept.
Then the solution sets: armik's successes against ssik's answers within the limits, each
joint within 1e-6 rad modulo 2 pi, on the targets where both read the swivel angle from
the same reference (ssik switches from the base z axis to x where the line from shoulder to
wrist is within 8.1 deg of z; armik keeps axis 1, z on the iiwa), and whether q is among
armik's. ssik's full ``solve`` (16 swivel angles swept, limits applied) is timed too, as
context: it answers another question (branches at 16 angles).

ssik is for measuring only, never a dependency of armik:

    pip install --no-deps --target /tmp/peerpkgs ssik cython
    PYTHONPATH=/tmp/peerpkgs python benchmarks/srs_ssik.py -n 200

Without ssik the script times armik alone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import armik
from armik.solvers.closed_form import srs
from armik.targets.pose import parsed

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

REPEATS = 5


def timed(call, repeats: int = REPEATS) -> tuple[float, object]:
    """(median seconds of ``repeats`` calls, the last call's value)."""
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = call()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def same_set(a: list[np.ndarray], b: list[np.ndarray], tol: float = 1e-6) -> bool:
    """Whether every configuration of ``a`` has one of ``b`` within ``tol`` (each joint,
    modulo 2 pi) and the other way round."""

    def near(x, y):
        d = np.asarray(x) - np.asarray(y)
        return bool(np.all(np.abs(np.arctan2(np.sin(d), np.cos(d))) < tol))

    return all(any(near(x, y) for y in b) for x in a) and all(any(near(y, x) for x in a) for y in b)


def _calls(arm, T, q, psi: float, iiwa14_ik, ssik_srs) -> dict:
    """The calls timed on one target, by name."""
    tgt = parsed(T, arm.kinematics)
    H = T.homogeneous
    calls = {
        "armik solve_all(T, swivel=psi)": lambda: arm.solve_all(T, swivel=psi),
        "armik srs.at_swivel (no verdict)": lambda: srs.at_swivel(arm.kinematics, tgt, q, psi),
    }
    if ssik_srs is not None:
        calls["ssik seven_r.srs.solve (one swivel)"] = lambda: ssik_srs.solve(
            iiwa14_ik._KB, H, swivel_samples=np.array([psi])
        )
        calls["ssik solve (16 swivels, limits)"] = lambda: iiwa14_ik.solve(
            H, enumerate_windings=False
        )
    return calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-n", type=int, default=200, help="targets (200)")
    parser.add_argument("--seed", type=int, default=53)
    args = parser.parse_args()
    arm = armik.load("kuka_iiwa14")
    model = arm.kinematics
    try:
        from ssik.prebuilt.kuka import iiwa14_ik
        from ssik.solvers.seven_r import srs as ssik_srs
    except ImportError:
        iiwa14_ik = ssik_srs = None
    rng = np.random.default_rng(args.seed)
    configs = [arm.random_q(rng) for _ in range(args.n)]
    # the first calls (compiles, caches) outside the timing
    T0 = arm.fk(configs[0])
    arm.solve_all(T0, swivel=0.1)
    if ssik_srs is not None:
        ssik_srs.solve(iiwa14_ik._KB, T0.homogeneous, swivel_samples=np.array([0.1]))
        iiwa14_ik.solve(T0.homogeneous, enumerate_windings=False)
    times: dict[str, list[float]] = {}
    equal = compared = generating = 0
    lower, upper = arm.lower, arm.upper
    for i, q in enumerate(configs):
        T = arm.fk(q)
        H = T.homogeneous
        psi = srs.swivel_of(model, q)
        calls = _calls(arm, T, q, psi, iiwa14_ik, ssik_srs)
        names = list(calls)
        outs = {}
        for k in range(len(names)):  # interleaved: the order rotates with the target
            name = names[(i + k) % len(names)]
            seconds, outs[name] = timed(calls[name])
            times.setdefault(name, []).append(seconds)
        ours = [r.q for r in outs["armik solve_all(T, swivel=psi)"] if r.success]
        generating += any(same_set([r], [q]) for r in ours)
        if ssik_srs is not None:
            S = srs.geometry(model).shoulder
            W = H[:3, 3] + H[:3, :3] @ (srs.geometry(model).wrist - arm.fk(np.zeros(7)).translation)
            n = (W - S) / np.linalg.norm(W - S)
            if abs(n[2]) < 0.99:  # the same reference direction in both
                theirs = [
                    s.q
                    for s in outs["ssik seven_r.srs.solve (one swivel)"][0]
                    if np.all((s.q >= lower - 1e-9) & (s.q <= upper + 1e-9))
                ]
                compared += 1
                equal += same_set(ours, theirs)
    print(f"KUKA iiwa 14, {args.n} targets (seed {args.seed}), median of {REPEATS} calls each")
    print()
    print("| call | median (us) | mean (us) |")
    print("|---|---|---|")
    for name, ts in times.items():
        print(f"| {name} | {1e6 * statistics.median(ts):.1f} | {1e6 * statistics.mean(ts):.1f} |")
    base = statistics.median(times["armik solve_all(T, swivel=psi)"])
    for name, ts in times.items():
        print(f"ratio armik solve_all / {name}: {base / statistics.median(ts):.2f}")
    print(f"generating configuration among armik's branches: {generating}/{args.n}")
    if ssik_srs is not None:
        print(f"same in-limits solution set as ssik at that swivel: {equal}/{compared} targets")


if __name__ == "__main__":
    main()
