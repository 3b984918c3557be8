"""6R arms written for the closed-form tests: variants of the bundled ones with base
mounts, tools and near misses."""

from __future__ import annotations

import math

# (origin xyz, origin rpy, axis) of each joint, ABB IRB 120 (robots/abb_irb120.urdf)
IRB120 = [
    ("0 0 0", "0 0 0", "0 0 1"),
    ("0 0 0.29", "0 0 0", "0 1 0"),
    ("0 0 0.27", "0 0 0", "0 1 0"),
    ("0 0 0.07", "0 0 0", "1 0 0"),
    ("0.302 0 0", "0 0 0", "0 1 0"),
    ("0.072 0 0", "0 0 0", "1 0 0"),
]
# UR5 from its DH parameters (d1 0.089159, a2 0.425, a3 0.39225, d4 0.10915, d5 0.09465,
# d6 0.0823), with joint axes flipped here and there to exercise the signs.
UR5 = [
    ("0 0 0.089159", "0 0 0", "0 0 1"),
    ("0 0.13585 0", "0 0 0", "0 1 0"),
    ("0.425 -0.1197 0", "0 0 0", "0 -1 0"),
    ("0.39225 0 0", "0 0 0", "0 1 0"),
    ("0 0.093 0", "0 0 0", "0 0 -1"),
    ("0 0 -0.09465", "0 0 0", "0 1 0"),
]
# Axes 1 and 2 meet, axes 2 and 3 do not run parallel; spherical wrist.
MEETING_12 = [
    ("0 0 0.3", "0 0 0", "0 0 1"),
    ("0 0 0.1", "0 0 0", "0 1 0"),
    ("0.05 0 0.4", "0 0 0", "1 0 0"),
    ("0.3 0.1 0.05", "0 0 0", "0 0 1"),
    ("0 0 0.2", "0 0 0", "0 1 0"),
    ("0 0 0", "0 0 0", "0 0 1"),
]
# Axis 6 of the IRB 120 moved 1 mm off the wrist centre.
IRB120_NEAR_MISS = [*IRB120[:5], ("0.072 0.001 0", "0 0 0", "1 0 0")]
# Axis 3 of the UR5 tilted by 1 mrad.
UR5_NEAR_MISS = [*UR5[:2], ("0.425 -0.1197 0", "0.001 0 0", "0 -1 0"), *UR5[3:]]


def six_r(
    joints,
    *,
    mount_xyz: str = "0 0 0",
    mount_rpy: str = "0 0 0",
    tool_xyz: str = "0 0 0",
    tool_rpy: str = "0 0 0",
    limit: float = 2 * math.pi,
) -> str:
    parts = ['<?xml version="1.0"?>', '<robot name="six_r">', '  <link name="world"/>']
    parts += [f'  <link name="l{i}"/>' for i in range(7)] + ['  <link name="tool"/>']
    parts.append(
        '  <joint name="mount" type="fixed"><parent link="world"/><child link="l0"/>'
        f'<origin xyz="{mount_xyz}" rpy="{mount_rpy}"/></joint>'
    )
    for i, (xyz, rpy, axis) in enumerate(joints):
        parts.append(
            f'  <joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>'
            f'<limit lower="{-limit}" upper="{limit}" effort="1" velocity="1"/></joint>'
        )
    parts.append(
        '  <joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>'
        f'<origin xyz="{tool_xyz}" rpy="{tool_rpy}"/></joint>'
    )
    parts.append("</robot>")
    return "\n".join(parts)
