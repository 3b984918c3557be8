"""One chain's constraint on a robot of several tips (``Arms``, ``constraints={tip: [c]}``),
where the chains are solved together in one model (``armik.model.union``): its box and its
check read that chain's joints of each answer, with the chain's own model (the union's
``chain_of`` the tip: no model travels with the constraint to a worker), as on the chain
alone; a failure names the tip."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from armik.constraints.base import Check, Constraint

if TYPE_CHECKING:
    from armik.model.union import Union


class OnChain(Constraint):
    """``inner``, a constraint of the chain to ``tip``, over a union of chains (``Union``)
    whose joints ``columns`` are the chain's, in the chain's order."""

    def __init__(self, inner: Constraint, tip: str, columns: np.ndarray):
        self.inner, self.tip = inner, tip
        self.columns = np.asarray(columns, dtype=np.intp)
        self.pose_only = inner.pose_only

    def __repr__(self) -> str:
        return f"OnChain({self.inner!r}, tip={self.tip!r})"

    def at(self, arm: Union, seed: np.ndarray) -> Constraint:  # type: ignore[override]
        bound = self.inner.at(arm.chain_of(self.tip), np.asarray(seed)[self.columns])
        return self if bound is self.inner else OnChain(bound, self.tip, self.columns)

    def box(self, arm: Union) -> tuple[np.ndarray, np.ndarray] | None:  # type: ignore[override]
        own = self.inner.box(arm.chain_of(self.tip))
        if own is None:
            return None
        lower, upper = np.full(arm.dof, -np.inf), np.full(arm.dof, np.inf)
        lower[self.columns], upper[self.columns] = own
        return lower, upper

    def check(self, arm: Union, Q: np.ndarray) -> Check:  # type: ignore[override]
        got = self.inner.check(arm.chain_of(self.tip), np.asarray(Q)[:, self.columns])
        tip, why = self.tip, got.why
        return got._replace(why=lambda i: f"{tip}: {why(i)}")
