"""The XML pass over a URDF before Pinocchio sees it: every joint and link checked, axes
normalised in place, and what armik needs from the file besides the model (``URDFInfo``).

Each refusal names the joint or link, the value and the fix (``armik.model.urdf`` says
how armik reads a URDF).
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from armik.errors import URDFError, listing, warn
from armik.model.limit_units import MAX_ANGLE
from armik.tolerances import MAX_LENGTH, MAX_LIMIT

# Pinocchio's parser recursed about 2 KB of stack per link and crashed at 4000 links on an
# 8 MB stack (measured with pin 4.1): deeper trees are refused before it sees them.
MAX_DEPTH = 1000
# Pinocchio's data for a model grows as about nv^2.7 (measured with pin 4.1: 0.14 GB at 100
# joints, 0.6 GB at 200, 1.8 GB at 300, whether a chain or a tree): more moving joints than
# this would take gigabytes per thread, or end the process, before any chain is cut.
MAX_MOVING = 256
AXIS_MIN_NORM = 1e-6
AXIS_UNIT_TOL = 1e-9  # |norm - 1| below this is a unit axis already
# |norm - 1| up to this is a unit axis written to a few digits, normalised without a word but
# a note: six significant digits move each component of a unit axis by at most 5e-7, its
# norm by at most sqrt(3) * 5e-7 < 1e-6 (romeo.urdf's hands: 0.9999998); beyond, a warning
AXIS_ROUNDED_TOL = 1e-5
JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
MOVING = ("revolute", "continuous", "prismatic", "floating", "planar")
_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


@dataclass(frozen=True)
class JointXML:
    """One ``<joint>`` as written in the URDF (after the axis is normalised)."""

    name: str
    type: str
    parent: str
    child: str
    axis_norm: float = 1.0  # the norm of <axis xyz> as written


@dataclass(frozen=True)
class URDFInfo:
    """What armik needs from the XML besides the Pinocchio model."""

    name: str
    root_link: str
    joint_types: dict[str, str]
    mimic: dict[str, str]  # mimicking joint -> joint it follows
    links: tuple[str, ...] = ()
    joints: dict[str, JointXML] = field(default_factory=dict)
    unset_limits: frozenset[str] = frozenset()  # revolute/prismatic with lower == upper == 0
    notes: tuple[str, ...] = ()  # what was read in a way the user should know (armik info)
    depth: int = 0  # joints on the longest path from the root
    text: str = field(default="", repr=False, compare=False)  # the XML the model was built from
    # mimicking joint -> (multiplier, offset) of <mimic>: q = multiplier * q_driver + offset
    mimic_factors: dict[str, tuple[float, float]] = field(default_factory=dict)

    def children(self) -> dict[str, list[JointXML]]:
        """parent link -> the joints that hang from it, in file order."""
        out: dict[str, list[JointXML]] = {name: [] for name in self.links}
        for j in self.joints.values():
            out.setdefault(j.parent, []).append(j)
        return out


def _roots_words(path: str, roots: list[str], joints: dict[str, JointXML]) -> str:
    """Why a URDF without exactly one root link is refused, and what to do."""
    found = f"URDF {path!r} must have exactly one root link (a link no joint has as child)"
    if not roots:
        return (
            f"{found}, found none: the joints form a loop; a URDF is a tree: remove the joint "
            "that closes the loop"
        )
    parents = {j.parent for j in joints.values()}
    alone = [r for r in roots if r not in parents]  # in no joint at all
    if len(alone) >= len(roots) - 1:
        stray = alone if len(alone) < len(roots) else alone[1:]
        one = len(stray) == 1
        which = f"link {stray[0]!r} is" if one else f"links {listing(stray)} are"
        return (
            f"{found}, found {roots}: {which} in no joint; remove {'it' if one else 'them'}, "
            f'or attach {"it" if one else "each"} with a <joint type="fixed"> to the link '
            "it is mounted on"
        )
    return (
        f"{found}, found {roots}, each the root of its own tree: join them with a joint "
        '(a <joint type="fixed"> where one is mounted on another), or load each from a file '
        "of its own"
    )


def inspect(root: ET.Element, path: str) -> tuple[URDFInfo, bool]:
    """Check the tree; normalise the axes in place. Returns the info and whether the XML
    was changed."""
    if root.tag != "robot":
        raise URDFError(
            f"{path!r} is XML but not a URDF: its root element is <{root.tag}>, expected <robot>",
            path=path,
        )
    links: list[str] = []
    named: set[str] = set()  # links' names so far: a list's ``in`` made huge files quadratic
    for link in root.findall("link"):
        name = link.get("name")
        if not name:
            raise URDFError(f"URDF {path!r} has a <link> without a name: name it", path=path)
        if name in named:
            raise URDFError(
                f"URDF {path!r} has two links named {name!r}: link names must be unique",
                path=path,
            )
        links.append(name)
        named.add(name)
        for elem in link.iter("origin"):
            _origin(elem, f"link {name!r}", path)
        for elem in link.iter("mass"):
            xml_number(elem.get("value", "0"), f"link {name!r}", "mass value", path)
        for elem in link.iter("inertia"):
            for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
                xml_number(elem.get(key, "0"), f"link {name!r}", f"inertia {key}", path)
    if not links:
        raise URDFError(f"URDF {path!r} has no <link> element", path=path)
    link_set = set(links)

    joints: dict[str, JointXML] = {}
    mimic: dict[str, str] = {}
    factors: dict[str, tuple[float, float]] = {}
    unset: set[str] = set()
    notes: list[str] = []
    parent_of: dict[str, str] = {}  # child link -> joint
    changed = False
    for joint in root.findall("joint"):
        name = joint.get("name")
        if not name:
            raise URDFError(f"URDF {path!r} has a <joint> without a name: name it", path=path)
        what = f"joint {name!r}"
        if name in joints:
            raise URDFError(
                f"URDF {path!r} has two joints named {name!r}: joint names must be unique",
                path=path,
            )
        jtype = joint.get("type")
        if jtype is None:
            raise URDFError(
                f'{what} in {path!r} has no type attribute: add one, e.g. type="revolute" '
                f"(URDF joint types are {', '.join(JOINT_TYPES)})",
                path=path,
            )
        if jtype not in JOINT_TYPES:
            raise URDFError(
                f"{what} in {path!r} has type {jtype!r}; URDF joint types are "
                f"{', '.join(JOINT_TYPES)}",
                path=path,
            )
        ends: list[str] = []
        for tag in ("parent", "child"):
            end = joint.find(tag)
            end_link = None if end is None else end.get("link")
            if not end_link:
                raise URDFError(f'{what} in {path!r} has no <{tag} link="..."/>: add it', path=path)
            if end_link not in link_set:
                raise URDFError(
                    f"{what} in {path!r} names {tag} link {end_link!r}, which is not a <link> of "
                    "the file: add the link or fix the name",
                    path=path,
                )
            ends.append(end_link)
        parent, child = ends
        if child in parent_of:
            raise URDFError(
                f"link {child!r} in {path!r} is the child of two joints, {parent_of[child]!r} "
                f"and {name!r}: a URDF is a tree, each link has one parent joint",
                path=path,
            )
        parent_of[child] = name
        for elem in joint.findall("origin"):
            _origin(elem, what, path)
        norm = 1.0
        if jtype in ("revolute", "continuous", "prismatic"):
            norm, moved = _axis(joint, name, jtype, path)
            changed |= moved
            if moved:
                rounded = abs(norm - 1.0) <= AXIS_ROUNDED_TOL
                how = "a unit axis rounded to its digits" if rounded else "ROS reading"
                notes.append(
                    f"joint {name!r}: axis norm {_norm(norm)} read as the unit axis ({how})"
                )
        limit = joint.find("limit")
        if limit is not None:
            for key in ("effort", "velocity"):  # urdfdom wants both in any <limit>
                if limit.get(key) is None:
                    raise URDFError(
                        f"{what} in {path!r}: <limit> has no {key} (urdfdom requires it): "
                        f'add {key}="1" or the real value',
                        path=path,
                    )
                value = xml_number(limit.get(key), what, f"limit {key}", path)
                if value < 0.0 and jtype in ("revolute", "continuous", "prismatic"):
                    raise URDFError(  # a magnitude: Pinocchio refuses it without a name
                        f'{what} in {path!r}: <limit {key}="{limit.get(key)}"> is negative; '
                        f"the {key} limit is a magnitude: write it without the minus sign",
                        path=path,
                    )
        if jtype in ("revolute", "prismatic"):
            if limit is None:
                raise URDFError(
                    f"{what} in {path!r} is {jtype} but has no <limit>: add "
                    '<limit lower="..." upper="..." effort="..." velocity="..."/>, or make it '
                    "continuous if it turns freely",
                    path=path,
                )
            written = limit.get("lower"), limit.get("upper")  # as the file says them
            lower = xml_number(limit.get("lower", "0"), what, "lower limit", path)
            upper = xml_number(limit.get("upper", "0"), what, "upper limit", path)
            unlimited = lower == upper == 0.0  # no limits given (soft ones narrow nothing)
            if lower <= upper and not unlimited:
                soft = _soft_limits(joint, limit, lower, upper, name, path)
                if soft is not None:
                    notes.append(
                        f"joint {name!r}: limits [{soft[0]:g}, {soft[1]:g}], its "
                        f"<safety_controller> soft limits within <limit> [{lower:g}, "
                        f"{upper:g}] (as MoveIt reads them)"
                    )
                    lower, upper = soft
                    changed = True
            huge = [side for v, side in ((lower, "lower"), (upper, "upper")) if abs(v) > MAX_LIMIT]
            if huge:
                msg = (
                    f"joint {name!r} has {' and '.join(huge)} limit(s) beyond +-{MAX_LIMIT:g} "
                    f"(lower={written[0]}, upper={written[1]}), read as no "
                    "limit on that side"
                    + (": make it a continuous joint" if jtype == "revolute" else "")
                )
                notes.append(msg)
                warn(msg)
            if lower > upper:
                raise URDFError(
                    f"{what} in {path!r} has lower limit {lower} > upper limit {upper}: "
                    "swap them in the <limit> element",
                    path=path,
                )
            degrees = _degrees(name, jtype, lower, upper, huge)
            if degrees is not None:
                notes.append(degrees)
                warn(degrees)
            if unlimited:
                unset.add(name)
                msg = (
                    f"joint {name!r} has lower = upper = 0, read as no limits given: "
                    "it is unlimited; write its real limits in the URDF or use "
                    "Arm.with_limits"
                )
                notes.append(msg)
                warn(msg)
            elif lower == upper:
                notes.append(f"joint {name!r}: lower = upper = {lower:g}, the joint is pinned")
        elif limit is not None:
            for key in ("lower", "upper"):
                if limit.get(key) is not None:
                    xml_number(limit.get(key), what, f"limit {key}", path)
        mim = joint.find("mimic")
        if mim is not None:
            mimic[name] = mim.get("joint", "?")
            pair = [1.0, 0.0]  # the URDF defaults
            for k, key in enumerate(("multiplier", "offset")):
                if mim.get(key) is not None:
                    pair[k] = xml_number(mim.get(key), what, f"mimic {key}", path)
            factors[name] = (pair[0], pair[1])
        joints[name] = JointXML(name, jtype, parent, child, norm)

    for name, target in mimic.items():
        if target not in joints:  # Pinocchio ignores it; armik refuses it on a chain
            notes.append(f"joint {name!r} mimics {target!r}, which is not a joint of the file")
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        raise URDFError(_roots_words(path, roots, joints), path=path)
    depth = _depth(roots[0], joints, len(links), path)
    _refuse_too_many(joints, path)
    info = URDFInfo(
        root.get("name") or "",
        roots[0],
        {n: j.type for n, j in joints.items()},
        mimic,
        tuple(links),
        joints,
        frozenset(unset),
        tuple(notes),
        depth,
        mimic_factors=factors,
    )
    return info, changed


def _degrees(name: str, jtype: str, lower: float, upper: float, huge: list) -> str | None:
    """A revolute joint's limits beyond four turns each way, degrees by the look of them
    (ROS loads them all the same), in words; None for others (``huge`` ones are said
    apart, read as no limit)."""
    if jtype != "revolute" or huge or max(abs(lower), abs(upper)) <= MAX_ANGLE:
        return None
    rad = math.radians(lower), math.radians(upper)
    return (
        f"joint {name!r} has limits [{lower:g}, {upper:g}] rad, beyond four turns each way "
        f"(+-{MAX_ANGLE:.4g} rad): URDF limits are radians; for degrees write "
        f'lower="{rad[0]:.6g}" upper="{rad[1]:.6g}"'
    )


def _soft_limits(
    joint: ET.Element, limit: ET.Element, lower: float, upper: float, name: str, path: str
) -> tuple[float, float] | None:
    """The limits of a revolute or prismatic joint narrowed by the soft limits of its
    ``<safety_controller>``, as MoveIt and trac_ik bound the joint: its controller holds it
    within them. A soft limit not written is 0, as urdfdom reads it for them (a
    ``soft_upper_limit`` alone on [-2, 2] leaves [0, upper]). Writes them into ``limit``
    (Pinocchio reads them there) and returns them; None where they narrow nothing. A
    ``URDFError`` where nothing is left."""
    safety = joint.find("safety_controller")
    if safety is None:
        return None
    what = f"joint {name!r}"
    lo, hi = lower, upper
    for key in ("soft_lower_limit", "soft_upper_limit"):
        text = safety.get(key, "0")
        value = xml_number(text, what, f"safety_controller {key}", path, finite=False)
        if math.isnan(value):
            xml_number("nan", what, f"safety_controller {key}", path)  # refused, named
        lo, hi = (max(lo, value), hi) if key == "soft_lower_limit" else (lo, min(hi, value))
    if lo > hi:
        raise URDFError(
            f"{what} in {path!r}: the soft limits of its <safety_controller> "
            f'(soft_lower_limit="{safety.get("soft_lower_limit")}", soft_upper_limit='
            f'"{safety.get("soft_upper_limit")}") leave no value within its <limit> '
            f"[{lower:g}, {upper:g}]: write soft limits within the limits",
            path=path,
        )
    if (lo, hi) == (lower, upper):
        return None
    limit.set("lower", repr(lo))
    limit.set("upper", repr(hi))
    return lo, hi


def _refuse_too_many(joints: dict[str, JointXML], path: str) -> None:
    """A ``URDFError`` for more than ``MAX_MOVING`` moving joints, naming the count."""
    moving = sum(j.type in MOVING for j in joints.values())
    if moving > MAX_MOVING:
        raise URDFError(
            f"{path!r} has {moving} moving joints: armik reads URDFs of up to {MAX_MOVING} "
            "(Pinocchio's data for the whole model grows as about the cube of their count: "
            "1.8 GB at 300); make the joints you do not solve for fixed in the URDF "
            '(type="fixed")',
            path=path,
        )


def _depth(root: str, joints: dict[str, JointXML], n_links: int, path: str) -> int:
    """The number of joints on the longest path from the root (iterative: no recursion)."""
    children: dict[str, list[str]] = {}
    for j in joints.values():
        children.setdefault(j.parent, []).append(j.child)
    deepest, seen = 0, 1
    stack = [(root, 0)]
    while stack:
        link, d = stack.pop()
        if d > MAX_DEPTH:
            raise URDFError(
                f"the tree of {path!r} is more than {MAX_DEPTH} links deep (at link "
                f"{link!r}): armik refuses it because Pinocchio's parser recurses once per "
                "link and crashes the process on deep trees; no real arm is this deep",
                path=path,
            )
        deepest = max(deepest, d)
        for child in children.get(link, ()):
            seen += 1
            stack.append((child, d + 1))
    if seen != n_links:
        raise URDFError(
            f"the joints of {path!r} form a loop or leave links unconnected to the root "
            f"{root!r}: a URDF is a tree",
            path=path,
        )
    return deepest


def _axis(joint: ET.Element, name: str, jtype: str, path: str) -> tuple[float, bool]:
    """Check the joint's axis and write it back as a unit vector, with a warning unless it
    is a unit axis rounded (``AXIS_ROUNDED_TOL``). Returns the norm as written and whether
    the element was changed."""
    elem = joint.find("axis")
    if elem is None:
        return 1.0, False  # the URDF default, (1, 0, 0)
    text = elem.get("xyz")
    fix = 'write the axis direction, e.g. <axis xyz="0 0 1"/>'
    if text is None:
        raise URDFError(f"joint {name!r} in {path!r} has an <axis> without xyz: {fix}", path=path)
    v = xml_vector(text, f"joint {name!r}", "axis xyz", path, finite=False)
    if not all(math.isfinite(c) for c in v):
        raise URDFError(
            f"joint {name!r} in {path!r} has a non-finite axis xyz={text!r}: {fix}", path=path
        )
    norm = math.hypot(*v)  # no overflow for 1e300, no underflow for 1e-200
    if norm < AXIS_MIN_NORM:
        raise URDFError(
            f"joint {name!r} in {path!r} has a zero axis xyz={text!r} (norm {norm:.3g}): {fix}",
            path=path,
        )
    if abs(norm - 1.0) <= AXIS_UNIT_TOL:
        return norm, False
    unit = [c / norm for c in v]
    elem.set("xyz", " ".join(repr(c) for c in unit))
    if abs(norm - 1.0) <= AXIS_ROUNDED_TOL:  # a rounded unit axis: said by its note only
        return norm, True
    if jtype == "prismatic":
        msg = (
            f"joint {name!r} has a non-unit axis xyz={text!r} (norm {_norm(norm)}); armik reads "
            "it as the unit axis, as Pinocchio, KDL and MoveIt do (1 m of joint value moves "
            f"1 m); yourdfpy and pybullet would move {_norm(norm)} m: write a unit axis to "
            "silence this"
        )
    else:
        msg = (
            f"joint {name!r} has a non-unit axis xyz={text!r} (norm {_norm(norm)}); armik "
            "normalises it (the rotation is about the unit axis)"
        )
    warn(msg)
    return norm, True


def _norm(norm: float) -> str:
    """An axis norm as text that is never "1": six digits print 0.99999974 as 1, which
    reads as no reason for a warning; ten resolve AXIS_UNIT_TOL."""
    return f"{norm:.10g}"


def _origin(elem: ET.Element, what: str, path: str) -> None:
    for key in ("xyz", "rpy"):
        text = elem.get(key)
        if text is None:
            continue
        v = xml_vector(text, what, f"origin {key}", path)
        if max(abs(c) for c in v) > MAX_LENGTH:
            raise URDFError(
                f"{what} in {path!r} has origin {key}={text!r}, beyond the {MAX_LENGTH:g} "
                "armik accepts: give the value in metres or radians",
                path=path,
            )


def xml_vector(text: str, what: str, attr: str, path: str, finite: bool = True) -> list[float]:
    parts = text.split()
    if len(parts) != 3:
        raise URDFError(
            f"{what} in {path!r} has {attr}={text!r}: expected 3 numbers separated by spaces",
            path=path,
        )
    return [xml_number(p, what, attr, path, finite=finite, whole=text) for p in parts]


def xml_number(
    text: str | None,
    what: str,
    attr: str,
    path: str,
    finite: bool = True,
    whole: str | None = None,
) -> float:
    text = (text or "").strip()
    ok = bool(_NUMBER.match(text))
    value = float(text) if ok else math.nan
    if not finite and text.lower().lstrip("+-") in ("inf", "infinity", "nan"):
        return float(text)
    if not ok or not math.isfinite(value):
        shown = whole if whole is not None else text
        raise URDFError(
            f"{what} in {path!r} has {attr}={shown!r}: {text!r} is not a finite number; "
            "write a decimal number such as 0.25 or 1e-3",
            path=path,
        )
    return value
