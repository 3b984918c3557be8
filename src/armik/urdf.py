"""Reading a URDF file into a Pinocchio model, with errors a user can act on.

The XML is checked here before Pinocchio sees it, because Pinocchio's own messages for a
malformed file are C++ exception texts. Meshes are never loaded: kinematics needs none.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import pinocchio as pin

from .errors import URDFError


@dataclass(frozen=True)
class URDFInfo:
    """What armik needs from the XML besides the Pinocchio model."""

    name: str
    root_link: str
    joint_types: dict[str, str]
    mimic: dict[str, str]  # mimicking joint -> joint it follows


def read_urdf(path: str | Path) -> tuple[pin.Model, URDFInfo]:
    """Parse ``path`` into a Pinocchio model. Raises ``URDFError`` naming the problem."""
    path = Path(path)
    if not path.exists():
        raise URDFError(f"URDF file {str(path)!r} does not exist: check the path", path=str(path))
    if path.is_dir():
        raise URDFError(
            f"{str(path)!r} is a directory: pass the .urdf file inside it", path=str(path)
        )
    text = path.read_text(encoding="utf-8", errors="replace")
    if not text.strip():
        raise URDFError(f"URDF file {str(path)!r} is empty", path=str(path))
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise URDFError(
            f"URDF file {str(path)!r} is not well-formed XML ({exc}): fix the XML", path=str(path)
        ) from None
    info = _inspect(root, str(path))
    try:
        model = pin.buildModelFromXML(text)
    except Exception as exc:  # Pinocchio raises bare RuntimeError/ValueError from C++
        raise URDFError(
            f"Pinocchio could not build a model from {str(path)!r}: {exc}", path=str(path)
        ) from None
    return model, info


def _inspect(root: ET.Element, path: str) -> URDFInfo:
    if root.tag != "robot":
        raise URDFError(
            f"{path!r} is XML but not a URDF: its root element is <{root.tag}>, expected <robot>",
            path=path,
        )
    links = [link.get("name") for link in root.findall("link")]
    if not links:
        raise URDFError(f"URDF {path!r} has no <link> element", path=path)
    joint_types: dict[str, str] = {}
    mimic: dict[str, str] = {}
    children: set[str] = set()
    for joint in root.findall("joint"):
        name = joint.get("name", "?")
        jtype = joint.get("type", "?")
        joint_types[name] = jtype
        child = joint.find("child")
        if child is not None and child.get("link"):
            children.add(child.get("link"))
        limit = joint.find("limit")
        if jtype in ("revolute", "prismatic") and limit is not None:
            lower = _number(limit.get("lower", "0"), name, "lower", path)
            upper = _number(limit.get("upper", "0"), name, "upper", path)
            if lower > upper:
                raise URDFError(
                    f"joint {name!r} in {path!r} has lower limit {lower} > upper limit {upper}: "
                    "swap them in the <limit> element",
                    path=path,
                )
        mim = joint.find("mimic")
        if mim is not None:
            mimic[name] = mim.get("joint", "?")
    roots = [name for name in links if name not in children]
    if len(roots) != 1:
        raise URDFError(f"URDF {path!r} must have exactly one root link, found {roots}", path=path)
    return URDFInfo(root.get("name", ""), roots[0], joint_types, mimic)


def _number(text: str, joint: str, attr: str, path: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise URDFError(
            f"joint {joint!r} in {path!r} has a {attr} limit {text!r} that is not a finite number",
            path=path,
        )
    return value
