"""The general 6R solver (``solver="general_6r"``, the 2-D search) on random arms with every
axis random: completeness, false successes, median time of a verified ``solve_all``.
``--solver`` times another (``elimination_6r``, or ``auto``: what ``solve_all`` runs).

    python benchmarks/general_6r.py -n 60 --seed 0
    python benchmarks/general_6r.py -n 60 --seed 0 --solver elimination_6r
    python benchmarks/general_6r.py --held -n 30

Each arm has 6 revolute joints with random unit axes through random points (within 0.4 m),
random fixed transforms before joint 1 and after joint 6, limits +-2 pi; one target per arm
from a uniform random configuration. Complete: the configuration that made the target is
among the answers (every joint within 1e-6 rad modulo 2 pi). A false success: an answer
called a success whose pose error, measured here with Pinocchio (``pin.log6``), exceeds
1e-9. Times: ``solve_all`` after one warm-up call per arm, the median over the arms, wall clock and
the process's CPU time (the second is less sensitive to other work on a shared machine).

``--held``: the Panda with joint 7, then joint 1, and an iiwa-like arm (a spherical
shoulder and wrist: ``armik.model.random_arms.iiwa_like_urdf``) with joint 3, held at the
generating configuration's
value (``hold=``), ``-n`` targets each: completeness, the solver that solved the six others,
median ``solve_all`` time with a new held value (the locked arm is built) and again.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np
import pinocchio as pin

import armik
from armik.model.random_arms import iiwa_like_urdf
from armik.solvers.closed_form import general_6r

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


def _fmt(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def random_urdf(rng: np.random.Generator) -> str:
    """A 6R arm's URDF: every axis a random unit vector through a random point."""
    parts = ['<?xml version="1.0"?>', '<robot name="g6">', '<link name="world"/>']
    parts += [f'<link name="l{i}"/>' for i in range(7)] + ['<link name="tool"/>']
    parts.append(
        '<joint name="mount" type="fixed"><parent link="world"/><child link="l0"/>'
        f'<origin xyz="{_fmt(rng.uniform(-1, 1, 3))}" rpy="{_fmt(rng.uniform(-3, 3, 3))}"/>'
        "</joint>"
    )
    prev = np.zeros(3)
    for i in range(6):
        c = rng.uniform(-0.4, 0.4, 3)
        h = rng.normal(size=3)
        h /= np.linalg.norm(h)
        parts.append(
            f'<joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{_fmt(c - prev)}"/><axis xyz="{_fmt(h)}"/>'
            f'<limit lower="{-2 * np.pi}" upper="{2 * np.pi}" effort="1" velocity="1"/></joint>'
        )
        prev = c
    parts.append(
        '<joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>'
        f'<origin xyz="{_fmt(rng.uniform(-0.2, 0.2, 3))}" rpy="{_fmt(rng.uniform(-3, 3, 3))}"/>'
        "</joint></robot>"
    )
    return "\n".join(parts)


def held(n: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    panda = armik.load("panda")
    iiwa = armik.load_string(iiwa_like_urdf(), base="base", tip="tool")
    for arm, joint in ((panda, "panda_joint7"), (panda, "panda_joint1"), (iiwa, "j3")):
        k = arm.joint_names.index(joint)
        first, again, complete, solvers = [], [], 0, set()
        for _ in range(n):
            q = arm.random_q(rng)
            T = arm.fk(q)
            hold = {joint: float(q[k])}
            t0 = time.perf_counter()
            arm.solve_all(T, hold=hold)
            first.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            results = arm.solve_all(T, hold=hold)
            again.append(time.perf_counter() - t0)
            ok = [r for r in results if r.success]
            solvers |= {r.solver for r in ok}
            wrapped = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in ok]
            complete += bool(wrapped) and min(wrapped) < 1e-6
        print(
            f"{arm.name}, {joint} held: complete {complete}/{n}, solvers {sorted(solvers)}, "
            f"solve_all median {1e3 * statistics.median(first):.2f} ms with a new value, "
            f"{1e3 * statistics.median(again):.2f} ms again"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=60, help="random arms (one target each)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--held", action="store_true", help="the Panda with one joint held")
    ap.add_argument("--solver", default="general_6r", help="the solver timed (general_6r)")
    args = ap.parse_args()
    if args.held:
        held(args.n, args.seed)
        return
    rng = np.random.default_rng(args.seed)
    times, cpu, complete, false_ok, counts = [], [], 0, 0, []
    for _ in range(args.n):
        arm = armik.load_string(random_urdf(rng), base="world", tip="tool")
        q = arm.random_q(rng)
        T = arm.fk(q)
        arm.solve_all(T, solver=args.solver)  # warm-up (compiles on the first arm)
        t0, c0 = time.perf_counter(), time.process_time()
        results = arm.solve_all(T, solver=args.solver)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        ok = [r for r in results if r.success]
        counts.append(len(ok))
        for r in ok:
            if np.linalg.norm(pin.log6(arm.fk(r.q).inverse() * T).vector) > 1e-9:
                false_ok += 1
        wrapped = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in ok]
        complete += bool(wrapped) and min(wrapped) < 1e-6
    print(f"arms: {args.n} (seed {args.seed}), {args.solver}, general_6r's grid {general_6r.GRID}")
    print(f"complete (generating configuration found): {complete}/{args.n}")
    print(f"false successes: {false_ok}")
    print(f"solutions per target: median {statistics.median(counts)}, max {max(counts)}")
    print(
        f"solve_all: median {1e3 * statistics.median(times):.2f} ms, "
        f"max {1e3 * max(times):.2f} ms; CPU time median {1e3 * statistics.median(cpu):.2f} ms"
    )


if __name__ == "__main__":
    main()
