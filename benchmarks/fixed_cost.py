"""What one solve costs outside the iteration, part by part.

For each arm: a target and a q0 at its answer (so the kernel makes one error evaluation
and no step), then best-of-7 timeit of
  - ``arm.solve(T, q0=q)``, whole (without options, and with the benchmark's options),
  - the compiled call alone on the same input (``kernel.single``'s entry for dls, the
    family's ``solve_into`` for a closed form): what runs inside compiled code,
  - Pinocchio's FK and tip placement, and the compiled check of its errors.
"Outside the kernel" is the whole minus the compiled call. For a closed form, also
``arm.solve_all`` and its parts: the compiled call with every row, Pinocchio's placements of
every answer, the compiled check of them all (the rest is Python: rows and results); and
the batch kernel's time per target (``kernel_many`` over 1000 random targets, one call: what
``solve_batch`` runs before its verification) and ``solve_batch``'s on one worker, every
answer verified by Pinocchio. "Bare steps": only what a verified closed-form answer needs
(``bare_steps``), the floor of ``solve`` from Python; and EAIK's all-solutions call on the
same pose when it is installed.

    python benchmarks/fixed_cost.py [--arms panda ur5 abb_irb120] [--solver dls] [--number N]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import timeit

import numpy as np
import pinocchio as pin

import armik
from armik.kernel.measure import placement_check, pose_checks
from armik.result import IKResult
from armik.solve.prepared import plan_for
from armik.solve.read import settings
from armik.tools.compare import _eaik

NOTES: list[str] = []  # why a peer's column is empty (EAIK not installed), printed last

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

BENCH = dict(timeout=0.005, tol_position=1e-5, tol_orientation=1e-5, seed=3)


def best(fn, number: int) -> float:
    return min(timeit.repeat(fn, number=number, repeat=7)) / number * 1e6


def bare_steps(arm, T, q0, plan, solve_into, chain):
    """The steps a verified closed-form answer cannot do without, and nothing else (no
    options, plan lookup, branch label, reason or fallback): the floor of ``solve``.
    ``arm``: the arm's model (``Arm.kinematics``)."""
    model, frame, measured = arm.model, arm.tip_frame_id, plan.measured
    data, R_w, p_w = arm.tip_views()
    # Pinocchio's q: a continuous joint takes (cos, sin); the identity where there is none
    to_pin = (lambda q: q) if arm.model.nq == arm.dof else arm.to_pin
    fk, place, clock, new = (
        pin.forwardKinematics,
        pin.updateFramePlacement,
        time.perf_counter,
        object.__new__,
    )

    def run():
        t0 = clock()
        H = T.homogeneous
        rows = np.empty((8, 11))
        solve_into(chain, H, q0, False, rows)
        q = rows[0, :6]
        q.setflags(write=False)
        fk(model, data, to_pin(q))
        place(model, data, frame)
        pos, ori, inside = placement_check(measured, R_w, p_w, H, q)
        result = new(IKResult)
        result.__dict__.update(
            q=q, success=bool(inside), position_error=pos, orientation_error=ori, time=clock() - t0
        )
        return result

    return run


def measure(name: str, solver: str, number: int) -> dict:
    arm = armik.load(name)
    kin = arm.kinematics
    q = arm.random_q(np.random.default_rng(3))
    T = arm.fk(q)
    H = T.homogeneous
    opts, key, _ = settings(kin, {})
    r = arm.solve(T, q0=q, solver=solver)
    plan = plan_for(kin, r.solver, key, opts)
    runner = plan.run_pose  # the closure holds the compiled entry and its arrays
    cells = dict(zip(runner.__code__.co_freevars, runner.__closure__))
    out = {"arm": name, "solver": r.solver}
    out["solve_us"] = best(lambda: arm.solve(T, q0=q, solver=solver), number)
    out["solve_bench_options_us"] = best(lambda: arm.solve(T, q0=q, solver=solver, **BENCH), number)
    if "entry" in cells:  # numeric: the single-pose entry with the plan's arrays
        entry = cells["entry"].cell_contents
        args = [cells[k].cell_contents for k in ("packed", "kind", "halton_", "sf", "si")]
        dof = arm.dof
        out_q, info, err = np.empty((1, dof)), np.empty(5, np.int64), np.empty(2)
        out["compiled_us"] = best(lambda: entry(*args, H, q, 0, out_q, info, err), number)
    else:  # a closed form: its compiled solve_into
        solve_into = cells["solve_into"].cell_contents
        chain = cells["chain"].cell_contents
        out8 = np.empty((8, 11))
        out["compiled_us"] = best(lambda: solve_into(chain, H, q, False, out8), number)
        out["bare_steps_us"] = best(bare_steps(kin, T, q, plan, solve_into, chain), number)
        peer = _eaik(arm, NOTES)  # None when EAIK is not installed or does not apply
        if peer is not None:  # its all-solutions call, timed the same way on the same pose
            H_peer = peer.fwdKin(np.asarray(q))
            out["eaik_us"] = best(lambda: peer.IK(H_peer), number)
        out["solve_all_us"] = best(lambda: arm.solve_all(T, q0=q), number)
        out["compiled_every_us"] = best(lambda: solve_into(chain, H, q, True, out8), number)
        Q = runner(H, q, 0, True).q  # every branch's answers
        out["placements_us"] = best(lambda: plan._placements(Q), number)
        H_all, measured = plan._placements(Q), np.empty((len(Q), 3))
        out["checks_us"] = best(lambda: pose_checks(plan.measured, H_all, H, Q, measured), number)
        module = sys.modules[solve_into.__module__]  # the family's kernel_many beside it
        rng = np.random.default_rng(4)
        qs = np.array([arm.random_q(rng) for _ in range(1000)])
        Hs = np.array([arm.fk(x).homogeneous for x in qs])
        Rs, ps = np.ascontiguousarray(Hs[:, :3, :3]), np.ascontiguousarray(Hs[:, :3, 3])
        q0s = np.ascontiguousarray(np.roll(qs, 1, axis=0))  # another target's configuration
        many = module.kernel_many
        out["batch_kernel_us"] = best(lambda: many(chain, Rs, ps, q0s), max(1, number // 1000))
        out["batch_kernel_us"] /= 1000
        # the same targets through solve_batch on one worker, every answer verified by Pinocchio
        batch = lambda: arm.solve_batch(Hs, q0=q0s, workers=1)  # noqa: E731
        out["solve_batch_us"] = best(batch, max(1, number // 1000)) / 1000
    model, frame = kin.model, kin.tip_frame_id
    qp = kin.to_pin(q)
    data, R_w, p_w = kin.tip_views()

    def fk():
        pin.forwardKinematics(model, data, qp)
        pin.updateFramePlacement(model, data, frame)

    out["pinocchio_fk_us"] = best(fk, number)
    fk()
    args = (plan.measured, R_w, p_w, H, q)
    out["check_us"] = best(lambda: placement_check(*args), number)
    out["outside_us"] = out["solve_us"] - out["compiled_us"]
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--arms", nargs="+", default=["panda", "kinova", "ur5", "abb_irb120"])
    p.add_argument("--solver", default="auto", help="dls, qp, a closed form or auto")
    p.add_argument("--number", type=int, default=5000)
    args = p.parse_args()
    cols = [
        "solve_us",
        "solve_bench_options_us",
        "compiled_us",
        "outside_us",
        "bare_steps_us",
        "pinocchio_fk_us",
        "check_us",
    ]
    cols += [
        "eaik_us",
        "solve_all_us",
        "compiled_every_us",
        "placements_us",
        "checks_us",
        "batch_kernel_us",
        "solve_batch_us",
    ]
    print("| arm | solver | " + " | ".join(c.replace("_us", " (us)") for c in cols) + " |")
    print("|---|---|" + "---|" * len(cols))
    for name in args.arms:
        m = measure(name, args.solver, args.number)
        cells = (f"{m[c]:.2f}" if c in m else "n/a" for c in cols)  # solve_all: closed forms
        print(f"| {name} | {m['solver']} | " + " | ".join(cells) + " |")
    for note in NOTES:
        print(note)


if __name__ == "__main__":
    main()
