"""Small URDFs written in the tests, for the URDF-reading tests."""

from __future__ import annotations

LIMIT = '<limit lower="-2" upper="2" effort="1" velocity="1"/>'


def joint(
    name: str,
    parent: str,
    child: str,
    jtype: str = "revolute",
    xyz: str = "0 0 0.1",
    axis: str | None = '<axis xyz="0 0 1"/>',
    limit: str | None = LIMIT,
    rpy: str = "0 0 0",
) -> str:
    inner = f'<parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}" rpy="{rpy}"/>'
    if axis is not None and jtype != "fixed":
        inner += axis
    if limit is not None and jtype in ("revolute", "prismatic"):
        inner += limit
    return f'<joint name="{name}" type="{jtype}">{inner}</joint>'


def chain(*joints: str, links: list[str] | None = None, name: str = "chain") -> str:
    """A URDF with the given joints; links are those the joints name (or ``links``)."""
    import re

    if links is None:
        links = []
        for j in joints:
            for link in re.findall(r'link="([^"]+)"', j):
                if link not in links:
                    links.append(link)
    body = "".join(f'<link name="{link}"/>' for link in links) + "".join(joints)
    return f'<?xml version="1.0"?><robot name="{name}">{body}</robot>'


def arm3(axis2: str = "0 1 0", jtype2: str = "revolute", limit2: str = LIMIT, **kw) -> str:
    """base -> j1 (z) -> j2 (axis2) -> j3 (y) -> fixed tool."""
    return chain(
        joint("j1", "base", "l1"),
        joint(
            "j2",
            "l1",
            "l2",
            jtype=jtype2,
            xyz="0 0 0.3",
            axis=f'<axis xyz="{axis2}"/>',
            limit=limit2,
        ),
        joint("j3", "l2", "l3", xyz="0.25 0 0", axis='<axis xyz="0 1 0"/>'),
        joint("tool_joint", "l3", "tool", jtype="fixed", xyz="0.2 0 0"),
        **kw,
    )
