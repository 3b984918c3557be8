"""IK solvers, one per file. Importing this package registers every built-in solver."""

from . import clik, dls, planar2r, qp, spherical, swept, three_parallel  # noqa: F401  (registration)
from .registry import SolverSpec, choose, get, register, solvers, why_not

__all__ = ["SolverSpec", "choose", "get", "register", "solvers", "why_not"]
