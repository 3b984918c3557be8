"""SRDF files: the link pairs an SRDF exempts from the self-collision check
(``armik.load(..., srdf=path)``: its ``<disable_collisions>``, and every pair of a
``<disable_default_collisions>`` link but those ``<enable_collisions>`` names), read and
written; a file that is not an SRDF (a URDF given in its place, another XML) refused by
name."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from armik.errors import CollisionError

Pair = tuple[str, str]

# the elements of an SRDF (MoveIt's srdfdom), children of its <robot>
SRDF_ELEMENTS = frozenset(
    {
        "group",
        "group_state",
        "end_effector",
        "virtual_joint",
        "passive_joint",
        "joint_property",
        "disable_collisions",
        "disable_default_collisions",
        "enable_collisions",
        "link_sphere_approximation",
    }
)
URDF_ELEMENTS = frozenset({"link", "joint", "transmission", "gazebo", "material"})


def read_srdf(path: object, links: tuple[str, ...]) -> frozenset[Pair]:
    """The link pairs an SRDF exempts from the self-collision check, sorted, read as MoveIt
    reads them (srdfdom, then its allowed collision matrix): every pair of a link that
    ``<disable_default_collisions link=>`` names, but the pairs ``<enable_collisions link1=
    link2=>`` names, and every pair ``<disable_collisions link1= link2=>`` names; the
    ``<robot>``'s own children only, each name without the spaces around it.
    Raises ``CollisionError`` for a missing or malformed file, a file that is not an SRDF
    (its root not ``<robot>``, a URDF's ``<link>``/``<joint>`` in it, or children none of
    which an SRDF has) or an unknown link."""
    if not isinstance(path, (str, Path)) or not Path(path).is_file():
        raise CollisionError(
            f"srdf {str(path)!r} is not an existing file: give the path of an SRDF",
            option="srdf",
            value=path,
        )
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise CollisionError(
            f"srdf {str(path)!r} is not well-formed XML ({exc}): fix the XML",
            option="srdf",
            value=path,
        ) from None
    _is_srdf(root, str(path))
    known = set(links)

    def link(elem: ET.Element, attribute: str) -> str:
        name = elem.get(attribute)
        name = None if name is None else name.strip()  # as srdfdom trims it
        if name is None or name not in known:
            raise CollisionError(
                f"srdf {str(path)!r}: <{elem.tag}> names link {name!r}, which is not a link "
                "of the URDF: fix the name or load the SRDF of this robot",
                option="srdf",
                value=name,
            )
        return name

    def pairs(tag: str) -> set[Pair]:
        return {sorted_pair(link(e, "link1"), link(e, "link2")) for e in root.findall(tag)}

    alone = {link(e, "link") for e in root.findall("disable_default_collisions")}
    enabled, disabled = pairs("enable_collisions"), pairs("disable_collisions")
    # MoveIt's order: the defaults, then the pairs enabled, then those disabled (which win)
    by_default = {sorted_pair(a, b) for a in alone for b in known if b != a}
    return frozenset((by_default - enabled) | disabled)


def _is_srdf(root: ET.Element, path: str) -> None:
    """``CollisionError`` naming ``path`` unless ``root`` reads as an SRDF's: a ``<robot>``
    without a URDF's elements, its children (if any) including an SRDF's."""
    tags = {child.tag for child in root if isinstance(child.tag, str)}
    fix = "give the robot's SRDF (its <disable_collisions>, <group>, ...) as srdf="
    if root.tag != "robot":
        raise CollisionError(
            f"srdf {path!r} is not an SRDF: its root element is <{root.tag}>, an SRDF's is "
            f"<robot>: {fix}",
            option="srdf",
            value=path,
        )
    urdf = sorted(tags & URDF_ELEMENTS)
    if urdf:
        raise CollisionError(
            f"srdf {path!r} is a URDF, not an SRDF: it has <{'>, <'.join(urdf)}> elements; "
            f"the URDF is armik.load's first argument: {fix}",
            option="srdf",
            value=path,
        )
    if tags and not tags & SRDF_ELEMENTS:
        raise CollisionError(
            f"srdf {path!r} is not an SRDF: none of its elements "
            f"<{'>, <'.join(sorted(tags))}> is an SRDF's: {fix}",
            option="srdf",
            value=path,
        )


def sorted_pair(a: str, b: str) -> Pair:
    """``tuple(sorted((a, b)))``, typed as a pair."""
    return (a, b) if a <= b else (b, a)


def write_srdf(pairs, path, robot: str = "robot") -> None:
    """Write ``pairs`` of link names as an SRDF's ``<disable_collisions reason="Never">``.
    Raises ``CollisionError`` naming a bad pair or path, or why the file was not written."""
    if not isinstance(path, (str, Path)):  # an int would be written to that descriptor
        raise CollisionError(
            f"write_srdf's path must be a file path (str or pathlib.Path), got {path!r}",
            option="path",
            value=path,
        )
    try:
        if isinstance(pairs, (str, bytes)):
            raise TypeError
        pairs = list(pairs)
    except TypeError:
        raise CollisionError(
            f"write_srdf takes a list of pairs of link names [(link1, link2), ...], got {pairs!r}",
            value=pairs,
        ) from None
    root = ET.Element("robot", name=robot)
    for pair in pairs:
        try:
            if isinstance(pair, (str, bytes)):  # two letters are no pair of links
                raise TypeError
            a, b = pair
        except (TypeError, ValueError):
            raise CollisionError(
                f"write_srdf takes pairs of link names (link1, link2), got {pair!r}",
                value=pair,
            ) from None
        ET.SubElement(root, "disable_collisions", link1=str(a), link2=str(b), reason="Never")
    ET.indent(root)
    try:
        ET.ElementTree(root).write(path, encoding="unicode", xml_declaration=True)
    except OSError as exc:
        raise CollisionError(
            f"cannot write the SRDF {str(path)!r}: {exc.strerror or exc}", value=str(path)
        ) from None
