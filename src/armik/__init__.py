"""armik: inverse kinematics for URDF robot arms on Pinocchio.

``import armik`` loads nothing else: each public name imports its module at its first use
(``armik.load`` the facade and the solvers, ``armik.view`` the viewer), so that a script,
the CLI or a test pays for what it uses. numba and its cache rule (``compiled_cache``) come
with ``armik.kernel``, which every package holding compiled code imports first.
"""

from __future__ import annotations

import copyreg as _copyreg
import sys as _sys
import types as _types
from typing import TYPE_CHECKING
from typing import Any as _Any  # private: the package namespace is its API

if TYPE_CHECKING:  # what the names below are, for type checkers; imported at first use
    from armik import collision, view
    from armik.arm import Arm
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
    from armik.loading import load, load_string
    from armik.model.catalogue import robots
    from armik.precompile import compile
    from armik.problem import Axis, LookAt, Pose, Position, Posture, Relative
    from armik.problem.budget import Budget
    from armik.result import IKResult
    from armik.solutions import Solutions
    from armik.solvers import solvers
    from armik.status import Status
    from armik.targets.pose import Target, parse_target
    from armik.view.plot import plot
    from armik.view.viewer import Viewer

__version__ = "0.1.0"

# Each public name: (the module holding it, its name there; None: the module itself).
_WHERE: dict[str, tuple[str, str | None]] = {
    "collision": ("armik.collision", None),
    "view": ("armik.view", None),  # the package, callable: ``armik.view(arm)``
    "Arm": ("armik.arm", "Arm"),
    **{n: ("armik.loading", n) for n in ("load", "load_string")},
    "Arms": ("armik.arms", "Arms"),
    "BatchResult": ("armik.batch_result", "BatchResult"),
    "Collisions": ("armik.constraints.clear", "Collisions"),
    "Hold": ("armik.constraints.hold", "Hold"),
    **{
        n: ("armik.constraints.shapes", n)
        for n in ("Box", "Capsule", "Cylinder", "HalfSpace", "Mesh", "Sphere")
    },
    **{
        n: ("armik.errors", n)
        for n in (
            "ArmikError",
            "ArmikWarning",
            "CollisionError",
            "FrameError",
            "InputError",
            "JointError",
            "OptionError",
            "SolverError",
            "TargetError",
            "URDFError",
            "ViewerError",
        )
    },
    "export": ("armik.export", "export"),
    "robots": ("armik.model.catalogue", "robots"),
    "compile": ("armik.precompile", "compile"),
    **{
        n: ("armik.problem", n)
        for n in ("Axis", "LookAt", "Pose", "Position", "Posture", "Relative")
    },
    "Budget": ("armik.problem.budget", "Budget"),
    "IKResult": ("armik.result", "IKResult"),
    "Solutions": ("armik.solutions", "Solutions"),
    "solvers": ("armik.solvers", "solvers"),
    "Status": ("armik.status", "Status"),
    **{n: ("armik.targets.pose", n) for n in ("Target", "parse_target")},
    "plot": ("armik.view.plot", "plot"),
    "Viewer": ("armik.view.viewer", "Viewer"),
}
# Subpackages whose public name is a function of theirs: importing ``armik.solvers`` (or any
# module in it) would set the package as this package's attribute ``solvers``.
_FUNCTIONS_OF = ("solvers", "export")


def __getattr__(name: str) -> _Any:  # a module, a function or a class, at its first use
    if name not in _WHERE:
        raise AttributeError(f"module 'armik' has no attribute {name!r}")
    import importlib

    module, attr = _WHERE[name]
    value = importlib.import_module(module)
    if attr is not None:
        value = getattr(value, attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The public names and the module's own dunders (``__version__``, ``__doc__``): not
    this file's imports (``TYPE_CHECKING``, ``annotations``), its private names, nor the
    subpackages an import sets as attributes (``armik.model``)."""
    own = (n for n in globals() if n.startswith("__") and n.endswith("__"))
    return sorted({*own, *_WHERE})


class _Package(_types.ModuleType):
    def __setattr__(self, name: str, value: _Any) -> None:
        # the import system sets a subpackage as its parent's attribute; ``armik.solvers``
        # and ``armik.export`` stay the functions (resolved by ``__getattr__``)
        if name in _FUNCTIONS_OF and isinstance(value, _types.ModuleType):
            return
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package


def _by_name(module: _types.ModuleType) -> tuple[_Any, tuple[str]]:
    """The package pickled as its name, imported again where it is read."""
    import importlib

    return importlib.import_module, (module.__name__,)


# a pickler handles the package, of its own class, as no module: a user's function of a
# script (a constraint, a ``prefer=`` cost), pickled by value with the ``armik`` its code
# reads, travels to a process pool or a Dask worker by the package's name
_copyreg.pickle(_Package, _by_name)

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
