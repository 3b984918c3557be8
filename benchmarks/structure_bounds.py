"""Warm costs on arms whose structure bounds their targets (docs/performance.md, "An arm
whose structure bounds its targets"): the median CPU time of ``arm.solve`` (dls, seed 0)
over ``--rounds`` calls cycling through 20 reached poses (the FK of random
configurations, seed 0), q0 the pose's configuration times 0.99 on the SCARA and 0.05
(rad or m) off every joint, within the limits, on the others; of a 20-row
``solve_batch`` of those poses (one worker); and, on the SCARA, of the cheap measures a
reachable target passes (``structure.beyond``) and of the exact measure of a rotation
tilted 0.3 rad off the family (``orientations.refused``). The arms: the SCARA,
planar_3link, a three-slide gantry on a rail without limits, a gantry with a wrist on a
rail 10 m long, and the UR5 and the Panda (no bounds: the cost of asking).

    python benchmarks/structure_bounds.py [--rounds 400]

from a checkout: the gantries are the tests' (``tests/solvers/numeric``).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
import pinocchio as pin

import armik

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))  # the tests package
from tests.solvers.numeric.test_long_rail import GANTRY  # noqa: E402
from tests.solvers.numeric.test_slides import XYZ  # noqa: E402

from armik.options import Options  # noqa: E402
from armik.solvers.numeric import orientations, structure  # noqa: E402


def arms() -> dict:
    return {
        "scara": armik.load("scara"),
        "planar_3link": armik.load("planar_3link"),
        "gantry, rail without limits": armik.load_string(XYZ).with_limits(
            {"px": (-np.inf, np.inf)}
        ),
        "gantry with a wrist, 10 m rail": armik.load_string(GANTRY.replace("RAIL", "10")),
        "ur5": armik.load("ur5"),
        "panda": armik.load("panda"),
    }


def median_us(call, rounds: int) -> float:
    """The median CPU time (us) of ``call(k)`` for k in range(rounds), after 20 warm calls."""
    for k in range(20):
        call(k)
    times = []
    for k in range(rounds):
        t0 = time.process_time_ns()
        call(k)
        times.append(time.process_time_ns() - t0)
    return float(np.median(times)) / 1e3


def measure(name: str, arm, rounds: int) -> dict:
    rng = np.random.default_rng(0)
    Q = [arm.random_q(rng) for _ in range(20)]
    T = [arm.fk(q) for q in Q]
    off = [np.clip(q + 0.05, arm.kinematics.lower, arm.kinematics.upper) for q in Q]
    Q0 = [q * 0.99 for q in Q] if name == "scara" else off

    def solve(k: int) -> None:
        r = arm.solve(T[k % 20], q0=Q0[k % 20], solver="dls", seed=0)
        assert r.success, (name, r.reason)

    out = {"solve": median_us(solve, rounds)}
    batch = lambda k: arm.solve_batch(T, solver="dls", seed=0, workers=1, progress=False)  # noqa: E731
    out["batch"] = median_us(batch, max(rounds // 20, 5))
    if name == "scara":
        opts, sf, kin = Options(), np.zeros(32), arm.kinematics
        R, P = [t.rotation for t in T], [t.translation for t in T]
        out["beyond"] = median_us(
            lambda k: structure.beyond(kin, R[k % 20], P[k % 20], opts, sf), rounds
        )
        tilt = pin.exp3(np.array([0.3, 0.0, 0.0]))
        tilted = [tilt @ r for r in R]
        assert orientations.refused(kin, tilted[0], opts) is not None
        out["exact rotation"] = median_us(
            lambda k: orientations.refused(kin, tilted[k % 20], opts), rounds
        )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=400)
    args = parser.parse_args()
    for name, arm in arms().items():
        m = measure(name, arm, args.rounds)
        print(f"{name}: " + ", ".join(f"{k} {v:.1f} us" for k, v in m.items()))


if __name__ == "__main__":
    main()
