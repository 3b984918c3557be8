"""Collision helpers for users: the self-collision pairs that never touch, as an SRDF.

``never_colliding_pairs(arm, n=1000)`` samples ``n`` configurations within the limits and
returns the link pairs (not adjacent) that never touched, as MoveIt's setup assistant does;
``write_srdf(pairs, path)`` writes them as ``<disable_collisions reason="Never">`` for
``armik.load(..., srdf=path)``.
"""

import numpy as np
import pinocchio as pin

from armik.constraints.collision import arm_geometry
from armik.constraints.srdf import Pair, read_srdf, sorted_pair, write_srdf
from armik.errors import CollisionError
from armik.model import mimic_frames
from armik.model.arm_model import model_of

__all__ = ["never_colliding_pairs", "read_srdf", "write_srdf"]


def never_colliding_pairs(arm: object, n: int = 1000, seed: int = 0) -> list[Pair]:
    """The link pairs that can touch (not adjacent) yet never do over ``n`` random
    configurations within the limits, sorted: what MoveIt's setup assistant disables as
    "Never". Ignores the arm's own SRDF. ``write_srdf`` writes them."""
    arm = model_of(arm)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise CollisionError(f"n must be a whole number >= 1, got {n!r}", option="n", value=n)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise CollisionError(
            f"seed must be a whole number >= 0, got {seed!r}", option="seed", value=seed
        )
    g = arm_geometry(arm)
    model = g.model.copy()
    for a, b in g.candidates:
        model.addCollisionPair(pin.CollisionPair(a, b))
    gd = pin.GeometryData(model)
    touched = np.zeros(len(g.candidates), bool)
    data = arm.model.createData()
    full = arm.chain.full.createData() if g.followed else None
    for q in arm.random_q(seed, n=int(n)):
        pin.updateGeometryPlacements(arm.model, data, model, gd, arm.to_pin(q))
        if full is not None:  # where their drivers put them, as every check places them
            mimic_frames.place_followed(arm, q, gd, g.followed, full)
        pin.computeCollisions(model, gd, False)
        touched |= np.array([r.isCollision() for r in gd.collisionResults])
    pairs = {sorted_pair(g.links[a], g.links[b]) for a, b in g.candidates}
    hit = {sorted_pair(g.links[a], g.links[b]) for (a, b), t in zip(g.candidates, touched) if t}
    return sorted(pairs - hit)
