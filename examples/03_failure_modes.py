"""What armik returns when a 2-link target cannot be reached normally.

Too far, inside the inner dead zone, and exactly on the stretched singular boundary.
"""

from _common import out_dir

import armik

out_dir(__doc__, figures=False)  # takes --out like every example; writes no figure

arm = armik.load("planar_2link")
cases = {"too far": [2.5, 0.0], "inner dead zone": [0.1, 0.05], "singular boundary": [1.8, 0.0]}
for name, target in cases.items():
    r = arm.solve(target)
    print(
        f"{name:<18} success={r.success!s:<5} status={r.status:<12} singular={r.singular!s:<5}"
        f" q={[round(float(v), 4) for v in r.q]}"
    )
    print(f"{'':<18} {r.reason}")
