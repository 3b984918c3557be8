"""The tip of a chain when none is given, and the words that say why it was chosen."""

from __future__ import annotations

from armik.errors import FrameError, listing
from armik.model.urdf import URDFInfo


def default_tip(info: URDFInfo, base: str) -> tuple[str, str]:
    """The tip when none is given, and why: ``tool0`` downstream of the base (REP 199,
    the tool flange of ROS-Industrial and UR descriptions); else a tool frame beside a
    gripper, or the hand a gripper's jaws hang from (``_tool_frame``); else the leaf at
    the end of the longest chain of moving joints; leaves tied there that hang on fixed
    joints from one link give that link.
    Raises ``FrameError`` listing the leaves when it is a choice."""
    children = info.children()
    if base not in children:
        raise FrameError(
            f"no tip given and the base {base!r} is not a link of the URDF: pass tip=",
            frame=base,
        )
    leaves: list[tuple[str, int, str | None]] = []
    stack: list[tuple[str, int, str | None]] = [(base, 0, None)]
    tool0 = False
    while stack:  # iterative: trees can be deep
        link, moving, last = stack.pop()
        tool0 |= link == "tool0" and moving > 0
        kids = children.get(link, [])
        if not kids:
            leaves.append((link, moving, last))
        for j in kids:
            step = j.type != "fixed"
            stack.append((j.child, moving + step, j.name if step else last))
    if tool0:
        return "tool0", "'tool0', the tool flange by convention (REP 199)"
    best = max(m for _, m, _ in leaves)
    if best == 0:
        raise FrameError(
            f"no tip given and no moving joint lies downstream of {base!r}: pick another base",
            frame=base,
        )
    top = sorted((leaf for leaf in leaves if leaf[1] == best), key=lambda leaf: leaf[0])
    joints = f"{best} moving joint{'' if best == 1 else 's'}"
    # a gripper hangs from a hand an arm moves: one moving joint from the base is the arm
    tool = _tool_frame(info, children, {last for _, _, last in top}) if best > 1 else None
    if tool is not None:
        return tool
    if len(top) == 1:
        return top[0][0], f"the leaf at the end of the longest chain ({joints})"
    lasts = {last for _, _, last in top if last is not None}  # each: best > 0 moving joints
    if len(lasts) == 1:
        joint = info.joints[lasts.pop()]
        return joint.child, (
            f"the link after the last moving joint {joint.name!r} of the longest chain "
            f"({joints}); the leaves {listing(n for n, _, _ in top)} hang from "
            "it on fixed joints"
        )
    names = [n for n, _, _ in top]
    raise FrameError(
        f"no tip given and the URDF has {len(names)} leaf links at the end of chains of "
        f"{joints}: pass tip= one of {listing(names)}",
        frame="",
        candidates=names,
    )


def _tool_frame(info: URDFInfo, children: dict, lasts: set) -> tuple[str, str] | None:
    """A gripper's tool frame, and why, or None. When the longest chains end in moving
    joints (``lasts``) that all start at one link (the hand) and lead to leaves with no
    other moving joint (a gripper's jaws or fingers), the jaws are off the arm: the tip is
    the hand's one leaf on fixed joints alone, the tool frame the arm is driven by (the
    SO-101's ``gripper_frame_link`` beside its moving jaw); without exactly one, the hand
    itself when the jaws are named as a gripper's (``_JAW_WORDS``: the SO-100's ``gripper``
    link, which holds the fixed jaw, the Z1's ``gripperStator``)."""
    if None in lasts:
        return None
    parents = {info.joints[name].parent for name in lasts}
    if len(parents) != 1:
        return None
    hand = parents.pop()
    if not all(_only_fixed_below(children, info.joints[name].child) for name in lasts):
        return None
    jaws = listing(sorted(lasts))
    tools = _fixed_leaves(children, hand)
    if len(tools) == 1:
        return tools[0], (
            f"the tool frame {tools[0]!r}, fixed to {hand!r}, from which the longest chains "
            f"go on only through the gripper joint(s) {jaws}: those are left off the arm "
            "(pass tip= to choose another)"
        )
    if not all(_named_as_jaw(info, name) for name in lasts):
        return None
    return hand, (
        f"the hand {hand!r}, from which the longest chains go on only through the gripper "
        f"joint(s) {jaws}: those are left off the arm (pass tip= to choose another)"
    )


# Words that name a gripper's jaw in its joint's or its link's name. Not "finger": a
# finger robot's last joint is part of the chain (example-robot-data's finger_edu).
_JAW_WORDS = ("gripper", "jaw")


def _named_as_jaw(info: URDFInfo, joint: str) -> bool:
    names = (joint + " " + info.joints[joint].child).lower()
    return any(word in names for word in _JAW_WORDS)


def _only_fixed_below(children: dict, link: str) -> bool:
    """No moving joint below ``link``."""
    stack = [link]
    while stack:
        for j in children.get(stack.pop(), []):
            if j.type != "fixed":
                return False
            stack.append(j.child)
    return True


def _fixed_leaves(children: dict, link: str) -> list[str]:
    """The leaves reached from ``link`` through fixed joints only (not ``link`` itself)."""
    leaves, stack = [], [j for j in children.get(link, []) if j.type == "fixed"]
    while stack:
        j = stack.pop()
        below = children.get(j.child, [])
        if not below:
            leaves.append(j.child)
        stack.extend(k for k in below if k.type == "fixed")
    return sorted(leaves)
