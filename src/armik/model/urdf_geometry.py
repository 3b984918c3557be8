"""The ``<collision>`` elements of a URDF checked as urdfdom reads them.

urdfdom logs a ``<collision>`` it cannot read (a box of two numbers, a cylinder without a
length, a mesh without a filename, a ``<geometry>`` with no shape) and drops it: the
model loads, and the link has no shape for the collision checks, so an obstacle through it
is no collision and an answer inside the obstacle a success. armik refuses such an element
when it reads the file, naming the link, the value and the fix (as it refuses a bad
``<inertial>``, which the kinematics does not read either). ``<visual>`` elements are left
as urdfdom leaves them: the viewer draws what it can.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from armik.errors import URDFError
from armik.model.urdf_checks import xml_number, xml_vector

SHAPES = ("sphere", "box", "cylinder", "mesh")


def check_collisions(root: ET.Element, path: str) -> None:
    """Raise ``URDFError`` for the first ``<collision>`` of a link that urdfdom would drop."""
    capsules = root.get("version", "1.0").strip() not in ("1.0", "")  # URDF 1.1 reads them
    for link in root.findall("link"):
        name = link.get("name")
        for collision in link.findall("collision"):
            _check(collision, f"link {name!r}", path, capsules)


def _check(collision: ET.Element, what: str, path: str, capsules: bool) -> None:
    dropped = "urdfdom drops it, and collision checks would not see this shape"
    geometry = collision.find("geometry")
    shape = None if geometry is None else next(iter(geometry), None)
    if shape is None or not isinstance(shape.tag, str):
        raise URDFError(
            f"{what} in {path!r} has a <collision> without a shape in its <geometry> "
            f'({dropped}): add one, e.g. <geometry><box size="0.1 0.1 0.1"/></geometry>, or '
            "remove the <collision>",
            path=path,
        )
    kind = shape.tag
    if kind == "capsule" and capsules:
        kind = "cylinder"  # the same attributes
    if kind not in SHAPES:
        known = ", ".join(f"<{s}>" for s in SHAPES)
        capsule = ' (<capsule> needs <robot version="1.1">)' if shape.tag == "capsule" else ""
        raise URDFError(
            f"{what} in {path!r} has a <collision> shape <{shape.tag}>{capsule} ({dropped}): "
            f"use one of {known}",
            path=path,
        )
    needed = {"sphere": ("radius",), "box": ("size",), "cylinder": ("radius", "length")}
    for key in needed.get(kind, ("filename",)):
        if shape.get(key) is None:
            raise URDFError(
                f"{what} in {path!r} has a <collision> <{shape.tag}> without {key} "
                f"({dropped}): add {key}=...",
                path=path,
            )
    attr = f"<collision> {shape.tag}"
    if kind in ("sphere", "cylinder"):
        for key in needed[kind]:
            xml_number(shape.get(key), what, f"{attr} {key}", path)
    elif kind == "box":
        xml_vector(shape.get("size", ""), what, f"{attr} size", path)
    elif shape.get("scale") is not None:
        xml_vector(shape.get("scale", ""), what, f"{attr} scale", path)
