"""Seeing the answers: every branch of a UR5 target drawn with ``armik.plot``, then the same
target in the browser viewer (when viser is installed), which closes itself here.

1. ``armik.plot``: one panel per branch of ``solve_all``, the target's axes dashed. Writes
   ur5_branches.png into --out (docs/ur5_branches.png is this figure).
2. ``armik.view``: ``set_target`` gives what ``arm.solve`` gives, ``play`` walks a path.
   Interactively, ``armik view ur5`` (or ``viewer.wait()``) keeps the page up until Ctrl-C.
"""

import importlib.util

import numpy as np
import pinocchio as pin
from _common import out_dir, pyplot

import armik

out = out_dir(__doc__)
plt = pyplot()

ur5 = armik.load("ur5")
q = np.array([0.4, -1.1, 1.3, -1.6, -1.4, 0.3])
T = ur5.fk(q)
solutions = ur5.solve_all(T, q0=q)
print(f"{len(solutions)} branches, all verified: {all(r.success for r in solutions)}")

if plt is not None:
    fig = plt.figure(figsize=(15, 7.6), layout="constrained")
    for k, r in enumerate(solutions):
        ax = fig.add_subplot(2, (len(solutions) + 1) // 2, k + 1, projection="3d")
        title = r.branch.replace("/", "\n") + ("" if k else "\n(nearest q0)")
        armik.plot(ur5, r, ax=ax, target=T, title=title, elev=20, azim=-50)
    fig.suptitle("ur5: every solution of one target (three_parallel), drawn by armik.plot")
    path = out / "ur5_branches.png"
    fig.savefig(path, dpi=80)
    print(f"wrote {path}")

if importlib.util.find_spec("viser") is None:
    print('viewer skipped: pip install "armik[view]"')
else:
    with armik.view(ur5, port=0, open_browser=False, q=q) as viewer:  # port 0: any free port
        r = viewer.set_target(T, q0=solutions[3].q)
        print(f"viewer at {viewer.url}: {r.status} on {r.branch}, as arm.solve gives:",
              np.array_equal(r.q, ur5.solve(T, q0=solutions[3].q).q))  # fmt: skip
        line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(10)]
        viewer.play(ur5.solve_path(line, viewer.q), fps=200)
        print(f"played 10 waypoints, the arm now at the last: {viewer.q.round(3).tolist()}")
