"""The exported C solvers (``armik export``): one ``N_ik`` call with every branch, timed
from a small C harness, and the answers of the same targets checked.

For each arm, ``-n`` targets from FK of seeded random configurations within the limits.
The harness (``cc -O3 -march=native``) calls ``N_ik`` on every target in turn, ``--reps``
sweeps, and reports the mean CPU time of one call (the process's CPU clock, so that other
work on a shared machine counts less; the best of ``--rounds`` rounds); it writes
each target's solutions, which are then checked as the tests check them: within the limits,
within 1e-9 m and 1e-9 rad of the target by Pinocchio's FK, and the rows of ``solve_all``
in its order (each joint within 1e-7 rad modulo 2 pi). With ``ssik`` importable and
Eigen's headers found (``--eigen DIR``), ssik's C++ (``ssik::Solver`` from its wheel's
headers, the same flags) is timed on the same targets in the same script, else it says
which is missing.

    python benchmarks/export_c.py ur5 ur10 abb_irb120 -n 300
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik
from armik.export import family as family_of

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "NAME_ik.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    int n, reps, rounds, i, r, k, count;
    double *T, q[UPPER_IK_MAX_SOLUTIONS][UPPER_IK_DOF], best = 1e30, t0, sum = 0.0;
    FILE *in, *out;
    if (argc != 6) return 1;
    n = atoi(argv[1]);
    reps = atoi(argv[2]);
    rounds = atoi(argv[3]);
    T = malloc(sizeof(double) * 16 * n);
    in = fopen(argv[4], "rb");
    out = fopen(argv[5], "w");
    if (!T || !in || !out || fread(T, sizeof(double), 16 * n, in) != (size_t)(16 * n)) return 1;
    for (k = 0; k < rounds; k++) {
        t0 = now();
        for (r = 0; r < reps; r++)
            for (i = 0; i < n; i++) {
                count = NAME_ik(T + 16 * i, q);
                sum += count > 0 ? q[0][0] + count : 0.0;
            }
        t0 = (now() - t0) / ((double)reps * n);
        best = t0 < best ? t0 : best;
    }
    for (i = 0; i < n; i++) {
        count = NAME_ik(T + 16 * i, q);
        fprintf(out, "%d", count);
        for (r = 0; r < count; r++)
            for (k = 0; k < UPPER_IK_DOF; k++) fprintf(out, " %.17g", q[r][k]);
        fprintf(out, "\n");
    }
    printf("%.6f %g\n", best * 1e6, sum);
    return 0;
}
"""


def build_and_time(arm: armik.Arm, name: str, poses: np.ndarray, folder: Path, args):
    """(mean us a call, each target's solutions) from the compiled harness."""
    armik.export(arm, name, folder)
    (folder / "bench.c").write_text(HARNESS.replace("NAME", name).replace("UPPER", name.upper()))
    exe = folder / "bench"
    flags = ["-std=c99", "-O3", "-march=native", "-Wall", "-Wextra", "-Werror"]
    subprocess.run(
        [
            "cc",
            *flags,
            str(folder / "bench.c"),
            str(folder / f"{name}_ik.c"),
            "-o",
            str(exe),
            "-lm",
        ],
        check=True,
    )
    targets = folder / "targets.bin"
    np.ascontiguousarray(poses, dtype="<f8").tofile(targets)
    answers = folder / "answers.txt"
    run = [str(exe), str(len(poses)), str(args.reps), str(args.rounds), str(targets), str(answers)]
    done = subprocess.run(run, check=True, capture_output=True, text=True)
    mean = float(done.stdout.split()[0])
    rows = []
    for line in answers.read_text().splitlines():
        values = [float(x) for x in line.split()]
        rows.append(np.array(values[1:]).reshape(int(values[0]), arm.dof))
    return mean, rows


def check(arm: armik.Arm, poses: np.ndarray, rows: list[np.ndarray]) -> tuple[int, int, int]:
    """(targets whose solutions are all right and are solve_all's, solutions, failures)."""
    good = solutions = 0
    for T, Q in zip(poses, rows):
        ok = True
        for q in Q:
            got = arm.fk(q)
            position = np.linalg.norm(got.translation - T[:3, 3])
            orientation = np.linalg.norm(pin.log3(got.rotation.T @ T[:3, :3]))
            inside = np.all(q >= arm.lower - 1e-12) and np.all(q <= arm.upper + 1e-12)
            ok &= bool(inside and position < 1e-9 and orientation < 1e-9)
        expected = [r.q for r in arm.solve_all(T) if r.success]
        if len(expected) != len(Q):
            ok = False
        else:
            for a, b in zip(Q, expected):
                ok &= bool(np.abs(np.angle(np.exp(1j * (a - b)))).max() < 1e-7)
        good += ok
        solutions += len(Q)
    return good, solutions, len(poses) - good


def ssik_absent(eigen: str | None) -> str | None:
    """Why ssik's C++ cannot be timed here, or None."""
    try:
        import ssik  # noqa: F401
    except ImportError:
        return "ssik is not installed (pip install ssik)"
    if eigen is None or not (Path(eigen) / "Eigen" / "Core").exists():
        return "Eigen's headers were not found (give --eigen DIR, the folder holding Eigen/)"
    return None


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("robots", nargs="*", default=["ur5", "ur10", "abb_irb120"])
    p.add_argument("-n", type=int, default=300, help="targets an arm")
    p.add_argument("--reps", type=int, default=200, help="sweeps over the targets a round")
    p.add_argument("--rounds", type=int, default=5, help="rounds, the best one counted")
    p.add_argument("--eigen", help="Eigen's include folder, for ssik's C++")
    args = p.parse_args()
    if shutil.which("cc") is None:
        raise SystemExit("no C compiler (cc) on this machine")
    absent = ssik_absent(args.eigen)
    print(f"{'arm':<12} {'family':<16} {'N_ik (us)':>10} {'solutions':>10} {'checked':>9}")
    for robot in args.robots:
        arm = armik.load(robot)
        rng = np.random.default_rng(0)
        poses = np.array([arm.fk(arm.random_q(rng)).homogeneous for _ in range(args.n)])
        family = family_of(arm.kinematics)
        with tempfile.TemporaryDirectory() as tmp:
            mean, rows = build_and_time(arm, "arm", poses, Path(tmp), args)
        good, solutions, _ = check(arm, poses, rows)
        print(f"{robot:<12} {family:<16} {mean:>10.3f} {solutions:>10} {good:>5}/{len(poses)}")
    print(f"ssik: {absent}" if absent else "ssik: see below")


if __name__ == "__main__":
    main()
