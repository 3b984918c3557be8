"""``SolverSettings``: what a solver reads of a request, and nothing the stages around it read.

A solver's ``run``, ``run_batch`` and ``prepare_pose`` are typed against this record: the
verification tolerances, the budget and seed of a search, the target's form beyond an exact
pose (position only, weights, bounds; a cone is the target's own ``aim``), the numeric
solvers' tuning and a user's own constraints, which the verdict checks. What only the
stages read (obstacles, held joints, the swivel angle, the collision slide) is on
``armik.options.Options``, which extends this record; so mypy refuses a solver that reads
a stage's field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from armik.constraints.base import Constraint
from armik.errors import OptionError
from armik.frozen import frozen
from armik.problem.budget import DEFAULT as DEFAULT_BUDGET
from armik.problem.budget import Budget


@dataclass(frozen=True, eq=False)
class SolverSettings:
    """What a solver and the verdict on its answers read of a request (units: m, rad, s):
    the tolerances, the budget, the seed, the target's form, the numeric solvers' tuning and
    a user's own constraints. ``armik.options.Options`` adds what the stages around a solver
    read (collisions, held joints, the swivel); a solver is typed against this part only.

    - ``tol_position``, ``tol_orientation``: verification tolerances (1e-6 m, 1e-6 rad),
      at least ``tolerances.MIN_TOLERANCE`` (1e-12).
    - ``timeout``: budget of a numeric solve, restarts included, in CPU time of the thread
      that solves (0.05 s): other threads' work does not count, so the same seeded call
      gives the same answer whether one thread or eight are solving (up to the thread's
      own timing noise). Checked every 16 iterations and between attempts.
    - ``iteration_budget``: a deterministic budget instead: at most this many iterations
      per solve, restarts included (None: off). When given, ``timeout`` is not used, and
      the same seeded call gives the same answer on every machine.
    - ``max_restarts``: random restarts after the first attempt (1000; 0 disables).
    - ``max_iterations``: iterations per attempt of a numeric solver (100).
    - ``seed``: random seed of the restarts (0), so the same call gives the same answer.
    - ``position_only``: ignore the target's orientation.
    - ``weights``: 6 non-negative weights on (x, y, z, rx, ry, rz) of the error expressed
      in the tip frame; a zero weight frees that axis (e.g. rotation about the tool axis).
      With ``bounds``, the weights act on the error in the target frame, as the bounds do.
    - ``bounds``: a region around the target, with TRAC-IK's meaning: the error twist of
      the reached tip pose relative to the target, in the target frame (position
      ``R_t^T (p - p_t)`` m, rotation ``log3(R_t^T R)`` rad), each component within +- its
      bound (bx, by, bz, brx, bry, brz); ``math.inf`` frees an axis. A success lies within
      the bounds (plus the tolerances); its errors are its distance outside them.
    - A cone around a tip axis (``cone=``, ``look_at=``, ``toward=``) is the target's, not
      a setting: its ``aim`` (``armik.targets.aim``), which the solver reads from the target.
    - ``qp_solver``: the qpsolvers backend of the ``qp`` solver ("osqp").
    - ``nullspace_gain``: pull toward q0 in the null space of redundant arms (1.0; 0 disables).
    - ``max_solutions``: cap on ``solve_all`` answers of numeric solvers (16).
    - ``posture``: (q_ref, weights): the null-space pull goes toward ``q_ref``, each joint's
      share by its weight, instead of toward q0 (what ``secondary=[armik.Posture(q_ref,
      weights)]`` spells; say it that way). ``dls`` and ``qp`` follow it where the task
      leaves joints free; a closed form returns its answers nearest q0 as ever.
    - ``budget``: ``timeout``, ``iteration_budget``, ``max_restarts`` and ``max_iterations``
      as one object (``armik.Budget``), spelled here as those options (``Options.budget``
      gives it back).
    - ``checks``: the constraints no option spells, as objects: the verdict of every route
      applies their ``check`` to every answer, so that none that violates one is a
      success (``armik.verify.verdict``); the task solver also steps within their boxes.
    """

    tol_position: float = 1e-6
    tol_orientation: float = 1e-6
    timeout: float = DEFAULT_BUDGET.timeout  # type: ignore[assignment]
    max_restarts: int = DEFAULT_BUDGET.restarts  # type: ignore[assignment]
    max_iterations: int = DEFAULT_BUDGET.per_attempt  # type: ignore[assignment]
    seed: int | None = 0
    position_only: bool = False
    weights: tuple[float, ...] | None = None
    bounds: tuple[float, ...] | None = None
    qp_solver: str = "osqp"
    nullspace_gain: float = 1.0
    max_solutions: int = 16
    iteration_budget: int | None = None
    posture: tuple[tuple[float, ...], tuple[float, ...]] | None = None
    checks: tuple[Constraint, ...] = ()

    # Equal by class and every field, a subclass's too (``Options``): written here rather
    # than generated per class, so that the registry, which keeps its choices per settings,
    # hashes them through this module.
    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self.__dict__ == other.__dict__

    def __hash__(self) -> int:  # every copy keeps the fields' order (``frozen`` over __dict__)
        return hash(tuple(self.__dict__.values()))

    @property
    def budget(self) -> Budget:
        """The budget these options spell, every field filled (``armik.problem.budget``)."""
        return frozen(
            Budget,
            timeout=self.timeout,
            iterations=self.iteration_budget,
            restarts=self.max_restarts,
            per_attempt=self.max_iterations,
        )

    def forms(self, aimed: bool = False) -> frozenset[str]:
        """What these options ask beyond an exact pose, with a target that has an aim or not
        (``aimed``: a cone, ``Target.aim``), as a solver declares what it solves
        (``registry.FORMS``; "spin": bounds that free one rotation component only)."""
        found = []
        if self.position_only:
            found.append("position_only")
        if self.weights is not None:
            found.append("weights")
        if aimed:
            found.append("cone")
        if self.bounds is not None:
            found.append("spin" if not aimed and spin_of(self.bounds) else "bounds")
        return frozenset(found)

    @property
    def region_bounds(self) -> tuple[float, ...]:
        """The bounds of the region (a cone alone: the position exact; the rotation
        components are the cone's to measure then). The target has a region where it has
        bounds or an aim (``opts.bounds is not None or target.aim is not None``)."""
        return self.bounds if self.bounds is not None else (0.0,) * 6

    def weight_vector(self, position_only_target: bool) -> np.ndarray:
        """The 6 weights of the task; raises ``OptionError`` when they leave no axis to
        measure (zero position weights on a position target or with ``position_only``):
        every answer would then pass the check."""
        w = np.ones(6) if self.weights is None else np.array(self.weights)
        if self.position_only or position_only_target:
            w[3:] = 0.0
            if not w[:3].any():
                why = "position_only=True" if self.position_only else "a position target"
                raise OptionError(
                    f"weights {self.weights} with {why} leave nothing to measure (the "
                    "orientation is ignored and every position weight is 0): give x, y or z "
                    "a positive weight",
                    option="weights",
                    value=self.weights,
                )
        return w

    def left_free(self, position_target: bool, aimed: bool) -> tuple[bool, bool]:
        """(position, rotation): whether weights of 0 and infinite bounds leave every
        component of each free, its error 0 whatever the answer: a result's words leave it
        out, where a "0" would read as reached (a look-at, ``weights=(0, 0, 0, 1, 1, 1)``).
        An aim (``aimed``) measures the rotation: the tip's axis in its cone."""
        if self.weights is None and self.bounds is None:
            return (False, False)
        w = self.weight_vector(position_target)
        if self.bounds is not None:
            w = w * np.isfinite(np.array(self.bounds, dtype=float))
        return (not w[:3].any(), not aimed and not w[3:].any())


def spin_of(bounds: tuple[float, ...] | None) -> tuple[int, float] | None:
    """(k, half-width): the one rotation component of the target frame the bounds free
    (rad, at most pi), the others and the position held exactly; else None."""
    if bounds is None:
        return None
    b = [float(x) for x in bounds]  # plain floats: this runs on every spin solve
    free = [k for k in range(3) if b[3 + k] != 0.0]
    if any(x != 0.0 for x in b[:3]) or len(free) != 1:
        return None
    k = free[0]
    return k, min(b[3 + k], math.pi)
