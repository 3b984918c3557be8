"""A spin past a joint's limit on a followed path is reported once, where the limit stops
it: the closed form's singular rows put a joint that lies on its limit onto it."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

import armik


def test_a_720_degree_spin_from_wrist_3_at_0_breaks_once_at_the_limit():
    """The UR5's wrist 3 (limits +-2 pi) spun 720 degrees from 0 by 5-degree steps, the arm
    stretched (wrist-singular rows): one jump, the step past 2 pi, where the stretched
    row's wrist 3 came back 1e-9 past 2 pi, was turned to 0 and broke the path at 360 and
    720 degrees as well."""
    ur5 = armik.load("ur5")
    q = np.zeros(6)
    T0 = ur5.fk(q)
    spin = [
        T0 * pin.SE3(pin.utils.rotate("z", np.radians(a)), np.zeros(3)) for a in range(0, 721, 5)
    ]
    path = ur5.solve_path(spin, q)
    breaks = np.flatnonzero(path.status != "converged").tolist()
    assert breaks == [73]  # 365 degrees: wrist 3 past 2 pi, the limit
    assert path.q[72][5] == ur5.upper[5] or abs(path.q[72][5] - 2 * np.pi) < 1e-7
    for i in (72, 144):
        F = ur5.fk(path.q[i])
        assert np.linalg.norm(F.translation - spin[i].translation) < 1e-6
        assert np.linalg.norm(pin.log3(F.rotation.T @ spin[i].rotation)) < 1e-6
