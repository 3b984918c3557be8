"""Seeded mutations of the bundled URDFs: each mutant either is refused with an
``ArmikError`` or loads into an arm whose FK agrees with yourdfpy's, an independent reader
(given the same file with its axes normalised: armik follows the ROS reading of a
non-unit axis, yourdfpy scales by the norm; see ``armik.model.urdf``)."""

from __future__ import annotations

import copy
import io
import logging
import math
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import yourdfpy

import armik
from armik.errors import ArmikError
from armik.model.catalogue import entry

ROBOTS = ["planar_3link", "scara", "ur5"]
MUTANTS_PER_ROBOT = 80
VALUES = ["0", "-0", "1e-200", "1e300", "nan", "inf", "-inf", "1x", "", "2.5", "-0.7", "1e7"]


def mutate(root: ET.Element, rng: np.random.Generator) -> str:
    """One random edit: a number in an origin, axis or limit, a removed element, a
    renamed joint or link, a changed joint type. Returns what was done."""
    joints = root.findall("joint")
    j = joints[rng.integers(len(joints))]
    kind = rng.integers(6)
    if kind <= 2:  # a number
        tag = ["origin", "axis", "limit"][kind]
        elem = j.find(tag)
        if elem is None:
            elem = ET.SubElement(j, tag)
        attrs = {"origin": ["xyz", "rpy"], "axis": ["xyz"], "limit": ["lower", "upper"]}[tag]
        attr = attrs[rng.integers(len(attrs))]
        value = VALUES[rng.integers(len(VALUES))]
        if attr in ("xyz", "rpy"):
            parts = (elem.get(attr) or "0 0 0").split()
            if len(parts) == 3 and rng.random() < 0.8:
                parts[rng.integers(3)] = value
                value = " ".join(parts)
            elif rng.random() < 0.5:
                value = f"{value} {value} {value}"
        elem.set(attr, value)
        return f"{j.get('name')}: {tag} {attr}={value!r}"
    if kind == 3:  # remove an element
        tag = ["origin", "axis", "limit", "parent", "child"][rng.integers(5)]
        elem = j.find(tag)
        if elem is not None:
            j.remove(elem)
        return f"{j.get('name')}: removed <{tag}>"
    if kind == 4:  # a name shared with another joint or a link
        others = [x.get("name") for x in joints] + [x.get("name") for x in root.findall("link")]
        new = others[rng.integers(len(others))]
        j.set("name", new)
        return f"{j.get('name')}: renamed to {new!r}"
    new_type = ["revolute", "continuous", "prismatic", "fixed", "floating", "hinge"][
        rng.integers(6)
    ]
    j.set("type", new_type)
    return f"{j.get('name')}: type {new_type}"


def normalised_axes(root: ET.Element) -> ET.Element:
    out = copy.deepcopy(root)
    for axis in out.iter("axis"):
        try:
            v = [float(x) for x in (axis.get("xyz") or "").split()]
            n = math.hypot(*v)
        except (TypeError, ValueError):
            continue
        if len(v) == 3 and math.isfinite(n) and n > 0:
            axis.set("xyz", " ".join(repr(c / n) for c in v))
    return out


def yourdfpy_tip(text: str, arm: armik.Arm, q: np.ndarray) -> np.ndarray | None:
    try:
        robot = yourdfpy.URDF.load(io.StringIO(text), load_meshes=False, build_scene_graph=True)
        robot.update_cfg(dict(zip(arm.joint_names, q.tolist())))
        return robot.get_transform(arm.tip, arm.base)
    except Exception:  # yourdfpy refuses or misreads what armik read: nothing to compare
        return None


@pytest.mark.parametrize("robot", ROBOTS)
def test_mutants_are_refused_or_agree_with_yourdfpy(robot, tmp_path):
    spec = entry(robot)
    original = ET.parse(spec.urdf_path()).getroot()
    rng = np.random.default_rng(2026)
    refused = compared = 0
    logging.getLogger("yourdfpy").setLevel(logging.CRITICAL)
    for k in range(MUTANTS_PER_ROBOT):
        root = copy.deepcopy(original)
        what = mutate(root, rng)
        path = tmp_path / f"{robot}_{k}.urdf"
        path.write_text(ET.tostring(root, encoding="unicode"))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                arm = armik.load(path, tip=spec.tip)
        except ArmikError as exc:
            refused += 1
            # Every refusal says what is wrong, never only Pinocchio's generic line.
            assert "not contain a valid URDF model" not in str(exc), f"mutant {k} ({what})"
            assert "\n" not in str(exc)
            continue
        # Anything else raised above fails the test: a raw exception is a bug.
        reference = ET.tostring(normalised_axes(root), encoding="unicode")
        for _ in range(3):
            q = arm.random_q(rng)
            T_ref = yourdfpy_tip(reference, arm, q)
            if T_ref is None:
                break
            T = arm.fk(q).homogeneous
            assert np.abs(T - T_ref).max() < 1e-9, f"mutant {k} ({what}): FK differs"
            compared += 1
    assert refused > 0 and compared > 0, (refused, compared)


@pytest.mark.parametrize("robot", ["panda", "ur5"])
def test_a_joint_named_universe_reads_as_yourdfpy_reads_it(tmp_path, robot):
    # Pinocchio calls its root joint and frame "universe": a URDF joint of that name must
    # still get its own placement when the joints off the chain are locked (the Panda's
    # fingers), where a lookup by name would find the root frame instead.
    base = armik.load(robot)
    text = open(base.source).read()
    rng = np.random.default_rng(3)
    for joint in base.joint_names:
        path = tmp_path / f"{joint}.urdf"
        path.write_text(text.replace(f'"{joint}"', '"universe"'))
        a = armik.load(path, tip=base.tip)
        assert "universe" in a.joint_names
        reader = yourdfpy.URDF.load(str(path), load_meshes=False, build_scene_graph=True)
        for q in (np.zeros(a.dof), a.random_q(rng)):
            reader.update_cfg(dict(zip(a.joint_names, q)))
            T_ref = reader.get_transform(a.tip, a.base)
            np.testing.assert_allclose(a.fk(q).homogeneous, T_ref, atol=1e-9)
