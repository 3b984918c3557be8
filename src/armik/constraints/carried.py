"""Links a chain carries but does not move: a link whose own joints are no joints of the
chain (another arm's, cut off where the chain was loaded) keeps their loaded values, and
only the chain's joints above them move it (TALOS's left arm's chain carries the right
arm on its torso joints). A checked pair holding such a link says so in a collision's
words, with the fix (``locked=`` where the chain is loaded, docs/several-tips.md): the
chain's answers move it only as the joints that carry it move, so a self-collision pair
of it may stay whatever they do. The pair is checked all the same.
"""

from __future__ import annotations

from armik import reasons


class Pair(tuple):
    """A checked pair's two names, equal to the plain tuple, with ``note``: what a
    collision's words add about its held links ("" for none)."""

    note: str

    def __new__(cls, a: str, b: str, note: str) -> Pair:
        pair = super().__new__(cls, (a, b))
        pair.note = note
        return pair

    def __reduce__(self):
        return Pair, (self[0], self[1], self.note)


def held_joints(arm, joints: list[int], body: list[int]) -> tuple[tuple[str, ...], ...]:
    """Each object's held joints (whole-model ``joints``, each moved by ``body``'s joint,
    ``collision._bodies``): the joints between it and that body, first the nearest the
    body, where a joint of the chain carries it (none for a link the base holds)."""
    full = arm.chain.full
    out = []
    for j, b in zip(joints, body):
        names = []
        while b != 0 and j != b:  # every joint from j up to its body is held
            names.append(str(full.names[j]))
            j = full.parents[j]
        out.append(tuple(reversed(names)))
    return tuple(out)


def named(names: list[str], held: tuple, pairs: list, tip: str) -> list:
    """The names of ``pairs`` (object indices into ``names``; ``held``: each of the arm's
    objects' held joints; an obstacle's index is beyond them): a ``Pair`` with its note
    where a link of a self-collision pair is held, else the plain tuple (an obstacle is
    cleared by moving the joints that carry the link)."""
    out: list = []
    for a, b in pairs:
        mine = a < len(held) and b < len(held)  # not an obstacle's pair
        notes = [reasons.held_link(names[i], held[i], tip) for i in (a, b) if mine and held[i]]
        out.append(Pair(names[a], names[b], "; ".join(notes)) if notes else (names[a], names[b]))
    return out


def note(pair) -> str:
    """What a collision's words add about ``pair``'s held links ("" for none)."""
    return getattr(pair, "note", "")
