"""One call of each feature, bounded by iterations: the answers ``test_tier`` compares when
run compiled and run as Python (``ARMIK_FIRST_CALLS=python``). Run as a script, it writes
them to the ``.npz`` file it is given."""

from __future__ import annotations

import sys
from importlib import metadata
from pathlib import Path

import numpy as np

import armik

BUDGET = {"iteration_budget": 400, "max_restarts": 3}  # the same work however fast


def answers() -> dict[str, np.ndarray]:
    got: dict[str, np.ndarray] = {}

    def keep(name: str, results) -> None:
        results = results if isinstance(results, list) else [results]
        got[name] = np.array([r.q for r in results])
        got[name + ".ok"] = np.array([r.success for r in results])

    panda = armik.load("panda")
    T = panda.fk(panda.middle + 0.2)
    keep("dls_weights", panda.solve(T, solver="dls", weights=(1, 1, 1, 1, 1, 0.5), **BUDGET))
    keep("qp", panda.solve(T, solver="qp", **BUDGET))
    keep("tolerance", panda.solve(T, bounds=(0.01, 0.01, 0.01, 0.1, 0.1, 0.1), **BUDGET))
    keep("swept_all", list(panda.solve_all(T, solver="swept")))
    batch = panda.solve_batch(panda.fk_batch(panda.random_q(0, n=6)), workers=1, progress=False)
    got["batch"], got["batch.ok"] = batch.q, batch.success
    path = panda.solve_path([panda.fk(panda.middle + 0.01 * k) for k in range(4)], panda.middle)
    keep("path", list(path))
    ur5 = armik.load("ur5")
    keep("ur5_all", list(ur5.solve_all(ur5.fk(ur5.middle + 0.2))))
    planar = armik.load("planar_2link")
    keep("planar_all", list(planar.solve_all([1.2, 0.5])))
    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share")))
    urdf = share / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    talos = armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])
    q = talos.random_q(np.random.default_rng(14))
    r = talos.solve({tip: talos.fk(q, frame=tip) for tip in talos.tips}, **BUDGET)
    got["talos"], got["talos.ok"] = r.q[None], np.array([r.success])
    return got


if __name__ == "__main__":
    np.savez(sys.argv[1], **answers())
