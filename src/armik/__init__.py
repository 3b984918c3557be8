"""armik: inverse kinematics for URDF robot arms on Pinocchio."""

from .arm import Arm, load
from .batch import BatchResult
from .errors import (
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
from .ik import solvers
from .result import IKResult
from .robots import robots
from .status import Status
from .targets import Target, parse_target

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
    "URDFError",
    "load",
    "parse_target",
    "robots",
    "solvers",
]
