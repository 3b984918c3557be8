"""armik: inverse kinematics for URDF robot arms on Pinocchio."""

from armik.arm import Arm, load, load_string
from armik.batch_result import BatchResult
from armik.errors import (
    ArmikError,
    ArmikWarning,
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
    "FrameError",
    "IKResult",
    "InputError",
    "JointError",
    "OptionError",
    "SolverError",
    "Status",
    "Target",
    "TargetError",
    "compile",
    "URDFError",
    "load",
    "load_string",
    "parse_target",
    "robots",
    "solvers",
]
