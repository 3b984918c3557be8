"""Elbow-up and elbow-down: the 2-link arm drawn in both configurations, and its workspace.

Writes elbow_branches.png into --out (default: a temporary folder); needs matplotlib
(``pip install "armik[plot]"``).
"""

import sys

import numpy as np
from _common import out_dir, pyplot

import armik
from armik.solvers.closed_form import planar2r

out = out_dir(__doc__)
plt = pyplot()
if plt is None:  # a figure is all this example makes
    sys.exit()
arm = armik.load("planar_2link")
geo = planar2r.geometry(arm.kinematics)  # the closed form reads the arm model

fig, ax = plt.subplots(figsize=(6, 6))
theta = np.linspace(0, 2 * np.pi, 200)
for radius in (geo.l1 + geo.l2, abs(geo.l1 - geo.l2)):
    ax.plot(radius * np.cos(theta), radius * np.sin(theta), "k:", lw=0.8)
for target, color in (((1.2, 0.5), "C0"), ((-0.6, 1.1), "C1"), ((0.3, -1.4), "C2")):
    for r in arm.solve_all(list(target)):
        shoulder_angle = geo.alpha1 + geo.s1 * r.q[0]
        elbow = geo.shoulder + geo.l1 * np.array([np.cos(shoulder_angle), np.sin(shoulder_angle)])
        tip = arm.fk(r.q).translation[:2]
        style = "-" if r.branch == "elbow-up" else "--"
        ax.plot(
            [0, elbow[0], tip[0]],
            [0, elbow[1], tip[1]],
            style,
            color=color,
            marker="o",
            label=f"{target} {r.branch}",
        )
    ax.plot(*target, "x", color=color, markersize=12)
ax.set_aspect("equal")
ax.set_title("2-link arm: both elbow solutions; dotted: reachable annulus")
ax.legend(fontsize=7, loc="lower left")
path = out / "elbow_branches.png"
fig.savefig(path, dpi=110)
print(f"wrote {path}")
