"""Full-pose IK on a 6-DOF (UR5) and a 7-DOF (Panda) arm with dls and qp, and the Panda's
closed form with joint 7 held (solver "swept")."""

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

# The Panda in closed form: joint 7 held at q0's value, every branch of joints 1-6.
panda = armik.load("panda")
q = panda.random_q(rng)
branches = [r for r in panda.solve_all(panda.fk(q), q0=q, solver="swept") if r.success]
found = any(np.allclose(r.q, q, atol=1e-9) for r in branches)
print(
    f"panda swept: joint 7 held at {q[6]:.4f} rad, {len(branches)} verified branches, "
    f"the configuration of the target among them: {found}"
)
