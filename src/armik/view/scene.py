"""The arm's body for drawing: the URDF's visual geometry (read with yourdfpy, meshes loaded
with trimesh, ``package://`` resolved), or the stick figure when the URDF has no visuals or
one of its meshes cannot be found or read (then with one warning naming the mesh).

``package://NAME/REST`` is looked up, in order: in a folder NAME among the URDF file's
ancestors (as ``example-robot-data`` lays its robots out), in NAME under each folder of
``ROS_PACKAGE_PATH``, in ``share/NAME`` under each prefix of ``AMENT_PREFIX_PATH`` and
``CMAKE_PREFIX_PATH``, and finally REST under each of the URDF's ancestors. ``file://``
paths are absolute; other relative paths start at the URDF's folder. A URDF read from text
(``armik.load_string``) has no folder: its boxes, cylinders and spheres are drawn, and its
meshes found by ``package://`` through the environment or by ``file://``.
"""

from __future__ import annotations

import io
import logging
import os
from pathlib import Path

import numpy as np
import pinocchio as pin

from armik.errors import warn
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.model.urdf import urdf_text
from armik.view.body import Body, Part
from armik.view.stick import stick_body

log = logging.getLogger(__name__)

DEFAULT_COLOR = (200, 200, 205, 255)


def arm_body(arm: ArmModel) -> Body:
    """The body the viewer draws for ``arm``, built once per arm."""
    return _BODY(arm)


def _build(arm: ArmModel) -> Body:
    try:
        parts, missing = visual_parts(arm)
    except Exception as exc:  # yourdfpy is stricter than armik's reader on some files
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        note = f"the URDF's visuals cannot be read ({first})"
        warn(f"{arm.name}: {note}; drawing the stick figure")
        return stick_body(arm, note)
    if missing:
        more = f" ({len(missing) - 1} more meshes missing)" if len(missing) > 1 else ""
        note = f"mesh {missing[0]}{more}"
        if any("pycollada" in m for m in missing):  # trimesh reads .dae with pycollada
            fix = 'pip install "armik[view]", whose pycollada reads .dae meshes'
        else:
            fix = "check the path, or the package's folder in ROS_PACKAGE_PATH"
        warn(f"{arm.name}: {note}; drawing the stick figure instead ({fix})")
        return stick_body(arm, note)
    if not parts:
        log.info("arm %r: the URDF has no visual geometry; drawing the stick figure", arm.name)
        return stick_body(arm, "the URDF has no visual geometry")
    return Body(parts=tuple(parts), kind="meshes")


_BODY = Derived("the viewer's body", _build)


def visual_parts(arm: ArmModel) -> tuple[list[Part], list[str]]:
    """Every visual of every link in the arm's model, and the meshes that could not be had
    (each as ``'FILE' of link 'LINK' not found`` or ``... cannot be read: WHY``)."""
    import trimesh
    import yourdfpy

    # an arm read from XML text (load_string) keeps the text in its recipe; its meshes
    # have no folder of their own: package:// and file:// paths only
    text = getattr(getattr(arm, "_recipe", None), "text", None)
    source = None if text is not None else Path(arm.source)
    xml = str(text) if source is None else urdf_text(source)
    urdf = yourdfpy.URDF.load(
        io.BytesIO(xml.encode()),
        build_scene_graph=False,
        build_collision_scene_graph=False,
        load_meshes=False,
        load_collision_meshes=False,
    )
    named = {m.name: m for m in urdf.robot.materials if m.name}
    model = arm.model
    parts: list[Part] = []
    missing: list[str] = []
    for link in urdf.robot.links:
        if not link.visuals or not model.existFrame(link.name, pin.BODY):
            continue  # links of the URDF that the arm's model does not hold
        frame = model.frames[model.getFrameId(link.name, pin.BODY)]
        T_joint_link = frame.placement.homogeneous
        for visual in link.visuals:
            origin = np.eye(4) if visual.origin is None else np.asarray(visual.origin, float)
            color = _color(visual.material, named)
            meshes, problem = _geometry(visual.geometry, source, color, trimesh)
            if problem:
                missing.append(f"{problem} of link {link.name!r}")
                continue
            for mesh in meshes:
                parts.append(Part(frame.parentJoint, T_joint_link @ origin, mesh, link.name))
    return parts, missing


def _geometry(geometry, source: Path | None, color, trimesh) -> tuple[list, str]:
    """The trimeshes of one visual (in the visual's frame) or why there are none."""
    if geometry is None:
        return [], ""
    if geometry.box is not None:
        meshes = [trimesh.creation.box(extents=np.asarray(geometry.box.size, float))]
    elif geometry.cylinder is not None:
        c = geometry.cylinder
        meshes = [trimesh.creation.cylinder(radius=c.radius, height=c.length, sections=32)]
    elif geometry.sphere is not None:
        meshes = [trimesh.creation.icosphere(subdivisions=3, radius=geometry.sphere.radius)]
    elif geometry.mesh is not None:
        name = geometry.mesh.filename
        path = resolve(name, source)
        if path is None:
            return [], f"{name!r} not found"
        try:
            loaded = trimesh.load(path)
        except Exception as exc:  # a format trimesh cannot read (a .dae without pycollada)
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return [], f"{name!r} cannot be read ({why})"
        meshes = loaded.dump() if isinstance(loaded, trimesh.Scene) else [loaded]
        meshes = [m for m in meshes if isinstance(m, trimesh.Trimesh) and len(m.faces)]
        if not meshes:
            return [], f"{name!r} holds no triangles"
        scale = geometry.mesh.scale
        if scale is not None:
            S = np.diag([*np.broadcast_to(np.asarray(scale, float), (3,)), 1.0])
            for m in meshes:
                m.apply_transform(S)
        if color is None:
            return meshes, ""  # the file's own materials
    else:
        return [], ""
    for m in meshes:
        if m.visual.kind != "texture":
            m.visual = trimesh.visual.ColorVisuals(m, face_colors=color or DEFAULT_COLOR)
    return meshes, ""


def _color(material, named: dict) -> tuple[int, int, int, int] | None:
    if material is None:
        return None
    if material.color is None and material.name in named:
        material = named[material.name]
    if material.color is None or material.color.rgba is None:
        return None
    rgba = np.clip(np.asarray(material.color.rgba, float), 0, 1)
    return tuple(int(round(255 * v)) for v in rgba)  # type: ignore[return-value]


def resolve(filename: str, urdf_path: str | Path | None) -> Path | None:
    """The file a URDF's mesh ``filename`` names (see the module docstring), or None;
    ``urdf_path`` None: a URDF read from text, whose folder is unknown."""
    here = None if urdf_path is None else Path(urdf_path).resolve().parent
    ancestors = [] if here is None else [here, *here.parents]
    if filename.startswith("file://"):
        candidates = [Path(filename[len("file://") :])]
    elif filename.startswith("package://"):
        package, _, rest = filename[len("package://") :].partition("/")
        if not package or not rest:
            return None  # not package://NAME/PATH
        candidates = [a / rest for a in ancestors if a.name == package]
        for d in _env_dirs("ROS_PACKAGE_PATH"):
            candidates += [d / package / rest] + ([d / rest] if d.name == package else [])
        for prefix in _env_dirs("AMENT_PREFIX_PATH") + _env_dirs("CMAKE_PREFIX_PATH"):
            candidates.append(prefix / "share" / package / rest)
        candidates += [a / rest for a in ancestors]
    else:
        candidates = [] if here is None else [here / filename]
    return next((c for c in candidates if c.is_file()), None)


def _env_dirs(variable: str) -> list[Path]:
    return [Path(p) for p in os.environ.get(variable, "").split(os.pathsep) if p]
