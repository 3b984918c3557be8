"""IK-Geo's public test cases (tests/data/ikgeo, see its README.md) as armik arms and
targets.

Each case is an arm given by IK-Geo's kinematics (H: the joint axes, P: the vectors
between them, from the base to the tool; every frame the base's at q = 0), a target
pose T_0T = (R, T) and the configuration Q that IK-Geo's setup drew and took the FK of.
The eight robot-class files hold one random arm a case (H and P in the row); the named
robots' files hold targets only, their H and P written here from IK-Geo's
``matlab/+hardcoded_IK_setups/<name>.m``. Three of them are 7R arms with one joint held
at a value (IK-Geo's ``fixed_q3``, ``fixed_q6``), solved here with ``hold=``.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DATA = Path(__file__).parent / "data" / "ikgeo"

# the robot classes: one random arm a case (IK-Geo's ``+IK_setups``)
CLASSES = (
    "IK_spherical_2_parallel",
    "IK_spherical_2_intersecting",
    "IK_spherical",
    "IK_3_parallel",
    "IK_3_parallel_2_intersecting",
    "IK_2_parallel",
    "IK_2_intersecting",
    "IK_gen_6_dof",
)

_X, _Y, _Z, _0 = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)


def _v(*terms: tuple[float, tuple]) -> tuple:
    """The sum of scale * axis terms."""
    return tuple(float(sum(s * a[i] for s, a in terms)) for i in range(3))


_S = tuple(c / math.sqrt(2.0) for c in (1.0, 0.0, 1.0))  # two_parallel_bot's es
_IN = 0.0254  # RRC's inches
_YUMI_P = np.array(
    [
        [0.0536, 0.0642, 0.1578, 0.0880, 0.1270, 0.0354, 0.0385, 0.0040],
        [0.0725, 0.0527, 0.0406, 0.0011, -0.0877, -0.0712, -0.0087, -0.0043],
        [0.4149, 0.0632, 0.0650, 0.0143, -0.0700, -0.0670, -0.0030, -0.0038],
    ]
)
_YUMI_H = np.array(
    [
        [0.8138, 0.1048, 0.8138, 0.1048, 0.5716, 0.1048, 0.5716],
        [0.3420, 0.7088, 0.3420, 0.7088, -0.6170, 0.7088, -0.6170],
        [0.4698, -0.6976, 0.4698, -0.6976, -0.5410, -0.6976, -0.5410],
    ]
)
_YUMI_H = _YUMI_H / np.linalg.norm(_YUMI_H, axis=0)  # as its setup normalises them

# the named robots: (H columns, P columns, the held joint (1-based) and its value, or None)
ROBOTS: dict[str, tuple] = {
    "IRB_6640": (
        (_Z, _Y, _Y, _X, _Y, _X),
        (
            _0,
            _v((0.32, _X), (0.78, _Z)),
            _v((1.075, _Z)),
            _v((1.1425, _X), (0.2, _Z)),
            _0,
            _0,
            _v((0.2, _X)),
        ),
        None,
    ),  # fmt: skip
    "ur5": (
        (_Z, _Y, _Y, _Y, _v((-1.0, _Z)), _Y),
        (
            _v((0.089159, _Z)),
            _v((0.1358, _Y)),
            _v((-0.1197, _Y), (0.425, _X)),
            _v((0.3922, _X)),
            _v((0.093, _Y), (-0.0946, _Z)),
            _0,
            _v((0.0823, _Y)),
        ),
        None,
    ),  # fmt: skip
    "spherical_bot": (
        (_Y, _Z, _Y, _X, _Y, _X),
        (_0, _v((1, _Z), (1, _X)), _v((1, _Z), (1, _X)), _v((1, _Z), (1, _X)), _0, _0, _X),
        None,
    ),
    "three_parallel_bot": (
        (_Z, _X, _X, _X, _Z, _X),
        (_Z, _Y, _Y, _Y, _Y, _v((1, _Y), (1, _X)), _X),
        None,
    ),
    "two_parallel_bot": ((_Z, _X, _X, _Z, _X, _S), (_Z, _Y, _Y, _Y, _Y, _Y, _Z), None),
    "KUKA_R800_fixed_q3": (
        (_Z, _Y, _Z, _v((-1, _Y)), _Z, _Y, _Z),
        (
            _v((0.15 + 0.19, _Z)),
            _0,
            _v((0.21, _Z)),
            _v((0.19, _Z)),
            _v((0.21 + 0.19, _Z)),
            _0,
            _0,
            _v((0.081 + 0.045, _Z)),
        ),
        (3, math.pi / 6),
    ),  # fmt: skip
    "RRC_fixed_q6": (
        (_X, _Z, _X, _Z, _X, _Z, _X),
        tuple(
            _v((_IN * a, _X), (_IN * b, _Y))
            for a, b in (
                (0, 0),
                (20, -4),
                (0, 4),
                (21.5, 3.375),
                (0, -3.375),
                (21.5, 3.325),
                (0, -3.325),
                (7, 0),
            )
        ),  # fmt: skip
        (6, math.pi / 6),
    ),
    "yumi_fixed_q3": (tuple(map(tuple, _YUMI_H.T)), tuple(map(tuple, _YUMI_P.T)), (3, math.pi / 6)),
}

FILES = (*CLASSES, *ROBOTS)


@dataclass(frozen=True)
class Case:
    """One test case: the arm's URDF, the target (4x4, base frame), the configuration IK-Geo
    drew (rad), and the held joint's name and value (or None)."""

    urdf: str
    target: np.ndarray
    q: np.ndarray
    hold: dict | None


def urdf(H, P, limit: float = 2 * math.pi) -> str:
    """A chain of revolute joints j1..jn from ``world`` to ``tool``: joint i placed at
    P[i - 1] from joint i - 1 (no rotation: every frame is the base's at q = 0), turning
    about H[i - 1]; the tool at P[n] from joint n, its frame the base's at q = 0 (IK-Geo's
    FK: R_0T = rot(h1, q1) ... rot(hn, qn), p_0T = p_01 + R_01 p_12 + ... + R_0n p_nT)."""

    def xyz(v) -> str:
        return " ".join(repr(float(c)) for c in v)

    n = len(H)
    parts = ['<?xml version="1.0"?>', '<robot name="ikgeo">', '  <link name="world"/>']
    parts += [f'  <link name="l{i}"/>' for i in range(1, n + 1)] + ['  <link name="tool"/>']
    for i in range(1, n + 1):
        parent = "world" if i == 1 else f"l{i - 1}"
        parts.append(
            f'  <joint name="j{i}" type="revolute"><parent link="{parent}"/>'
            f'<child link="l{i}"/><origin xyz="{xyz(P[i - 1])}"/><axis xyz="{xyz(H[i - 1])}"/>'
            f'<limit lower="{-limit!r}" upper="{limit!r}" effort="1" velocity="1"/></joint>'
        )
    parts.append(
        f'  <joint name="tool_joint" type="fixed"><parent link="l{n}"/><child link="tool"/>'
        f'<origin xyz="{xyz(P[n])}"/></joint>'
    )
    parts.append("</robot>")
    return "\n".join(parts)


def _target(row: dict) -> np.ndarray:
    """The 4x4 of a row's R (column-major, as MATLAB's ``R(:)``) and T."""
    H = np.eye(4)
    H[:3, :3] = np.array([row[f"R_{i}"] for i in range(1, 10)]).reshape(3, 3, order="F")
    H[:3, 3] = [row[f"T_{i}"] for i in range(1, 4)]
    return H


def cases(name: str) -> list[Case]:
    """The cases of IK-Geo's file ``name`` (a ``FILES`` entry), in its order."""
    with open(DATA / f"{name}.csv", newline="") as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    out = []
    for row in rows:
        if name in ROBOTS:
            H, P, held = ROBOTS[name]
        else:
            H = np.array([row[f"H_{i}"] for i in range(1, 19)]).reshape(3, 6, order="F").T
            P = np.array([row[f"P_{i}"] for i in range(1, 22)]).reshape(3, 7, order="F").T
            held = None
        dof = len(H)
        q = np.array([row[f"Q_{i}"] for i in range(1, dof + 1)])
        hold = None if held is None else {f"j{held[0]}": held[1]}
        out.append(Case(urdf(H, P), _target(row), q, hold))
    return out


def found(expected: np.ndarray, answers: list[np.ndarray], tol: float = 1e-6) -> bool:
    """Whether one of ``answers`` is ``expected``, each joint within ``tol`` rad modulo
    2 pi."""
    for q in answers:
        d = np.asarray(q) - expected
        if np.all(np.abs(np.arctan2(np.sin(d), np.cos(d))) < tol):
            return True
    return False
