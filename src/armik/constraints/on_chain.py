"""One chain's constraint on a robot of several tips (``Arms``, ``constraints={tip: [c]}``),
where the chains are solved together in one model (``armik.model.union``): its box and its
check read that chain's joints of each answer, with the chain's own model, as on the chain
alone; a failure names the tip."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from armik.constraints.base import Check, Constraint

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


class OnChain(Constraint):
    """``inner``, a constraint of the chain ``chain`` (tip ``tip``), over a model whose
    joints ``columns`` are the chain's, in the chain's order."""

    def __init__(self, inner: Constraint, tip: str, chain: ArmModel, columns: np.ndarray):
        self.inner, self.tip, self.chain = inner, tip, chain
        self.columns = np.asarray(columns, dtype=np.intp)
        self.pose_only = inner.pose_only

    def __repr__(self) -> str:
        return f"OnChain({self.inner!r}, tip={self.tip!r})"

    def at(self, arm: ArmModel, seed: np.ndarray) -> Constraint:
        bound = self.inner.at(self.chain, np.asarray(seed)[self.columns])
        return self if bound is self.inner else OnChain(bound, self.tip, self.chain, self.columns)

    def box(self, arm: ArmModel) -> tuple[np.ndarray, np.ndarray] | None:
        own = self.inner.box(self.chain)
        if own is None:
            return None
        lower, upper = np.full(arm.dof, -np.inf), np.full(arm.dof, np.inf)
        lower[self.columns], upper[self.columns] = own
        return lower, upper

    def check(self, arm: ArmModel, Q: np.ndarray) -> Check:
        got = self.inner.check(self.chain, np.asarray(Q)[:, self.columns])
        tip, why = self.tip, got.why
        return got._replace(why=lambda i: f"{tip}: {why(i)}")
