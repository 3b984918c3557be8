"""armik: inverse kinematics for URDF robot arms on Pinocchio."""

from armik import collision
from armik.arm import Arm, load, load_string
from armik.batch_result import BatchResult
from armik.constraints.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere
from armik.errors import (
    ArmikError,
    ArmikWarning,
    CollisionError,
    FrameError,
    InputError,
    JointError,
    OptionError,
    SolverError,
    TargetError,
    URDFError,
)
from armik.model.catalogue import robots
from armik.precompile import compile
from armik.result import IKResult
from armik.solvers import solvers
from armik.status import Status
from armik.targets.pose import Target, parse_target

__version__ = "0.1.0"

__all__ = [
    "Arm",
    "BatchResult",
    "ArmikError",
    "ArmikWarning",
    "Box",
    "Capsule",
    "CollisionError",
    "Cylinder",
    "FrameError",
    "HalfSpace",
    "IKResult",
    "InputError",
    "JointError",
    "Mesh",
    "OptionError",
    "SolverError",
    "Sphere",
    "Status",
    "Target",
    "TargetError",
    "collision",
    "compile",
    "URDFError",
    "load",
    "load_string",
    "parse_target",
    "robots",
    "solvers",
]
