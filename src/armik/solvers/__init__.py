"""Solvers: the registry, the claims between solver and verdict, the numeric solvers and the
closed forms. Importing this package registers every built-in solver."""

from armik.solvers.closed_form import (  # noqa: F401  (registration)
    elimination_6r,
    general_6r,
    planar2r,
    spherical_general,
    spherical_shoulder,
    spherical_wrist,
    spin,
    spin_joint,
    srs,
    swept_7r,
    three_parallel,
    three_parallel_general,
    two_intersecting,
    two_parallel,
)
from armik.solvers.numeric import clik, dls, qp  # noqa: F401  (registration)
from armik.solvers.registry import (
    SolverSpec,
    choose,
    get,
    register,
    solvers,
    unregister,
    why_not,
)

__all__ = ["SolverSpec", "choose", "get", "register", "solvers", "unregister", "why_not"]
