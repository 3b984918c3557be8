"""The worked example: a 2-link arm (l1 = 1.0 m, l2 = 0.8 m) reaching (1.2, 0.5).

Prints both elbow solutions in degrees, each checked by Pinocchio forward kinematics.
"""

import math

from _common import out_dir

import armik

out_dir(__doc__, figures=False)  # takes --out like every example; writes no figure

arm = armik.load("planar_2link")
for r in arm.solve_all([1.2, 0.5]):
    q1, q2 = (math.degrees(v) for v in r.q)
    tip = arm.fk(r.q).translation
    print(
        f"{r.branch:<10}  q1 = {q1:8.3f} deg  q2 = {q2:8.3f} deg  "
        f"tip = ({tip[0]:.12f}, {tip[1]:.12f})  FK error = {r.position_error:.1e} m"
    )
    assert r.success and r.position_error < 1e-12
