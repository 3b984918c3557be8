"""Preferences: the best answer, not just an answer (``prefer=``).

A 7-joint arm reaches a pose in a whole family of configurations. ``solve`` returns the
first verified answer from q0; ``prefer=`` asks for the best by a score: the most
manipulable, the farthest from its joint limits, the nearest q0, a reference posture, or
any cost of q. On the Panda, joint 7 is searched over its range, every other joint in
closed form at each value, so the optimum is the self-motion's, not a local one.

1. One Panda target, six answers: the default and one per score (manipulability, limits,
   nearest, a posture, a custom cost), each with its manipulability, limit margin, distance
   to q0 and joint 7.
2. A cost that raises is an armik error naming it.
"""

import numpy as np
from _common import out_dir

import armik
from armik.problem.scores import limit_margin, manipulability

out_dir(__doc__, figures=False)

panda = armik.load("panda")
rng = np.random.default_rng(12)
T = panda.fk(panda.random_q(rng))
home = panda.middle


def elbow_low(q):
    """A custom cost: keep joint 4 (the elbow) as bent as possible."""
    return float(q[3])


print(f"{'prefer':>16} | success | manipulability | limit margin | |q - q0| | joint 7")
for prefer in [None, "manipulability", "limits", "nearest", armik.Posture(home), elbow_low]:
    r = panda.solve(T, q0=home, prefer=prefer)
    name = getattr(prefer, "__name__", None) or getattr(prefer, "name", None) or str(prefer)
    print(
        f"{name:>16} | {r.success!s:>7} | {manipulability(panda.jacobian(r.q)):14.4f} | "
        f"{limit_margin(panda, r.q):12.3f} | {np.linalg.norm(r.q - home):8.3f} | {r.q[6]:7.3f}"
    )
best = panda.solve(T, q0=home, prefer="manipulability")
print(f"the most manipulable answer, by {best.solver}: {best.reason.split('; ')[-1]}")


def broken(q):
    raise ValueError("no model loaded")


try:
    panda.solve(T, prefer=broken)
except armik.InputError as err:
    print(f"a cost that raises: {err}")
