"""Random 6R arms of each kinematic family, as URDF text: for tests and benchmarks.

``random_axes(kind, rng)`` draws six axis lines (a point and a unit direction each, in the
base frame at q = 0) with the structure ``kind`` names and nothing else; ``urdf_text``
writes them as a 6R URDF (links ``world`` ... ``tool``) with a random fixed transform
before joint 1 (``mount``) and after joint 6 (``tool_joint``), every joint limited to
+-2 pi. Load one with ``armik.load_string(text, base="world", tip="tool")`` (or a file).

Kinds (IK-Geo's classification of 6R arms):

- ``parallel_23``: spherical wrist, axes 2 and 3 parallel
- ``meeting_12``: spherical wrist, axes 1 and 2 meeting
- ``three_parallel``: axes 2, 3, 4 parallel, axes 5 and 6 meeting (the UR family)
- ``spherical``: spherical wrist, the first three axes arbitrary
- ``three_parallel_free``: axes 2, 3, 4 parallel, nothing else
- ``two_parallel``: axes 2 and 3 parallel, nothing else
- ``two_intersecting``: axes 5 and 6 meeting, nothing else
- ``general``: every axis random

``iiwa_like_urdf()``: not random, a 7R arm with a KUKA iiwa 14's kinematics (a spherical
shoulder and wrist), for the solves with one joint held.
"""

from __future__ import annotations

import numpy as np

KINDS = (
    "parallel_23",
    "meeting_12",
    "three_parallel",
    "spherical",
    "three_parallel_free",
    "two_parallel",
    "two_intersecting",
    "general",
)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def random_axes(kind: str, rng: np.random.Generator) -> tuple[list, list]:
    """Axis lines (points c, unit directions h; six of each, m) of a random arm of
    ``kind`` (one of ``KINDS``). Raises ValueError for another kind."""
    if kind not in KINDS:
        raise ValueError(f"unknown kind {kind!r} of random arm; kinds: {', '.join(KINDS)}")
    h = [_unit(rng.normal(size=3)) for _ in range(6)]
    c = [rng.uniform(-0.4, 0.4, size=3) for _ in range(6)]

    def sign() -> float:
        return float(rng.choice([-1.0, 1.0]))

    if kind in ("parallel_23", "meeting_12", "spherical"):
        wrist = rng.uniform(-0.5, 0.5, size=3)
        c[3] = c[4] = c[5] = wrist
        if kind == "parallel_23":
            h[2] = h[1] * sign()
        elif kind == "meeting_12":
            c[1] = c[0] + rng.uniform(-0.3, 0.3) * h[0]  # axis 2 crosses axis 1 at c[1]
    elif kind in ("three_parallel", "three_parallel_free"):
        h[2] = h[1] * sign()
        h[3] = h[1] * sign()
        if kind == "three_parallel":
            c[5] = c[4]
    elif kind == "two_parallel":
        h[2] = h[1] * sign()
    elif kind == "two_intersecting":
        c[5] = c[4]
    return c, h


def _fmt(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def urdf_text(c, h, rng: np.random.Generator, limit: float = 2 * np.pi) -> str:
    """A 6R URDF of the axis lines ``c``, ``h`` (``random_axes``), with random fixed
    transforms before joint 1 and after joint 6."""
    parts = ['<?xml version="1.0"?>', '<robot name="random_6r">', '  <link name="world"/>']
    parts += [f'  <link name="l{i}"/>' for i in range(7)] + ['  <link name="tool"/>']
    parts.append(
        '  <joint name="mount" type="fixed"><parent link="world"/><child link="l0"/>'
        f'<origin xyz="{_fmt(rng.uniform(-1, 1, size=3))}" '
        f'rpy="{_fmt(rng.uniform(-3, 3, size=3))}"/></joint>'
    )
    prev = np.zeros(3)
    for i, (ci, hi) in enumerate(zip(c, h)):
        parts.append(
            f'  <joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{_fmt(ci - prev)}" rpy="0 0 0"/>'
            f'<axis xyz="{_fmt(hi)}"/>'
            f'<limit lower="{-limit}" upper="{limit}" effort="1" velocity="1"/></joint>'
        )
        prev = ci
    parts.append(
        '  <joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>'
        f'<origin xyz="{_fmt(rng.uniform(-0.2, 0.2, size=3))}" '
        f'rpy="{_fmt(rng.uniform(-3, 3, size=3))}"/></joint>'
    )
    parts.append("</robot>")
    return "\n".join(parts)


def random_urdf(kind: str, rng: np.random.Generator) -> str:
    """The URDF text of a random arm of ``kind`` (``random_axes``, ``urdf_text``)."""
    c, h = random_axes(kind, rng)
    return urdf_text(c, h, rng)


# (origin, axis, limit in degrees) of each joint of a KUKA iiwa 14: axes 1, 2, 3 meet
# (a spherical shoulder), and so do 5, 6, 7 (a spherical wrist)
IIWA = (
    ("0 0 0.1575", "0 0 1", 170),
    ("0 0 0.2025", "0 1 0", 120),
    ("0 0 0.2045", "0 0 1", 170),
    ("0 0 0.2155", "0 -1 0", 120),
    ("0 0 0.1845", "0 0 1", 170),
    ("0 0 0.2155", "0 1 0", 120),
    ("0 0 0.081", "0 0 1", 175),
)


def iiwa_like_urdf() -> str:
    """A URDF of the iiwa's kinematics: links ``base``, ``l1`` ... ``l7``, ``tool``, joints
    ``j1`` ... ``j7``, no geometry."""
    parts = ['<?xml version="1.0"?>', '<robot name="iiwa_like">', '<link name="base"/>']
    parts += [f'<link name="l{i}"/>' for i in range(1, 8)] + ['<link name="tool"/>']
    parent = "base"
    for i, (xyz, axis, limit) in enumerate(IIWA, start=1):
        rad = np.radians(limit)
        parts.append(
            f'<joint name="j{i}" type="revolute"><parent link="{parent}"/><child link="l{i}"/>'
            f'<origin xyz="{xyz}"/><axis xyz="{axis}"/>'
            f'<limit lower="{-rad}" upper="{rad}" effort="1" velocity="1"/></joint>'
        )
        parent = f"l{i}"
    parts.append(
        '<joint name="flange" type="fixed"><parent link="l7"/><child link="tool"/>'
        '<origin xyz="0 0 0.045"/></joint></robot>'
    )
    return "\n".join(parts)
