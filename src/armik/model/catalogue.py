"""The bundled robot catalogue: name -> URDF file, default tip, locked joints.

Two sources: URDFs shipped with armik (``robots/`` in the source tree, ``armik/robots``
in an installed wheel) and the arms that the ``example-robot-data`` package installs.
Nothing is downloaded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache
from importlib import metadata
from pathlib import Path

from armik.errors import InputError, did_you_mean, listing

ARMIK = "armik"
ERD = "example-robot-data"


@dataclass(frozen=True)
class RobotEntry:
    """One bundled arm. ``tip_offset`` adds a tool point (m) in the tip frame."""

    name: str
    source: str
    relpath: str
    tip: str
    description: str
    base: str | None = None
    tip_offset: tuple[float, float, float] | None = None
    locked: dict[str, float] = field(default_factory=dict)

    def urdf_path(self) -> Path:
        root = _armik_robot_dir() if self.source == ARMIK else _erd_robot_dir()
        return root / self.relpath


CATALOGUE: dict[str, RobotEntry] = {
    e.name: e
    for e in [
        RobotEntry(
            "planar_2link",
            ARMIK,
            "planar_2link.urdf",
            "tip",
            "2R planar arm about z, l1 = 1.0 m, l2 = 0.8 m (the worked example)",
        ),
        RobotEntry(
            "planar_3link",
            ARMIK,
            "planar_3link.urdf",
            "tip",
            "3R planar arm about z, links 1.0, 0.8, 0.5 m",
        ),
        RobotEntry(
            "scara",
            ARMIK,
            "scara.urdf",
            "tool",
            "SCARA: 2 revolute, 1 prismatic, 1 continuous joint",
        ),
        RobotEntry(
            "abb_irb120",
            ARMIK,
            "abb_irb120.urdf",
            "tool0",
            "ABB IRB 120, 6 DOF with a spherical wrist (ABB's published dimensions)",
        ),
        RobotEntry(
            "kuka_iiwa14",
            ARMIK,
            "kuka_iiwa14.urdf",
            "iiwa_link_ee",
            "KUKA LBR iiwa 14 R820, 7 DOF, SRS (KUKA's published dimensions)",
        ),
        RobotEntry(
            "panda",
            ERD,
            "panda_description/urdf/panda.urdf",
            "panda_hand",
            "Franka Emika Panda, 7 DOF, fingers locked",
        ),
        RobotEntry(
            "ur5", ERD, "ur_description/urdf/ur5_robot.urdf", "tool0", "Universal Robots UR5, 6 DOF"
        ),
        RobotEntry(
            "ur10",
            ERD,
            "ur_description/urdf/ur10_robot.urdf",
            "tool0",
            "Universal Robots UR10, 6 DOF",
        ),
        RobotEntry(
            "kinova",
            ERD,
            "kinova_description/robots/kinova.urdf",
            "j2s6s200_end_effector",
            "Kinova Jaco 2 (j2s6s200), 6 DOF, 3 continuous joints",
        ),
        RobotEntry(
            "xarm7", ERD, "xarm_description/urdf/xarm7.urdf", "link_eef", "UFactory xArm 7, 7 DOF"
        ),
        RobotEntry(
            "z1",
            ERD,
            "z1_description/urdf/z1.urdf",
            "gripperStator",
            "Unitree Z1, 6 DOF, gripper locked",
        ),
        RobotEntry(
            "so101",
            ERD,
            "so_arm_description/urdf/so101.urdf",
            "gripper_frame_link",
            "SO-101 (LeRobot), 5 DOF, gripper locked: a position and a tool direction",
        ),
        RobotEntry(
            "double_pendulum",
            ERD,
            "double_pendulum_description/urdf/double_pendulum_simple.urdf",
            "link2",
            "double pendulum, 2R about x; tool point at the end of the 0.2 m link 2",
            tip_offset=(0.0, 0.0, 0.2),
        ),
    ]
}

#: The arms with a full 3D workspace, used by the benchmark.
SPATIAL_ARMS = ("panda", "ur5", "ur10", "kinova", "xarm7", "z1")


def robots() -> list[str]:
    """Names of the bundled arms, for ``armik.load``."""
    return list(CATALOGUE)


def entry(name: str) -> RobotEntry:
    """The catalogue entry of ``name``; raises ``InputError`` listing the names if unknown."""
    try:
        return CATALOGUE[name]
    except KeyError:
        hint = did_you_mean(name, CATALOGUE)
        raise InputError(
            f"unknown robot {name!r}: {hint}pass a path to a URDF file or one of "
            f"{listing(CATALOGUE)}"
        ) from None


@cache
def _armik_robot_dir() -> Path:
    package = Path(__file__).resolve().parents[1]  # armik/, this file is armik/model/...
    installed = package / "robots"
    if installed.is_dir():
        return installed
    # Editable install: the package lives in src/armik, the URDFs in robots/ at the top.
    return package.parents[1] / "robots"


@cache
def _erd_robot_dir() -> Path:
    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        raise InputError(
            "the example-robot-data package is not installed: pip install example-robot-data"
        ) from None
    return Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))


def erd_share() -> str | None:
    """The share folder of example-robot-data (its meshes' ``package://`` root), or None
    when it is not installed."""
    try:
        return str(_erd_robot_dir().parents[1])
    except InputError:
        return None
