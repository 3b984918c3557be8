"""Full-pose IK on a 6-DOF (UR5) and a 7-DOF (Panda) arm with dls and qp."""

import numpy as np
import pinocchio as pin
from _common import out_dir

import armik

out_dir(__doc__, figures=False)  # takes --out like every example; writes no figure

rng = np.random.default_rng(0)
print(
    f"{'arm':<6} {'solver':<5} {'success':<8} {'pos err (m)':>12} {'ori err (rad)':>14} "
    f"{'iters':>6} {'time (ms)':>10}"
)
for name in ("ur5", "panda"):
    arm = armik.load(name)
    target = arm.fk(arm.random_q(rng))
    for solver in ("dls", "qp"):
        r = arm.solve(target, q0=arm.middle, solver=solver)
        print(
            f"{name:<6} {solver:<5} {r.success!s:<8} {r.position_error:>12.2e} "
            f"{r.orientation_error:>14.2e} {r.iterations:>6} {r.time * 1e3:>10.3f}"
        )
    far = pin.SE3(np.eye(3), np.array([2.0, 0.0, 0.5]))
    r = arm.solve(far)
    print(f"{name:<6} target 2 m away: success={r.success}, status={r.status}: {r.reason}")
