"""A 6R family's Python side, the same for every family solved in one compiled kernel
(the closed forms and the one-dimensional searches): ``applies``, ``run``, ``run_batch``,
``prepare_pose`` and its registration.

Each family keeps its own compiled ``kernel``, ``solve_into``, ``solve_all_into`` and
``kernel_many``: numba
caches no function that receives another as an argument, so the entries cannot be shared,
only the Python around them. The kernels take the same arguments: ``kernel(h, p, R_tip0,
R, pos, q0, lower, upper, variant, labelled, out)`` (``variant``: the flat chain's variant,
``sixr.flat``; a family with one layout ignores it).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers
from armik.solvers.closed_form import sixr, sixr_answers
from armik.solvers.closed_form.subproblems import mat, vec
from armik.solvers.registry import SolverSpec, register
from armik.targets.pose import Target


class Family:
    """One family: its name (``sixr.flat``'s key), classifier, the text of its claims, its
    compiled kernel and entries, and the most rows (solutions) its kernel writes."""

    def __init__(
        self,
        family: str,
        classify: Callable,
        closed_form: str,
        kernel: Callable,
        solve_into: Callable,
        kernel_many: Callable,
        rows: int = 8,
        solve_all_into: Callable | None = None,
    ) -> None:
        self.family, self.classify, self.closed_form = family, classify, closed_form
        self.kernel, self.solve_into, self.kernel_many = kernel, solve_into, kernel_many
        self.rows = rows
        self.solve_all_into = solve_all_into  # every row solved, measured and judged

    def applies(
        self, arm: ArmModel, target: Target | None = None, _opts: object = None
    ) -> str | None:
        return sixr.applies(arm, target, self.family, self.classify)

    def run(
        self,
        arm: ArmModel,
        target: Target,
        q0: np.ndarray,
        opts: SolverSettings,
        all_solutions: bool,
    ) -> Answers:
        chain = sixr.flat(arm, self.family, self.classify)
        h, p, R_tip0, lower, upper, variant = sixr.unflatten.py_func(chain)
        R, pos = sixr.pose_arrays(target)
        out = np.empty((self.rows, 11))
        # every row, labelled: ``solve``'s verdict takes the first that Pinocchio verifies
        n, _ = self.kernel(
            h, p, R_tip0, mat(R), vec(pos), q0, lower, upper, np.int64(variant),
            np.int64(self.rows), out,
        )  # fmt: skip
        beyond = sixr_answers.beyond_reach(arm, pos)
        limits = (arm.lower, arm.upper)  # an unreached row's closest q within them
        return sixr_answers.of_rows(out[:n], self.family, self.closed_form, beyond, limits)

    def run_batch(
        self, arm: ArmModel, targets, q0: np.ndarray, opts: SolverSettings, seeds=None
    ) -> Answers:
        """Every target in one compiled call (GIL released), the ``SolverSpec.run_batch``
        shape; ``seeds`` is unused (no restarts). ``solve_batch`` solves the rows that fail
        again through ``run``, so that they carry its per-target reasons."""
        chain = sixr.flat(arm, self.family, self.classify)
        return sixr_answers.batch(arm, targets, q0, self.kernel_many, chain)

    def prepare_pose(self, arm: ArmModel, opts: SolverSettings, position_only: bool):
        # position_only is always False: ``applies`` refuses position targets
        return sixr_answers.pose_runner(
            arm, self.family, self.classify, self.solve_into, self.closed_form, self.rows,
            self.solve_all_into,
        )  # fmt: skip

    def register(self, name: str, priority: int, summary: str, complete: bool = True) -> SolverSpec:
        """Register the family as solver ``name`` (``complete``: see ``SolverSpec``)."""
        return register(
            SolverSpec(
                name=name,
                kind="analytic",
                enforces_limits=True,
                priority=priority,
                why_not=self.applies,
                solves=frozenset(),
                run=self.run,
                summary=summary,
                run_batch=self.run_batch,
                prepare_pose=self.prepare_pose,
                complete=complete,
            )
        )
