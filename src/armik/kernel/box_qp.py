"""The QP backend behind the kernel's box-QP step, for the rare step its active set misses.

Called from compiled code through ``numba.objmode`` (which takes the GIL back for the call).
``box_problem`` is the one place the step's QP is written as a ``qpsolvers.Problem``.
"""

from __future__ import annotations

import functools
from importlib.metadata import version

import numpy as np

# qpsolvers (with scipy.sparse) is imported at the first use, not with armik: it costs a
# process 0.15 s, and most solves never reach a QP backend.


@functools.cache
def backends() -> tuple[str, ...]:
    """The QP backends qpsolvers finds installed, in its order (the kernel's codes)."""
    import qpsolvers

    return tuple(qpsolvers.available_solvers)


def _release(package: str) -> tuple[int, ...]:
    return tuple(int(x) for x in version(package).split(".")[:2] if x.isdigit())


@functools.cache
def backend_options(name: str) -> dict:
    """The settings armik gives backend ``name``."""
    if name != "osqp":
        return {}
    # Settings of osqp 1.x, which warns at the 0.6 names and, unless told whether a failure
    # raises, at every solve (the answer is checked here: it must not raise); qpsolvers
    # passes raise_error on from 4.13.
    if _release("osqp") < (1, 0):
        return {"eps_abs": 1e-9, "eps_rel": 1e-9, "polish": False, "verbose": False}
    opts = {"eps_abs": 1e-9, "eps_rel": 1e-9, "polishing": False, "verbose": False}
    if _release("qpsolvers") >= (4, 13):
        opts["raise_error"] = False
    return opts


def code(name: str) -> int:
    """The index the kernel uses for backend ``name`` (which must be installed)."""
    return backends().index(name)


def box_problem(H: np.ndarray, g: np.ndarray, lb: np.ndarray, ub: np.ndarray):
    """minimise 1/2 x^T H x - g^T x subject to lb <= x <= ub (sparse H, as osqp wants)."""
    import qpsolvers
    from scipy import sparse

    return qpsolvers.Problem(sparse.csc_matrix(H), -g, lb=lb, ub=ub)


def solve_box_qp(H: np.ndarray, g: np.ndarray, lb: np.ndarray, ub: np.ndarray, which: int):
    """The backend's solution, or NaNs when it finds none."""
    import qpsolvers

    name = backends()[which]
    sol = qpsolvers.solve_problem(box_problem(H, g, lb, ub), solver=name, **backend_options(name))
    if sol.found and sol.x is not None:
        return np.asarray(sol.x, dtype=np.float64)
    return np.full(H.shape[0], np.nan)
