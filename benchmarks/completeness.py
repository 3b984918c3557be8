"""Completeness and truth of ``solve_all``'s closed forms: misses, false rows, duplicates.

For each case (a bundled arm with a closed form, a 7R arm with one joint held or swept, a
random 6R arm of each kind of ``armik.model.random_arms``), ``--configs`` configurations q
within the limits, the target ``T = fk(q)``, and ``solve_all(T)``. Counted per case:

- miss: no success within 1e-6 rad of q (each revolute joint modulo 2 pi);
- none: no success at all (a reachable target answered as a failure);
- false: a success whose pose an independent Pinocchio FK puts more than 1e-9 (m, rad)
  from the target;
- limits: a success outside the joint limits;
- dup: two successes within 1e-9 of each other;
- over: more successes than the family's maximum (2 planar, 8 Pieper, 16 general 6R).

``--near`` draws the targets near singular configurations instead: the wrist (q5 at 0 and
at +-1e-9 ... 1e-5), the elbow (q3 where the arm is stretched: found by a scan) and the
joint limits (a joint at its limit). Prints one line per case; nothing is timed. With
the iiwa's joint 4 held, the chain left keeps a self-motion (a free joint,
flagged singular): its rows are one value of it, so "miss" counts every target there.

    python benchmarks/completeness.py [--configs 300] [--arms 3] [--near] [--cases ur5 ...]
"""

from __future__ import annotations

import argparse
import os

import numpy as np
import pinocchio as pin

import armik
from armik.model.random_arms import KINDS, random_urdf

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # compiled code, not Python runs

# the most solutions of a family: Pieper's 6R arms (and one swivel or held joint 7), others
PIEPER = 8
GENERAL = 16


def bundled_cases() -> dict[str, tuple]:
    """case name -> (arm, options(q) -> solve_all keywords, maximum count)."""
    cases: dict[str, tuple] = {}
    for name, most in (
        ("planar_2link", 2),
        ("double_pendulum", 2),
        ("abb_irb120", PIEPER),
        ("kinova", PIEPER),
        ("ur5", PIEPER),
        ("ur10", PIEPER),
        ("z1", PIEPER),
    ):
        cases[name] = (armik.load(name), lambda q: {}, most)
    iiwa, panda, xarm = armik.load("kuka_iiwa14"), armik.load("panda"), armik.load("xarm7")
    cases["kuka_iiwa14 srs q0"] = (iiwa, lambda q: {"q0": q}, PIEPER)
    cases["panda swept q0"] = (panda, lambda q: {"q0": q, "solver": "swept"}, PIEPER)
    cases["kuka_iiwa14 swept q0"] = (iiwa, lambda q: {"q0": q, "solver": "swept"}, PIEPER)
    for arm in (iiwa, panda, xarm):
        for j, joint in enumerate(arm.joint_names):
            cases[f"{arm.name} hold {joint}"] = (
                arm,
                lambda q, joint=joint, j=j: {"hold": {joint: float(q[j])}},
                GENERAL,
            )
    return cases


def random_cases(arms: int, seed: int) -> dict[str, tuple]:
    rng = np.random.default_rng(seed)
    cases: dict[str, tuple] = {}
    for kind in KINDS:
        most = PIEPER if kind in ("parallel_23", "meeting_12", "three_parallel") else GENERAL
        for k in range(arms):
            arm = armik.load_string(random_urdf(kind, rng), base="world", tip="tool")
            cases[f"random {kind} #{k}"] = (arm, lambda q: {}, most)
    return cases


class Checker:
    """An independent Pinocchio FK of ``arm``'s tip (its own Data)."""

    def __init__(self, arm: armik.Arm) -> None:
        kin = arm.kinematics
        self.kin, self.model = kin, kin.model
        self.data = kin.model.createData()
        self.revolute = np.array([t != "prismatic" for t in arm.joint_types])
        self.lower, self.upper = arm.lower, arm.upper

    def fk(self, q: np.ndarray) -> pin.SE3:
        pin.forwardKinematics(self.model, self.data, self.kin.to_pin(np.asarray(q)))
        T = pin.updateFramePlacement(self.model, self.data, self.kin.tip_frame_id)
        return self.kin.T_base_world * T

    def error(self, q: np.ndarray, T: pin.SE3) -> float:
        A = self.fk(q)
        dp = np.linalg.norm(A.translation - T.translation)
        dr = np.linalg.norm(pin.log3(A.rotation.T @ T.rotation))
        return float(max(dp, dr))

    def distance(self, a: np.ndarray, b: np.ndarray) -> float:
        d = np.asarray(a) - np.asarray(b)
        d = np.where(self.revolute, np.angle(np.exp(1j * d)), d)
        return float(np.abs(d).max()) if d.size else 0.0


def near_qs(arm: armik.Arm, rng: np.random.Generator, n: int) -> list[np.ndarray]:
    """Configurations near the wrist singularity (q5 ~ 0), at a joint limit, or random."""
    out = []
    for i in range(n):
        q = arm.random_q(rng)
        kind = i % 3
        if kind == 0 and arm.dof >= 5:
            q[4] = float(rng.choice([0.0, 1e-9, -1e-9, 1e-7, -1e-7, 1e-5, -1e-5]))
        elif kind == 1:
            j = int(rng.integers(arm.dof))
            limit = arm.lower[j] if rng.random() < 0.5 else arm.upper[j]
            q[j] = limit if np.isfinite(limit) else q[j]
        out.append(np.clip(q, arm.lower, arm.upper))
    return out


def measure(arm: armik.Arm, options, most: int, qs: list[np.ndarray]) -> dict:
    check = Checker(arm)
    counts = dict.fromkeys(("miss", "none", "false", "limits", "dup", "over"), 0)
    examples: list[np.ndarray] = []
    for q in qs:
        T = arm.fk(q)
        rows = [r for r in arm.solve_all(T, **options(q)) if r.success]
        bad = False
        if not rows:
            counts["none"] += 1
            bad = True
        elif min(check.distance(r.q, q) for r in rows) > 1e-6:
            counts["miss"] += 1
            bad = True
        for r in rows:
            if check.error(r.q, T) > 1e-9:
                counts["false"] += 1
                bad = True
            if np.any(r.q < check.lower - 1e-12) or np.any(r.q > check.upper + 1e-12):
                counts["limits"] += 1
                bad = True
        for i in range(len(rows)):
            for j in range(i):
                if np.abs(rows[i].q - rows[j].q).max() < 1e-9:
                    counts["dup"] += 1
                    bad = True
        if len(rows) > most:
            counts["over"] += 1
            bad = True
        if bad and len(examples) < 3:
            examples.append(q)
    counts["targets"] = len(qs)
    counts["examples"] = examples
    return counts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--configs", type=int, default=300)
    ap.add_argument("--arms", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--near", action="store_true")
    ap.add_argument("--cases", nargs="*", default=None, help="case names starting with these")
    ap.add_argument("--examples", action="store_true", help="print failing configurations")
    args = ap.parse_args()
    cases = {**bundled_cases(), **random_cases(args.arms, args.seed)}
    if args.cases:
        cases = {k: v for k, v in cases.items() if any(k.startswith(c) for c in args.cases)}
    keys = ("targets", "miss", "none", "false", "limits", "dup", "over")
    print(f"{'case':44} " + " ".join(f"{k:>7}" for k in keys))
    for name, (arm, options, most) in cases.items():
        rng = np.random.default_rng(args.seed)
        n = args.configs
        qs = near_qs(arm, rng, n) if args.near else list(arm.random_q(rng, n))
        m = measure(arm, options, most, qs)
        print(f"{name:44} " + " ".join(f"{m[k]:>7}" for k in keys), flush=True)
        if args.examples:
            for q in m["examples"]:
                print("    q =", np.array2string(q, precision=17, separator=", "))


if __name__ == "__main__":
    main()
