"""Several tips of one robot at once: ``armik.load(source, tips=[...])``.

Each tip's chain from the common base is an ``Arm`` of its own, solved by its own best
solver (a closed form where one applies), and verified by Pinocchio's FK as every answer
is; the robot's configuration is the chains' joints side by side, in the order of
``tips``. Chains that share a moving joint (a torso, a lift) are refused for now, naming
the joints and the way round (hold them with ``locked=``): solving over a shared joint
needs the union of the chains in one model, the next step of docs/problem-model.md.

A result is one ``IKResult`` for the whole robot: ``q`` over every joint, ``success`` when
every tip's answer is one, the worst tip's status and errors, a reason naming each tip
that failed, and per tip in ``extra``: ``"errors"`` (tip -> (position m, orientation
rad)) and ``"results"`` (tip -> that chain's ``IKResult``).
"""

from __future__ import annotations

import time
from collections.abc import Mapping

import numpy as np

from armik.errors import FrameError, OptionError
from armik.result import IKResult
from armik.status import Status


class Arms:
    """The chains of ``tips`` of one robot, each an ``Arm`` (``chain(tip)``)."""

    def __init__(self, chains: Mapping[str, object]) -> None:
        names = [j for arm in chains.values() for j in arm.joint_names]  # type: ignore[attr-defined]
        shared = sorted({n for n in names if names.count(n) > 1})
        if shared:
            raise OptionError(
                f"the chains of {list(chains)} share the joints {shared}: several tips with a "
                "shared joint are not solved yet; hold those joints with locked={...} to solve "
                "the chains on their own",
                option="tips",
                value=list(chains),
            )
        self._chains = dict(chains)
        self.tips: tuple[str, ...] = tuple(chains)
        self.joint_names: tuple[str, ...] = tuple(names)
        self.dof = len(names)
        self._slices, start = {}, 0
        for tip, arm in self._chains.items():
            self._slices[tip] = slice(start, start + arm.dof)  # type: ignore[attr-defined]
            start += arm.dof  # type: ignore[attr-defined]
        self.lower = np.concatenate([a.lower for a in self._chains.values()])  # type: ignore[attr-defined]
        self.upper = np.concatenate([a.upper for a in self._chains.values()])  # type: ignore[attr-defined]
        self.middle = np.concatenate([a.middle for a in self._chains.values()])  # type: ignore[attr-defined]

    def __repr__(self) -> str:
        return f"Arms(tips={list(self.tips)}, dof={self.dof})"

    def chain(self, tip: str):
        """The ``Arm`` from the base to ``tip``."""
        if tip not in self._chains:
            raise FrameError(
                f"unknown tip {tip!r}; this robot's tips: {list(self.tips)}",
                frame=tip,
                candidates=self.tips,
            )
        return self._chains[tip]

    def split(self, q: object) -> dict[str, np.ndarray]:
        """``q`` (one value per joint of ``joint_names``) as each chain's joint values."""
        arr = np.asarray(q, dtype=float).reshape(-1)
        if arr.shape != (self.dof,):
            raise OptionError(
                f"q must hold {self.dof} values, one per joint of {list(self.joint_names)}, "
                f"got {arr.size}",
                option="q",
                value=q,
            )
        return {tip: arr[s] for tip, s in self._slices.items()}

    def fk(self, q: object, frame: str | None = None):
        """``T_base_frame`` of a tip (default: the first) at ``q``."""
        tip = self.tips[0] if frame is None else frame
        return self.chain(tip).fk(self.split(q)[tip])

    def jacobian(self, q: object, frame: str | None = None) -> np.ndarray:
        """A tip's 6 x dof LOCAL Jacobian over every joint (zero for other chains')."""
        tip = self.tips[0] if frame is None else frame
        J = np.zeros((6, self.dof))
        J[:, self._slices[tip]] = self.chain(tip).jacobian(self.split(q)[tip])
        return J

    def random_q(self, rng: np.random.Generator | int | None = None) -> np.ndarray:
        rng = np.random.default_rng(rng)
        return np.concatenate([a.random_q(rng) for a in self._chains.values()])  # type: ignore[attr-defined]

    def solve(self, targets: Mapping[str, object], *, q0: object = None, **options) -> IKResult:
        """Every tip at its target (any target form ``Arm.solve`` takes, or a task list),
        each chain by its own solver; one ``IKResult`` for the robot (module docstring)."""
        t0 = time.perf_counter()
        self._check_targets(targets)
        seeds = self.split(self.middle if q0 is None else q0)
        results = {
            tip: self._chains[tip].solve(target, q0=seeds[tip], **options)  # type: ignore[attr-defined]
            for tip, target in targets.items()
        }
        return _joined(self, results, seeds, time.perf_counter() - t0)

    def _check_targets(self, targets: object) -> None:
        if not isinstance(targets, Mapping) or not targets:
            raise OptionError(
                f"targets must map tip names {list(self.tips)} to targets, got {targets!r}",
                option="targets",
                value=targets,
            )
        unknown = [t for t in targets if t not in self._chains]
        if unknown:
            raise FrameError(
                f"unknown tips {unknown}; this robot's tips: {list(self.tips)}",
                frame=str(unknown[0]),
                candidates=self.tips,
            )


def _joined(arms: Arms, results: dict[str, IKResult], seeds, elapsed: float) -> IKResult:
    # one loop over the tips: this runs on every solve of a cell
    parts, solvers, failed, errors = [], {}, [], {}
    iterations = restarts = 0
    position, orientation, singular = 0.0, None, False
    for tip in arms.tips:
        r = results.get(tip)
        if r is None:
            parts.append(seeds[tip])
            continue
        parts.append(r.q)
        solvers[r.solver] = None
        if not r.success:
            failed.append(tip)
        errors[tip] = (r.position_error, r.orientation_error)
        iterations += r.iterations
        restarts += r.restarts
        position = max(position, r.position_error)
        if r.orientation_error is not None:
            orientation = max(orientation or 0.0, r.orientation_error)
        singular = singular or r.singular
    if failed:
        status = results[failed[0]].status
        reason = "; ".join(f"{t}: {results[t].status.value}: {results[t].reason}" for t in failed)
    else:
        status = Status.CONVERGED
        reason = "every tip verified: " + "; ".join(
            f"{t} by {r.solver}" for t, r in results.items()
        )
    row = {
        "q": np.concatenate(parts),
        "success": not failed,
        "status": status,
        "reason": reason,
        "solver": "+".join(solvers),
        "iterations": iterations,
        "position_error": position,
        "orientation_error": orientation,
        "time": elapsed,
        "branch": None,
        "singular": singular,
        "restarts": restarts,
    }
    joined = IKResult._checked(row)  # every field, status a Status: the fast constructor
    object.__setattr__(joined, "extra", {"errors": errors, "results": results})
    return joined
