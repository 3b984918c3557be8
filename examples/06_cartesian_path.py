"""Following Cartesian paths, each step seeded with the previous answer.

The 2-link arm follows a line that runs through the stretched singularity (x = 1.8 m) and
beyond; the Panda follows a circle. Writes path_2link.png and path_panda.png into --out.
"""

import numpy as np
import pinocchio as pin
from _common import out_dir, pyplot

import armik

out = out_dir(__doc__)
plt = pyplot()

arm = armik.load("planar_2link")
s = np.linspace(0.0, 1.0, 120)
line = np.stack([0.6 + 1.4 * s, 0.3 * (1 - s)], axis=1)  # ends 2.0 m away: out of reach
q = np.array([0.0, 1.0])
rows = []
for p in line:
    r = arm.solve(p, q0=q)
    q = np.asarray(r.q)
    rows.append((*q, r.success, r.singular))
rows = np.array(rows, dtype=float)
if plt is not None:
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(line[:, 0], rows[:, 0], label="q1")
    ax.plot(line[:, 0], rows[:, 1], label="q2")
    ax.fill_between(
        line[:, 0],
        -1.5,
        1.5,
        where=rows[:, 2] == 0,
        color="red",
        alpha=0.15,
        label="unreachable: closest configuration",
    )
    ax.axvline(1.8, color="k", lw=0.8, ls=":")
    ax.set_xlabel("x along the path (m)")
    ax.set_ylabel("joint angle (rad)")
    ax.set_title("2-link arm along a line through the stretched singularity")
    ax.legend(fontsize=8)
    fig.savefig(out / "path_2link.png", dpi=110)
first_fail = line[np.argmax(rows[:, 2] == 0), 0]
jump = np.abs(np.diff(rows[:, :2], axis=0)).max()
print(
    f"2-link: {int(rows[:, 2].sum())}/{len(line)} points reached; first unreachable at "
    f"x = {first_fail:.3f} m; largest joint jump {jump:.3f} rad"
)

panda = armik.load("panda")
q = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
T0 = panda.fk(q)
angles = np.linspace(0, 2 * np.pi, 100)
qs, ok = [], 0
for a in angles:
    p = T0.translation + 0.15 * np.array([0.0, np.cos(a) - 1.0, np.sin(a)])
    r = panda.solve(pin.SE3(T0.rotation, p), q0=q)
    ok += r.success
    q = np.asarray(r.q)
    qs.append(q)
qs = np.array(qs)
if plt is not None:
    fig, ax = plt.subplots(figsize=(7, 4))
    for j in range(panda.dof):
        ax.plot(np.degrees(angles), qs[:, j], label=panda.joint_names[j])
    ax.set_xlabel("angle along the circle (deg)")
    ax.set_ylabel("joint angle (rad)")
    ax.set_title("Panda along a 15 cm circle, fixed orientation")
    ax.legend(fontsize=7)
    fig.savefig(out / "path_panda.png", dpi=110)
print(
    f"panda: {ok}/{len(angles)} points reached; largest joint jump "
    f"{np.abs(np.diff(qs, axis=0)).max():.3f} rad"
)
if plt is not None:
    print(f"figures in {out}")
