"""Collision helpers for users: the self-collision pairs that never touch, as an SRDF.

``never_colliding_pairs(arm, n=1000)`` samples ``n`` configurations within the limits and
returns the link pairs (not adjacent) that never touched, as MoveIt's setup assistant does;
``write_srdf(pairs, path)`` writes them as ``<disable_collisions reason="Never">`` for
``armik.load(..., srdf=path)``.
"""

from armik.constraints.collision import never_colliding_pairs
from armik.constraints.srdf import read_srdf, write_srdf

__all__ = ["never_colliding_pairs", "read_srdf", "write_srdf"]
