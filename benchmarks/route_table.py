"""The route of one warm call on each of ten routes (the "one request" table): Python calls
inside armik, modules entered, calls against the direction of the imports, target parses,
as ``../shared/tools/route.py`` measures them (it sits beside the project's checkout).

    python benchmarks/route_table.py [--modules]   (from the project's root, in its environment)

``--modules``: each call's modules too, with their floors, in the order it enters them.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

ROOT = Path(__file__).resolve().parents[1]
ROUTE = ROOT.parent / "shared" / "tools" / "route.py"
IMPORTS = "import numpy as np, pinocchio as pin; "
UR5 = "arm = armik.load('ur5'); T = arm.fk(arm.middle + 0.1)"
PANDA = "arm = armik.load('panda'); T = arm.fk(arm.middle + 0.1)"
TALOS = (
    "from importlib import metadata; from pathlib import Path; "
    "share = Path(str(metadata.distribution('example-robot-data').locate_file("
    "'cmeel.prefix/share'))); arm = armik.load(share / 'example-robot-data/robots/talos_data/"
    "robots/talos_reduced.urdf', tips=['gripper_left_base_link', 'gripper_right_base_link']); "
    "q = arm.random_q(3); T = {t: arm.fk(q, t) for t in arm.tips}"
)
ROWS = [
    ("UR5 solve(T)", UR5, "arm.solve(T)"),
    ("UR5 solve(T, bounds=...)", UR5, "arm.solve(T, bounds=(0.01,)*3+(0.1,)*3)"),
    ("UR5 solve_all(T)", UR5, "arm.solve_all(T)"),
    (
        "Panda solve(T, obstacles=[sphere])",
        PANDA + "; s = [armik.Sphere(0.05, (2, 2, 2))]",
        "arm.solve(T, obstacles=s)",
    ),
    (
        "Panda solve((p, quat), prefer='manipulability')",
        PANDA + "; t = (T.translation, pin.Quaternion(T.rotation).coeffs())",
        "arm.solve(t, prefer='manipulability')",
    ),
    ("Panda solve(T, hold=joint 7)", PANDA, "arm.solve(T, hold={'panda_joint7': 0.3})"),
    ("Panda solve_all(T)", PANDA, "arm.solve_all(T)"),
    (
        "Panda solve_batch(4 poses, workers=1)",
        "arm = armik.load('panda'); T = arm.fk_batch(arm.random_q(0, n=4))",
        "arm.solve_batch(T, workers=1)",
    ),
    (
        "UR5 solve_path(3 poses, q)",
        "arm = armik.load('ur5'); q = arm.middle + 0.1; T = arm.fk(q); "
        "P = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]",
        "arm.solve_path(P, q)",
    ),
    ("TALOS Arms.solve, both hands", TALOS, "arm.solve(T)"),
]


def main() -> None:
    if not ROUTE.is_file():
        sys.exit(f"{ROUTE} is not there: the shared tools sit beside the project's checkout")
    for label, setup, call in ROWS:
        out = subprocess.run(
            [sys.executable, str(ROUTE), IMPORTS + setup, call],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        lines = out.splitlines()
        print(f"{label:50s} {lines[0]}")
        if "--modules" in sys.argv[1:]:
            print("\n".join(lines[1:]))


if __name__ == "__main__":
    main()
