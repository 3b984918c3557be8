"""Arms from ssik's prebuilt artifacts, for the benchmarks against ssik: the kinematic URDF
of an artifact's baked constants, and ssik's own solver of it (its native general-6R call
with the artifact's baked Raghavan-Roth tensor, as the artifact's ``solve`` makes it).

The constants are read from the artifact's source (``ast``), not by importing it: the
artifacts import sympy and mpmath, which the native call does not need. ssik is for
measuring only, never a dependency of armik.
"""

from __future__ import annotations

import ast
import importlib.util
import os
from pathlib import Path

import numpy as np
import pinocchio as pin

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

# name here -> the artifact's module under ssik.prebuilt
ARTIFACTS = {
    "kinova_jaco2": "kinova.jaco2",  # Kinova JACO 2 (j2n6s200): a 60-degree wrist
    "ufactory_xarm6": "ufactory.xarm6",  # UFactory xArm6: joint 6 offset from joint 5
    # more non-Pieper arms, for the solution sets (--arms)
    "fanuc_crx10ia": "fanuc.crx10ia",
    "agilex_piper": "agilex.piper",
    "i2rt_yam": "i2rt.yam",
    "kinova_gen3_lite": "kinova.gen3_lite",
    "doosan_m1013": "doosan.m1013",
    "yaskawa_hc10": "yaskawa.hc10",
    "rokae_xmatecr7": "rokae.xmatecr7",
}
_NAMES = ("_JOINT_AXES", "_JOINT_T_LEFTS", "_JOINT_T_RIGHTS", "_JOINT_LIMITS", "T_HOME",
          "_JOINT_NAMES", "_LINK_NAMES", "_JOINT_TYPES", "SOLVER_NAME")  # fmt: skip


def _prebuilt() -> Path | None:
    spec = importlib.util.find_spec("ssik")
    return None if spec is None or spec.origin is None else Path(spec.origin).parent / "prebuilt"


def available() -> bool:
    return _prebuilt() is not None


def constants(name: str) -> dict:
    """The baked constants of artifact ``name`` (``ARTIFACTS``)."""
    folder, module = ARTIFACTS[name].split(".")
    path = _prebuilt() / folder / f"{module}_ik.py"
    out, env = {}, {"np": np}
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            key = getattr(node.targets[0], "id", None)
            if key in _NAMES:
                out[key] = eval(compile(ast.Expression(node.value), str(path), "eval"), env)
    out["rr_npz"] = path.with_name(f"{module}_rr.npz")
    return out


def _origin(T: np.ndarray) -> str:
    xyz = " ".join(repr(float(v)) for v in T[:3, 3])
    rpy = " ".join(repr(float(v)) for v in pin.rpy.matrixToRpy(T[:3, :3]))
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def urdf(name: str) -> str:
    """The artifact's chain as a URDF from ``base`` to ``tool`` (its base and end-effector
    links): joint i's origin is joint i - 1's T_right times joint i's T_left; a joint
    without limits gets +-2 pi."""
    c = constants(name)
    parts, before = [f'<robot name="{name}">', '<link name="base"/>'], np.eye(4)
    for i, axis in enumerate(c["_JOINT_AXES"]):
        lo, hi = c["_JOINT_LIMITS"][i] or (-2 * np.pi, 2 * np.pi)
        parent = "base" if i == 0 else f"l{i}"
        parts += [
            f'<link name="l{i + 1}"/>',
            f'<joint name="j{i + 1}" type="revolute"><parent link="{parent}"/>'
            f'<child link="l{i + 1}"/>{_origin(before @ c["_JOINT_T_LEFTS"][i])}'
            f'<axis xyz="{" ".join(repr(float(v)) for v in axis)}"/>'
            f'<limit lower="{float(lo)!r}" upper="{float(hi)!r}" effort="1" velocity="1"/>'
            "</joint>",
        ]
        before = c["_JOINT_T_RIGHTS"][i]
    parts += [
        '<link name="tool"/>',
        f'<joint name="tool_joint" type="fixed"><parent link="l{len(c["_JOINT_AXES"])}"/>'
        f'<child link="tool"/>{_origin(before)}</joint>',
        "</robot>",
    ]
    return "\n".join(parts)


def solver(name: str):
    """ssik's solve of artifact ``name``: a 4x4 pose of ``tool`` in ``base`` -> its every
    branch within the limits (``Solution``s), one configuration a branch."""
    from ssik._kinbody import Joint, KinBody, Link
    from ssik._native import load_rr_native_geometry, try_native_solve

    c = constants(name)
    links = [Link(name=n) for n in c["_LINK_NAMES"]]
    joints = [
        Joint(
            name=c["_JOINT_NAMES"][i],
            dof_index=i,
            parent_link=links[i],
            T_left=c["_JOINT_T_LEFTS"][i],
            T_right=c["_JOINT_T_RIGHTS"][i],
            axis=c["_JOINT_AXES"][i],
            joint_type=c["_JOINT_TYPES"][i],
            limits=c["_JOINT_LIMITS"][i],
        )  # fmt: skip
        for i in range(len(c["_JOINT_NAMES"]))
    ]
    kb = KinBody(links=links, joints=joints)
    geometry = load_rr_native_geometry(str(c["rr_npz"]))
    kind = c["SOLVER_NAME"]

    def solve(H: np.ndarray) -> list:
        return try_native_solve(kind, kb, H, enumerate_windings=False, rr_geometry=geometry)

    return solve
