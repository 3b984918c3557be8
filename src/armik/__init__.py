"""armik: inverse kinematics for URDF robot arms on Pinocchio."""

from typing import Any as _Any  # private: the package namespace is its API

# first: numba picks the cache of a compiled function when it is decorated
from armik import compiled_cache as _compiled_cache  # noqa: F401  # isort: skip
from armik import collision
from armik.arm import Arm, load, load_string
from armik.arms import Arms
from armik.batch_result import BatchResult
from armik.constraints.clear import Collisions
from armik.constraints.hold import Hold
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
    ViewerError,
)
from armik.export import export
from armik.model.catalogue import robots
from armik.precompile import compile
from armik.problem import Axis, LookAt, Pose, Position, Posture, Relative
from armik.problem.budget import Budget
from armik.result import IKResult
from armik.solutions import Solutions
from armik.solvers import solvers
from armik.status import Status
from armik.targets.pose import Target, parse_target

__version__ = "0.1.0"

# The viewer and plots load on first use, so that ``import armik`` imports neither viser
# nor matplotlib: ``armik.view`` (the package, callable: ``armik.view(arm)``),
# ``armik.plot`` and ``armik.Viewer``.
_LAZY = {"view": ("armik.view", None), "plot": ("armik.view.plot", "plot"),
         "Viewer": ("armik.view.viewer", "Viewer")}  # fmt: skip


def __getattr__(name: str) -> _Any:  # a module, a function or a class
    if name not in _LAZY:
        raise AttributeError(f"module 'armik' has no attribute {name!r}")
    import importlib

    module, attr = _LAZY[name]
    value = importlib.import_module(module)
    value = globals()[name] = value if attr is None else getattr(value, attr)
    return value


__all__ = [
    "Arms",
    "Axis",
    "LookAt",
    "Pose",
    "Position",
    "Posture",
    "Relative",
    "Arm",
    "BatchResult",
    "ArmikError",
    "ArmikWarning",
    "Box",
    "Capsule",
    "Collisions",
    "CollisionError",
    "Cylinder",
    "FrameError",
    "HalfSpace",
    "Hold",
    "Budget",
    "IKResult",
    "InputError",
    "JointError",
    "Mesh",
    "OptionError",
    "Solutions",
    "SolverError",
    "Sphere",
    "Status",
    "Target",
    "TargetError",
    "collision",
    "compile",
    "export",
    "URDFError",
    "Viewer",
    "ViewerError",
    "load",
    "load_string",
    "parse_target",
    "plot",
    "robots",
    "solvers",
    "view",
]
