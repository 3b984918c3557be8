"""The swept closed form (joint 7 held, swept over its range) on Panda targets that only an
interval of joint 7 narrower than its sweep's cells reaches within the limits (two joints
of the configuration that gave the target on their limits): ``solver="swept"`` finds a
value there, ``solve`` and ``solve_all`` alike, each answer checked by Pinocchio's FK in
the test, where every cell's value of joint 7 leaves each branch outside the limits."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik.solvers.closed_form import swept_7r
from armik.targets.pose import parse_target

from .. import conftest

# configurations whose pose only such an interval reaches (joints on their limits)
NARROW = [
    [-0.7171483796247653, -0.27879953113667266, 0.9560177139690178, -3.0717,
     0.5013390966232243, -0.0174, 1.312323982316062],
    [-1.237199109596829, -1.7627, 2.675579760887484, -1.1317968374785528, -2.8972,
     2.664361294820573, -1.641207559973024],
    [-1.173294586693089, -0.3975942012003586, -1.9235913939905918, -2.846616538785245,
     -2.8972, 3.7524, -0.2270246466431578],
]  # fmt: skip


def _no_cell_within(arm, T, q0) -> bool:
    """Whether no branch is within the limits at any of the sweep's cell centres."""
    model = arm.kinematics
    exact = swept_7r.exact_at(model, parse_target(T, model), q0)
    lo, hi = swept_7r.sweep_range(model, float(q0[6]))
    width = (hi - lo) / swept_7r.SWEEP
    for k in range(swept_7r.SWEEP):
        Q = exact(lo + (k + 0.5) * width)
        if ((Q >= model.lower - 1e-9) & (Q <= model.upper + 1e-9)).all(axis=1).any():
            return False
    return True


@pytest.mark.parametrize("q", NARROW)
def test_a_narrow_interval_of_joint_7_is_found(q):
    arm = conftest.arm("panda")
    T = arm.fk(np.array(q))
    q0 = np.asarray(arm.middle, dtype=float)
    assert _no_cell_within(arm, T, q0)  # what the test is about: the cells step over it
    model = arm.kinematics.model
    data = model.createData()
    frame = model.getFrameId(arm.tip)

    def error(x: np.ndarray) -> float:
        pin.framesForwardKinematics(model, data, arm.kinematics.to_pin(x))
        return float(np.linalg.norm(pin.log6(data.oMf[frame].inverse() * T).vector))

    r = arm.solve(T, q0=q0, solver="swept")
    assert r.success, r.reason
    assert error(r.q) < 1e-9 and arm.within_limits(r.q)
    every = [x for x in arm.solve_all(T, q0=q0, solver="swept") if x.success]
    assert every and all(error(x.q) < 1e-9 and arm.within_limits(x.q) for x in every)
    assert all(x.q[6] == r.q[6] for x in every)  # one value of joint 7, as the solver says
