"""What every solver hands back before verification: ``Answers``, N candidate answers as
arrays, one row each, from the kernels up to the verdict (``armik.verify.verdict``), which
turns them into results.

A row is a joint configuration with the solver's own claim about it (a ``Status`` code;
verification decides), its iterations and restarts, and where the solver has them a branch
label, a singular flag and the solver's words for its claim. A batch's rows carry no words:
the verdict writes its failures' from their claims. The prepared fast path's claimed answer
is the one-row case kept on plain floats (``armik.solvers.claims.Claim``), made an
``Answers`` only when the general verdict needs it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from armik.frozen import frozen
from armik.status import Status

_CONVERGED = Status.CONVERGED.code
_CODE = {s: s.code for s in Status}  # a lookup per row, not a property call


@dataclass(frozen=True, kw_only=True)
class Answers:
    """N candidate answers (rows), before verification."""

    q: np.ndarray  # (N, dof) joint values, rad or m
    claim: np.ndarray  # (N,) int8: each row's Status code, the solver's own
    iterations: np.ndarray  # (N,) int64
    restarts: np.ndarray  # (N,) int64
    branch: tuple[str | None, ...] | None = None  # each row's label; None: no labels
    singular: np.ndarray | None = None  # (N,) bool; None: no row singular
    reasons: tuple[str, ...] | None = None  # the solver's words; None: the verdict's

    def __len__(self) -> int:
        return int(self.claim.shape[0])

    def status(self, i: int) -> Status:
        """Row i's claim."""
        return Status.from_code(int(self.claim[i]))

    def claimed(self, i: int) -> bool:
        """Whether row i is claimed converged."""
        return bool(self.claim[i] == _CONVERGED)

    def label(self, i: int) -> str | None:
        return None if self.branch is None else self.branch[i]

    def is_singular(self, i: int) -> bool:
        return False if self.singular is None else bool(self.singular[i])

    def reason(self, i: int) -> str:
        """The solver's words for row i's claim ("" where it gave none: a batch)."""
        return "" if self.reasons is None else self.reasons[i]

    def take(self, rows: Sequence[int]) -> Answers:
        """These rows, in this order."""
        index = list(rows)
        if len(index) == 1:  # one row: views of the columns (a verdict's usual case)
            i = index[0]
            if i < 0:
                i += len(self)
            one = slice(i, i + 1)
            return frozen(
                Answers,
                q=self.q[one],
                claim=self.claim[one],
                iterations=self.iterations[one],
                restarts=self.restarts[one],
                branch=None if self.branch is None else (self.branch[i],),
                singular=None if self.singular is None else self.singular[one],
                reasons=None if self.reasons is None else (self.reasons[i],),
            )
        return Answers(
            q=self.q[index],
            claim=self.claim[index],
            iterations=self.iterations[index],
            restarts=self.restarts[index],
            branch=None if self.branch is None else tuple([self.branch[k] for k in index]),
            singular=None if self.singular is None else self.singular[index],
            reasons=None if self.reasons is None else tuple([self.reasons[k] for k in index]),
        )

    def reworded(self, reasons: Sequence[str]) -> Answers:
        """The same rows in other words (a search's miss named by what ran next)."""
        return replace(self, reasons=tuple(reasons))

    @classmethod
    def of(
        cls,
        q: Sequence[np.ndarray] | np.ndarray,
        claims: Sequence[Status],
        reasons: Sequence[str],
        dof: int,
        *,
        iterations: Sequence[int] | None = None,
        restarts: Sequence[int] | None = None,
        branch: Sequence[str | None] | None = None,
        singular: Sequence[bool] | None = None,
    ) -> Answers:
        """Rows from per-row sequences: q (rows, or an (N, dof) array), claims (each a
        ``Status``) and reasons; iterations and restarts 0, no labels and no row singular
        where not given."""
        n = len(claims)
        zeros = np.zeros(n, dtype=np.int64)
        return cls(
            q=np.array(q, dtype=float).reshape(n, dof),
            claim=np.array([_CODE[c] for c in claims], dtype=np.int8),
            iterations=zeros if iterations is None else np.array(iterations, dtype=np.int64),
            restarts=zeros.copy() if restarts is None else np.array(restarts, dtype=np.int64),
            branch=None if branch is None else tuple(branch),
            singular=None if singular is None else np.array(singular, dtype=np.bool_),
            reasons=tuple(reasons),
        )


def one(
    q: np.ndarray,
    claim: Status,
    reason: str,
    *,
    iterations: int = 0,
    restarts: int = 0,
    branch: str | None = None,
    singular: bool = False,
) -> Answers:
    """One row (``q`` a float array, which its row views). Built from shared read-only
    columns where they are the common ones, without the generated ``__init__``: a closed
    form's unreached branch costs a solve no more than before."""
    return frozen(
        Answers,
        q=q[None],
        claim=_CLAIM_ROW[claim.code],
        iterations=_ZERO_ROW if iterations == 0 else np.array([iterations], dtype=np.int64),
        restarts=_ZERO_ROW if restarts == 0 else np.array([restarts], dtype=np.int64),
        branch=None if branch is None else (branch,),
        singular=_TRUE_ROW if singular else None,
        reasons=(reason,),
    )


def _read_only(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


# Read-only columns shared by every answer that has them: one row's claim, a true flag,
# and the counts and all-converged claims of up to 16 rows (a closed form's most).
_CLAIM_ROW = {s.code: _read_only(np.array([s.code], dtype=np.int8)) for s in Status}
_TRUE_ROW = _read_only(np.ones(1, dtype=np.bool_))
_ZEROS = tuple(_read_only(np.zeros(n, dtype=np.int64)) for n in range(17))
_ZERO_ROW = _ZEROS[1]
_CONVERGED_ROWS = tuple(_read_only(np.full(n, _CONVERGED, dtype=np.int8)) for n in range(17))


def zero_counts(n: int) -> np.ndarray:
    """(n,) zeros, read-only: the iterations or restarts of n rows a closed form found."""
    return _ZEROS[n] if n < len(_ZEROS) else _read_only(np.zeros(n, dtype=np.int64))


def converged_claims(n: int) -> np.ndarray:
    """(n,) claims, each converged, read-only: a closed form that reached every row."""
    if n < len(_CONVERGED_ROWS):
        return _CONVERGED_ROWS[n]
    return _read_only(np.full(n, _CONVERGED, dtype=np.int8))


def stacked(parts: Sequence[Answers], dof: int) -> Answers:
    """The rows of ``parts``, in their order (none: no rows)."""
    if len(parts) == 1:
        return parts[0]
    labelled = any(p.branch is not None for p in parts)
    flagged = any(p.singular is not None for p in parts)
    worded = all(p.reasons is not None for p in parts)
    return Answers(
        q=np.concatenate([p.q for p in parts]) if parts else np.empty((0, dof)),
        claim=np.concatenate([p.claim for p in parts]) if parts else np.empty(0, np.int8),
        iterations=np.concatenate([p.iterations for p in parts]) if parts else np.zeros(0, int),
        restarts=np.concatenate([p.restarts for p in parts]) if parts else np.zeros(0, int),
        branch=tuple(p.label(i) for p in parts for i in range(len(p))) if labelled else None,
        singular=(
            np.array([p.is_singular(i) for p in parts for i in range(len(p))], dtype=np.bool_)
            if flagged
            else None
        ),
        reasons=tuple(r for p in parts for r in p.reasons) if worded else None,  # type: ignore[union-attr]
    )
