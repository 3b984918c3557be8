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

    python benchmarks/export_c.py ur5 ur10 abb_irb120 z1 random:three_parallel:1 \
        random:parallel_23:2 random:meeting_12:3 random:spherical:4 \
        random:three_parallel_free:5 panda -n 300

An arm is a bundled name, or ``random:KIND:SEED``, a random arm of ``KIND``
(``armik.model.random_arms``: ``three_parallel``, ``parallel_23``, ``meeting_12``;
``spherical`` and ``three_parallel_free`` for the general families). A 7R arm is exported
with joint 7 held (the Panda): each target's joint 7 is the value it was made with, passed
to ``N_ik`` and to ``solve_all(hold=...)``; ssik is timed on the 6R arms only.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik
from armik.export import family as family_of
from armik.model.geometry import axis_lines
from armik.model.random_arms import random_urdf

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

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

/* IK(T, h, q): NAME_ik, with the held joint's value h when it takes one */
int main(int argc, char **argv)
{
    int n, reps, rounds, i, r, k, count;
    double *T, *H, q[UPPER_IK_MAX_SOLUTIONS][UPPER_IK_DOF], best = 1e30, t0, sum = 0.0;
    FILE *in, *out, *held;
    if (argc != 7) return 1;
    n = atoi(argv[1]);
    reps = atoi(argv[2]);
    rounds = atoi(argv[3]);
    T = malloc(sizeof(double) * 16 * n);
    H = malloc(sizeof(double) * n);
    in = fopen(argv[4], "rb");
    out = fopen(argv[5], "w");
    held = fopen(argv[6], "rb");
    if (!T || !H || !in || !out || !held) return 1;
    if (fread(T, sizeof(double), 16 * n, in) != (size_t)(16 * n)) return 1;
    if (fread(H, sizeof(double), n, held) != (size_t)n) return 1;
    for (k = 0; k < rounds; k++) {
        t0 = now();
        for (r = 0; r < reps; r++)
            for (i = 0; i < n; i++) {
                count = IK(T + 16 * i, H[i], q);
                sum += count > 0 ? q[0][0] + count : 0.0;
            }
        t0 = (now() - t0) / ((double)reps * n);
        best = t0 < best ? t0 : best;
    }
    for (i = 0; i < n; i++) {
        count = IK(T + 16 * i, H[i], q);
        fprintf(out, "%d", count);
        for (r = 0; r < count; r++)
            for (k = 0; k < UPPER_IK_DOF; k++) fprintf(out, " %.17g", q[r][k]);
        fprintf(out, "\n");
    }
    printf("%.6f %g\n", best * 1e6, sum);
    return 0;
}
"""


def load(robot: str) -> armik.Arm:
    if robot.startswith("random:"):
        _, kind, seed = robot.split(":")
        text = random_urdf(kind, np.random.default_rng(int(seed)))
        return armik.load_string(text, base="world", tip="tool")
    return armik.load(robot)


def build_and_time(
    arm: armik.Arm, name: str, poses: np.ndarray, held: np.ndarray | None, folder: Path, args
):
    """(mean us a call, each target's solutions) from the compiled harness; ``held``: each
    target's value of the held joint (a 7R arm), else None."""
    armik.export(arm, name, folder)
    call = f"{name}_ik(T, h, q)" if held is not None else f"((void)(h), {name}_ik(T, q))"
    text = f"#define IK(T, h, q) {call}\n" + HARNESS.replace("NAME", name)
    (folder / "bench.c").write_text(text.replace("UPPER", name.upper()))
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
    values = folder / "held.bin"
    np.ascontiguousarray(np.zeros(len(poses)) if held is None else held, "<f8").tofile(values)
    answers = folder / "answers.txt"
    run = [str(exe), str(len(poses)), str(args.reps), str(args.rounds), str(targets), str(answers)]
    run.append(str(values))
    done = subprocess.run(run, check=True, capture_output=True, text=True)
    mean = float(done.stdout.split()[0])
    rows = []
    for line in answers.read_text().splitlines():
        values = [float(x) for x in line.split()]
        rows.append(np.array(values[1:]).reshape(int(values[0]), arm.dof))
    return mean, rows


def check(
    arm: armik.Arm, poses: np.ndarray, rows: list[np.ndarray], held: np.ndarray | None
) -> tuple[int, int, int]:
    """(targets whose solutions are all right and are solve_all's, solutions, failures);
    ``held``: joint 7's value at each target (``solve_all(hold=...)``), else None."""
    good = solutions = 0
    for k, (T, Q) in enumerate(zip(poses, rows)):
        hold = {} if held is None else {"hold": {arm.joint_names[6]: float(held[k])}}
        ok = True
        for q in Q:
            got = arm.fk(q)
            position = np.linalg.norm(got.translation - T[:3, 3])
            orientation = np.linalg.norm(pin.log3(got.rotation.T @ T[:3, :3]))
            inside = np.all(q >= arm.lower - 1e-12) and np.all(q <= arm.upper + 1e-12)
            ok &= bool(inside and position < 1e-9 and orientation < 1e-9)
        expected = [r.q for r in arm.solve_all(T, **hold) if r.success]
        if len(expected) != len(Q):
            ok = False
        else:
            for a, b in zip(Q, expected):
                ok &= bool(np.abs(np.angle(np.exp(1j * (a - b)))).max() < 1e-7)
        good += ok
        solutions += len(Q)
    return good, solutions, len(poses) - good


SSIK_HARNESS = r"""
#include <time.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <ssik_cpp/solve.hpp>

static double now()
{
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

// argv: solver data (text), targets (n 4x4 row-major doubles), n, reps, rounds, windings
int main(int argc, char** argv)
{
    if (argc != 7) return 1;
    std::ifstream in(argv[1]);
    ssik::SolverData d;
    int arrays = 0;
    in >> d.family >> arrays;
    for (int a = 0; a < arrays; a++) {
        std::string name, dtype;
        int dims = 0;
        in >> name >> dtype >> dims;
        ssik::DataArray x;
        long count = 1;
        x.shape.resize(dims);
        for (int k = 0; k < dims; k++) { in >> x.shape[k]; count *= x.shape[k]; }
        x.dtype = dtype == "f8" ? ssik::DType::Float64 : ssik::DType::Int32;
        for (long k = 0; k < count; k++) {
            double v;
            in >> v;
            if (dtype == "f8") x.f64.push_back(v); else x.i32.push_back(static_cast<int>(v));
        }
        d.arrays[name] = x;
    }
    ssik::Solver solver(d);
    int n = std::atoi(argv[3]), reps = std::atoi(argv[4]), rounds = std::atoi(argv[5]);
    std::vector<double> raw(16 * n);
    FILE* f = std::fopen(argv[2], "rb");
    if (!f || std::fread(raw.data(), sizeof(double), raw.size(), f) != raw.size()) return 1;
    std::vector<ssik::Pose> poses(n);
    for (int i = 0; i < n; i++)
        for (int r = 0; r < 4; r++)
            for (int c = 0; c < 4; c++) poses[i](r, c) = raw[16 * i + 4 * r + c];
    ssik::ArtifactParams<6> p;
    p.enumerate_windings = std::atoi(argv[6]) != 0;
    double best = 1e30, sum = 0.0;
    long found = 0, refused = 0;
    std::vector<char> ok(n, 1);  // a target ssik refuses (throws for) is left out of the timing
    for (int i = 0; i < n; i++) {
        try {
            found += solver.solve<6>(poses[i], p).size();
        } catch (const std::exception&) {
            ok[i] = 0;
            refused++;
        }
    }
    for (int k = 0; k < rounds; k++) {
        double t0 = now();
        for (int r = 0; r < reps; r++)
            for (int i = 0; i < n; i++) {
                if (!ok[i]) continue;
                std::vector<ssik::Solution<6> > s = solver.solve<6>(poses[i], p);
                sum += s.empty() ? 0.0 : s[0].q[0] + s.size();
            }
        t0 = (now() - t0) / (static_cast<double>(reps) * (n - refused));
        best = t0 < best ? t0 : best;
    }
    std::printf("%.6f %ld %ld %g\n", best * 1e6, found, refused, sum);
    return 0;
}
"""


def ssik_build(folder: Path, eigen: str) -> Path:
    """The ssik harness, compiled once (``ssik_cpp/solve.hpp`` holds every family: minutes)."""
    import ssik.cpp

    (folder / "ssik.cpp").write_text(SSIK_HARNESS)
    exe = folder / "ssik_bench"
    subprocess.run(
        ["c++", "-std=c++17", "-O3", "-march=native", f"-I{ssik.cpp.get_include()}",
         f"-I{eigen}", str(folder / "ssik.cpp"), "-o", str(exe)],
        check=True,
    )  # fmt: skip
    return exe


def ssik_survives(exe: Path, data: Path, turned: np.ndarray, folder: Path) -> np.ndarray:
    """Which targets ssik's C++ solves without the process dying, each in a process of its
    own (with both settings of ``enumerate_windings``): on some arms its ``ssik::sp6``
    corrupts the heap and aborts (SIGABRT, ``munmap_chunk(): invalid pointer``) on a few
    targets, which no ``catch`` can stop."""
    ok = np.ones(len(turned), dtype=bool)
    one = folder / "ssik_one.bin"
    for i in range(len(turned)):
        np.ascontiguousarray(turned[i : i + 1], dtype="<f8").tofile(one)
        for windings in ("0", "1"):
            run = [str(exe), str(data), str(one), "1", "1", "1", windings]
            ok[i] &= subprocess.run(run, capture_output=True).returncode == 0
    return ok


def ssik_time(arm: armik.Arm, poses: np.ndarray, folder: Path, exe: Path, args) -> list:
    """ssik's C++ on the same targets: (mean us a call, solutions, targets it refused or
    died on) with one value a branch (``enumerate_windings`` off, as ``N_ik``) and with its
    default (every 2 pi winding within the limits). The arm is given to ssik as its axis
    lines (``from_axes``), whose tip rotation at q = 0 is the identity: each target's
    rotation is turned to match. When the harness dies (a signal, not an exception), the
    targets it dies on are found one by one (``ssik_survives``) and left out of its
    timing, as the ones it refuses are."""
    import ssik
    import ssik.cpp

    model = arm.kinematics
    ax = axis_lines(model)
    pts = ax.points
    offsets = [
        pts[0],
        *[pts[i] - pts[i - 1] for i in range(1, len(pts))],
        ax.tip_position - pts[-1],
    ]
    limits = np.c_[model.lower, model.upper]
    data = ssik.cpp.solver_data(ssik.Manipulator.from_axes(ax.directions, offsets, limits=limits))
    lines = [f"{data.family} {len(data.arrays)}"]
    for name, a in data.arrays.items():
        dtype = "f8" if a.dtype == np.float64 else "i4"
        head = f"{name} {dtype} {a.ndim} {' '.join(str(k) for k in a.shape)}"
        lines.append(head + " " + " ".join(repr(float(v)) for v in a.ravel()))
    (folder / "ssik.txt").write_text("\n".join(lines) + "\n")
    turned = poses.copy()
    turned[:, :3, :3] = poses[:, :3, :3] @ ax.tip_rotation.T
    died = 0
    for attempt in range(2):
        np.ascontiguousarray(turned, dtype="<f8").tofile(folder / "ssik_targets.bin")
        out = []
        try:
            for windings in ("0", "1"):
                run = [str(exe), str(folder / "ssik.txt"), str(folder / "ssik_targets.bin")]
                run += [str(len(turned)), str(args.reps), str(args.rounds), windings]
                done = subprocess.run(run, check=True, capture_output=True, text=True)
                mean, found, refused, _ = done.stdout.split()
                out.append((float(mean), int(found), int(refused) + died))
        except subprocess.CalledProcessError as error:
            if attempt or error.returncode >= 0:  # an exit code, or again: not a crash
                raise
            ok = ssik_survives(exe, folder / "ssik.txt", turned, folder)
            died, turned = int((~ok).sum()), turned[ok]
        else:
            return out
    raise AssertionError("unreachable")


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
    head = f"{'arm':<24} {'family':<16} {'N_ik (us)':>10} {'solutions':>10} {'checked':>9}"
    if not absent:
        head += (
            f" {'ssik (us)':>10} {'solutions':>10} {'ssik, windings (us)':>20} {'solutions':>10}"
        )
    print(head)
    build = tempfile.TemporaryDirectory()
    exe = None if absent else ssik_build(Path(build.name), args.eigen)
    for robot in args.robots:
        arm = load(robot)
        rng = np.random.default_rng(0)
        qs = np.array([arm.random_q(rng) for _ in range(args.n)])
        poses = np.array([arm.fk(q).homogeneous for q in qs])
        held = qs[:, 6].copy() if arm.dof == 7 else None
        family = family_of(arm.kinematics)
        with tempfile.TemporaryDirectory() as tmp:
            mean, rows = build_and_time(arm, "arm", poses, held, Path(tmp), args)
            timed = exe is not None and held is None
            try:
                peer = ssik_time(arm, poses, Path(tmp), exe, args) if timed else []
            except Exception as error:  # ssik's C++ has no solver for every family
                peer, missing = [], f"  (ssik: {type(error).__name__}: {str(error)[:60]})"
            else:
                missing = ""
        good, solutions, _ = check(arm, poses, rows, held)
        line = f"{robot:<24} {family:<16} {mean:>10.3f} {solutions:>10} {good:>5}/{len(poses)}"
        if peer:
            (one, n_one, r_one), (every, n_every, _) = peer
            line += f" {one:>10.3f} {n_one:>10} {every:>20.3f} {n_every:>10}"
            line += f"  (ssik left out {r_one} targets it refused or died on)" if r_one else ""
        print(line + missing, flush=True)
    build.cleanup()
    if absent:
        print(f"ssik: absent, {absent}")


if __name__ == "__main__":
    main()
