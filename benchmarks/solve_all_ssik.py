"""Every solution of a 6R arm: armik's ``solve_all`` against ssik's ``solve`` with one
configuration a branch (``enumerate_windings=False``), interleaved target by target.

Per arm, N seeded random configurations within the limits and their FK poses as targets;
per target, in turn (the order alternating): armik's ``arm.solve_all(T)`` (every branch,
each verified; the ``IKResult``s are built on first access, ``armik.solutions``), the same
call with each result read (``[r.q for r in arm.solve_all(T) if r.success]``: every
``IKResult`` built) and ssik's ``Manipulator.solve(T, enumerate_windings=False)``
(every branch within the limits, its own FK closure check), each timed ``--repeats`` times,
the median kept. ssik is given the arm as armik reads it from the URDF (its axis lines,
``Manipulator.from_axes``, the limits), each target's rotation turned to that model's tip,
so both solve the same kinematics, base and tip; its solve is called as its prebuilt
artifacts call it (``ssik._native.try_native_solve``: the C++ extension, limits applied;
``Manipulator.solve`` on such an arm runs its Python solver, about 1 ms). Then, per
target:

- the solution sets: armik's successes against ssik's answers, each joint within 1e-6 rad
  modulo 2 pi, both ways;
- false solutions: an answer of either whose tip, by Pinocchio's FK computed here, is
  more than 1e-9 m or 1e-9 rad from the target, or outside the limits.

The KUKA KR 6 R900 sixx (Agilus) is no URDF armik ships: its URDF is written here from the
numbers ssik's prebuilt ``kr6_r900_ik`` module bakes (joint origins, axes, limits; checked
against that module's home pose when ssik is importable). The two non-Pieper arms, the
Kinova JACO 2 (j2n6s200, a 60-degree wrist) and the UFactory xArm6 (an offset wrist: joint 6
off joint 5), are written from their ssik artifacts' baked constants (``ssik_prebuilt.py``,
which needs ssik) and solved by their artifacts' native call with the baked Raghavan-Roth
tensor; armik takes ``elimination_6r`` on both:

    PYTHONPATH=/tmp/peerpkgs python benchmarks/solve_all_ssik.py -n 200 \
        --arms kinova_jaco2 ufactory_xarm6

ssik is for measuring only, never a dependency of armik:

    pip install --no-deps --target /tmp/peerpkgs ssik cython
    PYTHONPATH=/tmp/peerpkgs python benchmarks/solve_all_ssik.py -n 200

Without ssik the script times armik alone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin
import ssik_prebuilt
from srs_ssik import timed  # the median of repeated calls, as the SRS benchmark times them

import armik
from armik.model.geometry import axis_lines

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

ARMS = ("ur5", "ur10", "abb_irb120", "kuka_kr6_r900", "kinova_jaco2", "ufactory_xarm6")
SAME = 1e-6  # rad: one joint of two solutions of one set
FALSE = 1e-9  # m and rad: an answer further from its target is a false solution

# KUKA KR 6 R900 sixx: joint i's origin in joint i - 1 (m), its axis, its limits (rad), as
# ssik 8.2.0's prebuilt kr6_r900_ik bakes them (T_left of each joint; T_right identity)
KR6 = (
    ((0.0, 0.0, 0.4), (0.0, 0.0, -1.0), (-2.9670597283903604, 2.9670597283903604)),
    ((0.025, 0.0, 0.0), (0.0, 1.0, 0.0), (-3.3161255787892263, 0.7853981633974483)),
    ((0.455, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0943951023931953, 2.722713633111154)),
    ((0.0, 0.0, 0.035), (-1.0, 0.0, 0.0), (-3.2288591161895095, 3.2288591161895095)),
    ((0.42, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0943951023931953, 2.0943951023931953)),
    ((0.08, 0.0, 0.0), (-1.0, 0.0, 0.0), (-6.1086523819801535, 6.1086523819801535)),
)


def kr6_urdf() -> str:
    """The KR 6 R900 sixx's kinematic URDF: base_link to link_6."""
    parts = ['<robot name="kuka_kr6_r900">', '<link name="base_link"/>']
    for i, (xyz, axis, (lo, hi)) in enumerate(KR6, start=1):
        parent = "base_link" if i == 1 else f"link_{i - 1}"
        parts += [
            f'<link name="link_{i}"/>',
            f'<joint name="joint_{i}" type="revolute"><parent link="{parent}"/>'
            f'<child link="link_{i}"/><origin xyz="{xyz[0]!r} {xyz[1]!r} {xyz[2]!r}"/>'
            f'<axis xyz="{axis[0]!r} {axis[1]!r} {axis[2]!r}"/>'
            f'<limit lower="{lo!r}" upper="{hi!r}" effort="1" velocity="1"/></joint>',
        ]
    return "\n".join([*parts, "</robot>"])


def load(name: str, folder: Path) -> armik.Arm:
    if name in ssik_prebuilt.ARTIFACTS:
        arm = armik.load_string(ssik_prebuilt.urdf(name), base="base", tip="tool")
        home = ssik_prebuilt.constants(name)["T_HOME"]  # the artifact's own check
        assert np.allclose(arm.fk(np.zeros(6)).homogeneous, home, atol=1e-12)
        return arm
    if name != "kuka_kr6_r900":
        return armik.load(name)
    path = folder / "kuka_kr6_r900.urdf"
    path.write_text(kr6_urdf())
    return armik.load(str(path), tip="link_6")


def ssik_of(arm: armik.Arm, name: str):
    """(ssik's solver of ``arm`` as armik reads it, the rotation that turns a target's
    rotation to that solver's tip), or None without ssik."""
    try:
        import ssik
    except ImportError:
        return None
    if name in ssik_prebuilt.ARTIFACTS:  # its artifact's solver: the same base and tip
        return ssik_prebuilt.solver(name), np.eye(3)
    ax = axis_lines(arm.kinematics)
    pts = ax.points
    offsets = [pts[0], *[pts[i] - pts[i - 1] for i in range(1, len(pts))]]
    offsets.append(ax.tip_position - pts[-1])
    limits = np.c_[arm.lower, arm.upper]
    m = ssik.Manipulator.from_axes(ax.directions, offsets, limits=limits)
    from ssik._native import try_native_solve

    name, kb = m.solver_name, m.kinbody

    def solve(H: np.ndarray) -> list:
        """ssik's every branch of ``H`` within the limits, one a branch (its artifacts'
        native call; its Python solver where the extension has no such family)."""
        got = try_native_solve(name, kb, H, enumerate_windings=False)
        return m.solve(H, enumerate_windings=False) if got is None else got

    return solve, ax.tip_rotation.T


def same_set(a: list, b: list) -> bool:
    """Each configuration of ``a`` has one of ``b`` within ``SAME`` (each joint, modulo
    2 pi), and the other way round."""

    def near(x, y) -> bool:
        d = np.asarray(x) - np.asarray(y)
        return bool(np.all(np.abs(np.arctan2(np.sin(d), np.cos(d))) < SAME))

    return all(any(near(x, y) for y in b) for x in a) and all(any(near(y, x) for x in a) for y in b)


def false_solutions(arm: armik.Arm, T: pin.SE3, qs: list) -> int:
    """The answers of ``qs`` whose tip, by Pinocchio's FK, misses ``T`` by more than
    ``FALSE`` (m, rad), or that leave the limits."""
    model = arm.kinematics
    bad = 0
    for q in qs:
        pin.forwardKinematics(model.model, model.data, model.to_pin(np.asarray(q)))
        tip = model.T_base_world * pin.updateFramePlacement(
            model.model, model.data, model.tip_frame_id
        )
        error = pin.log6(tip.actInv(T)).vector
        off = np.linalg.norm(error[:3]) > FALSE or np.linalg.norm(error[3:]) > FALSE
        bad += off or not model.within_limits(np.asarray(q, dtype=float))
    return bad


def run_arm(name: str, n: int, seed: int, repeats: int, folder: Path) -> dict:
    arm = load(name, folder)
    peer = ssik_of(arm, name)
    rng = np.random.default_rng(seed)
    targets = [arm.fk(arm.random_q(rng)) for _ in range(n)]
    arm.solve_all(targets[0])  # compiles, caches: outside the timing
    if peer is not None:
        peer[0](targets[0].homogeneous)
    ours_t: list[float] = []
    read_t: list[float] = []  # with every result read
    theirs_t: list[float] = []
    equal = false_ours = false_theirs = solutions = 0
    for i, T in enumerate(targets):
        H = T.homogeneous
        calls = [
            ("armik", lambda T=T: arm.solve_all(T)),
            ("read", lambda T=T: [r.q for r in arm.solve_all(T) if r.success]),
        ]
        if peer is not None:
            solver, turn = peer
            Hs = H.copy()
            Hs[:3, :3] = H[:3, :3] @ turn
            calls.append(("ssik", lambda solver=solver, Hs=Hs: solver(Hs)))
        if i % 2:
            calls.reverse()
        outs = {}
        for who, call in calls:
            seconds, outs[who] = timed(call, repeats)
            {"armik": ours_t, "read": read_t, "ssik": theirs_t}[who].append(seconds)
        ours = [r.q for r in outs["armik"] if r.success]
        solutions += len(ours)
        false_ours += false_solutions(arm, T, ours)
        if peer is not None:
            theirs = [np.asarray(s.q) for s in outs["ssik"]]
            false_theirs += false_solutions(arm, T, theirs)
            equal += same_set(ours, theirs)
    return dict(name=name, ours=ours_t, read=read_t, theirs=theirs_t, equal=equal,
                false_ours=false_ours, false_theirs=false_theirs, solutions=solutions, n=n,
                peer=peer is not None)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-n", type=int, default=200, help="targets an arm (200)")
    parser.add_argument(
        "--arms", nargs="+", default=list(ARMS), choices=(*ARMS, *ssik_prebuilt.ARTIFACTS)
    )
    parser.add_argument("--seed", type=int, default=53)
    parser.add_argument("--repeats", type=int, default=5, help="calls a target, median kept")
    args = parser.parse_args()
    print(f"{args.n} targets an arm (seed {args.seed}), median of {args.repeats} calls each")
    print()
    print("| arm | armik solve_all median (us) | mean (us) | ssik solve median (us) "
          "| mean (us) | median ratio | mean ratio | each result read: median (us) | ratio "
          "| same set | false (armik / ssik) | solutions |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name in args.arms:
            r = run_arm(name, args.n, args.seed, args.repeats, Path(folder))
            ours, read, theirs = r["ours"], r["read"], r["theirs"]
            row = [name, *(f"{1e6 * f(ours):.1f}" for f in (statistics.median, statistics.mean))]
            if r["peer"]:
                row += [f"{1e6 * f(theirs):.1f}" for f in (statistics.median, statistics.mean)]
                row += [f"{statistics.median(ours) / statistics.median(theirs):.2f}"]
                row += [f"{statistics.mean(ours) / statistics.mean(theirs):.2f}"]
                row += [f"{1e6 * statistics.median(read):.1f}"]
                row += [f"{statistics.median(read) / statistics.median(theirs):.2f}"]
                row += [f"{r['equal']}/{r['n']}", f"{r['false_ours']} / {r['false_theirs']}"]
            else:
                row += ["", "", "", "", f"{1e6 * statistics.median(read):.1f}", "", "",
                        f"{r['false_ours']} / "]  # fmt: skip
            row.append(str(r["solutions"]))
            print("| " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
