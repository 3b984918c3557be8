"""``BatchResult``: the answers for N targets as arrays, with the field names of ``IKResult``."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast, overload

import numpy as np

from armik import batch_file, batch_summary, reasons
from armik.problem.settings import SolverSettings
from armik.result import IKResult
from armik.status import Status

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel
    from armik.targets.aim import Aim

_WORDS = np.array([s.value for s in Status])
_NOT_CONVERGED = Status.NOT_CONVERGED.code  # the failure state rows start in (``empty``)
NO_BRANCH = -1  # ``branch_code``: a row without a branch label
UNREAD = -2  # ``branch_code``: the branch of the row's q, read by ``brancher`` when first read
PREFERRED = ", prefer"  # after the solver's name: a batch ranked by a preference (prefer=)


@dataclass(frozen=True, eq=False)
class BatchResult:
    """The answers for N targets, as arrays with the field names of ``IKResult``.

    - ``q`` (N, dof): joint values (rad, m); for a failure, the best configuration found.
    - ``success`` (N,) bool: verified by Pinocchio FK within the tolerances and the limits.
    - ``status`` (N,) words (``converged``, ``unreachable``, ...), as in ``IKResult``;
      stored as the small integer codes ``status_code`` (``Status.code``).
    - ``position_error`` (N,) m and ``orientation_error`` (N,) rad, measured on ``q``;
      each NaN where the target has no such part (a position's orientation, an
      ``armik.Axis``'s or ``armik.LookAt``'s position).
    - ``iterations``, ``restarts`` (N,) per target; ``solver``; ``time`` (s) for the whole
      batch, verification included.
    - ``reasons``: index -> each failure's reason; ``said``: a success's words where its
      errors do not give them (``reason(i)``); ``solvers``: each row's, where rows name several.
    - ``min_distance`` (N,) m: the distance of the closest checked pair at ``q`` (negative:
      overlapping), NaN where collisions were not checked; ``pair_index`` (N,) the index
      of that pair in ``pair_names`` (-1 where not checked); ``closest_pair(i)`` its names.
    - ``score`` (N,): each answer's score with ``prefer=`` (lower is better), NaN without.
    - ``measured`` (N, 2): where the request measured other than the distances to the
      targets (weights, a region), what each verdict measured (position, orientation);
      ``position_error`` and ``orientation_error`` are the distances all the same. NaN
      where the verdict measured the distances themselves (``armik.verify.distances``).
    - ``region``, ``cone``: the targets are regions (bounds, an aim) and the aim's cone (rad,
      None: no aim), ``looks_at``: the aim looks at a point, ``free``: (position, rotation)
      left wholly free by weights of 0 or infinite bounds, ``aims``: the orientation
      distance is the tip axis' angle to its direction (an aim at a point or along a
      direction, an ``armik.Axis``), not the angle to the targets' rotations, so that a
      success's ``reason(i)`` says what ``solve``'s says.
    - ``errors``: on several tips (``armik.Arms``), tip -> (N, 2) each row's distances to
      that tip's target (position m, orientation rad, NaN where not measured), as
      ``Arms.solve``'s ``errors[tip]``; empty for one arm.
    - ``branch`` (N,): each answer's branch label as ``solve`` gives it, None where none;
      stored as codes, ``branch_code`` indices into ``branch_names`` (-1: none), a compiled
      closed form's read from its answers by ``brancher`` when first read.

    ``len(r)``, ``r[i]`` (an ``IKResult``), ``r[mask]`` or ``r[a:b]`` (a ``BatchResult``),
    iteration over ``IKResult``s, ``save``/``load`` (.npz) and ``summary()``.
    """

    q: np.ndarray
    success: np.ndarray
    status_code: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    iterations: np.ndarray
    restarts: np.ndarray
    solver: str
    time: float
    joint_names: tuple[str, ...] = ()
    arm: str = ""
    tol_position: float = SolverSettings.tol_position
    tol_orientation: float = SolverSettings.tol_orientation
    reasons: dict[int, str] = field(default_factory=dict)
    margin: float = 0.0  # m: what a collision-checked success kept
    min_distance: np.ndarray | None = None  # (N,) m; NaN filled when None is given
    pair_index: np.ndarray | None = None  # (N,) index into pair_names, -1: none
    pair_names: list[tuple[str, str]] = field(default_factory=list)
    score: np.ndarray | None = None  # (N,) with prefer=; NaN filled when None is given
    region: bool = False  # the targets are regions (bounds, a cone): errors lie outside them
    cone: float | None = None  # rad: the targets' aim's cone (a batch shares one), None: no aim
    looks_at: bool = False  # the aim looks at a point (its words: the line to the point)
    free: tuple[bool, bool] = (False, False)  # (position, rotation): every component free
    aims: bool = False  # the orientation distance is the tip axis' angle to its direction
    measured: np.ndarray | None = None  # (N, 2) the verdict's errors; NaN filled when None
    # a success's claim before its verdict's words, as ``solve`` says it ("{}": its
    # restarts; a numeric solver's ``reasons.CONVERGED``), or "" for none
    claim: str = ""
    branch_code: np.ndarray | None = None  # (N,) int16; NO_BRANCH filled when None is given
    branch_names: list[str] = field(default_factory=list)
    # the codes of UNREAD rows' q (k, dof) in ``branch_names``, which start with its ``labels``
    brancher: Callable[[np.ndarray], np.ndarray] | None = None
    errors: dict[str, np.ndarray] = field(default_factory=dict)  # tip -> (N, 2), several tips
    weighted: bool = False  # weights on the axes: a success's distances said as ``solve``'s
    said: dict[int, str] = field(default_factory=dict)  # successes' words, where kept
    solvers: dict[int, str] = field(default_factory=dict)  # rows' solvers, where several

    def __post_init__(self) -> None:
        n = len(self.success)
        if self.branch_code is None:
            object.__setattr__(self, "branch_code", np.full(n, NO_BRANCH, dtype=np.int16))
        if not self.branch_names:  # a brancher's codes index its labels
            self.branch_names.extend(getattr(self.brancher, "labels", ()))
        if self.min_distance is None:
            object.__setattr__(self, "min_distance", np.full(n, np.nan))
        if self.score is None:
            object.__setattr__(self, "score", np.full(n, np.nan))
        if self.pair_index is None:
            object.__setattr__(self, "pair_index", np.full(n, -1, dtype=np.int32))
        if self.measured is None:
            object.__setattr__(self, "measured", np.full((n, 2), np.nan))

    # -- container --------------------------------------------------------------------

    def __len__(self) -> int:
        return len(self.success)

    @property
    def _scores(self) -> np.ndarray:
        """``score``: an array once built (``__post_init__`` fills a None)."""
        return cast(np.ndarray, self.score)

    @property
    def _distances(self) -> np.ndarray:
        """``min_distance``: an array once built (``__post_init__`` fills a None)."""
        return cast(np.ndarray, self.min_distance)

    @property
    def _measured(self) -> np.ndarray:
        """``measured``: an array once built (``__post_init__`` fills a None)."""
        return cast(np.ndarray, self.measured)

    @property
    def _pairs(self) -> np.ndarray:
        """``pair_index``: an array once built (``__post_init__`` fills a None)."""
        return cast(np.ndarray, self.pair_index)

    @property
    def _codes(self) -> np.ndarray:
        """``branch_code``: an array once built, UNREAD rows included."""
        return cast(np.ndarray, self.branch_code)

    def branch_codes(self, rows: np.ndarray | None = None) -> np.ndarray:
        """The ``branch_code`` of ``rows`` (None: every row), those UNREAD read from their
        q and kept first."""
        codes = self._codes
        unread = np.flatnonzero(codes == UNREAD) if rows is None else rows[codes[rows] == UNREAD]
        if len(unread):
            codes[unread] = NO_BRANCH if self.brancher is None else self.brancher(self.q[unread])
        return codes if rows is None else codes[rows]

    @property
    def branch(self) -> np.ndarray:
        """(N,) each answer's branch label as ``solve`` gives it (objects; None: none)."""
        names = np.array([*self.branch_names, None], dtype=object)  # -1: the None at the end
        return cast(np.ndarray, names[self.branch_codes()])

    @property
    def status(self) -> np.ndarray:
        """(N,) status words; ``r.status == "converged"`` compares element-wise."""
        words: np.ndarray = _WORDS[self.status_code]
        return words

    @property
    def success_rate(self) -> float:
        """Fraction of targets solved, in [0, 1] (NaN for an empty batch)."""
        return float(self.success.mean()) if len(self) else math.nan

    def counts(self) -> dict[str, int]:
        """How many targets ended in each status, statuses that occur only."""
        found = np.bincount(self.status_code.astype(np.intp), minlength=len(_WORDS))
        return {str(_WORDS[i]): int(c) for i, c in enumerate(found) if c}

    def reason(self, i: int) -> str:
        """Why target ``i`` ended as it did."""
        i = self._index(i)
        if (kept := self.reasons.get(i, self.said.get(i))) is not None:  # failed, or said
            return kept
        apart = self._measured[i]
        pos, ori = self.position_error[i], self.orientation_error[i]
        if not math.isnan(apart[0]):  # the verdict measured apart: what it measured first
            pos, ori = apart[0], apart[1]
        tol_p, tol_r, free = self.tol_position, self.tol_orientation, self.free
        # a target that holds no position (NaN: an Axis, a LookAt alone, on every tip):
        # its verdict's 0 m unsaid, as a part left wholly free is
        unheld = free[0] or self.position_error[i] != self.position_error[i]
        said_pos, said_ori = None if unheld else pos, None if free[1] or ori != ori else ori
        cone = None if self.cone is None else reasons.Cone(self.cone, self.looks_at)
        if self.region:  # inside it for a success; NaN: no orientation measured (a position)
            measured = reasons.region(said_pos, said_ori, tol_p, tol_r, cone)
        else:
            measured = reasons.measured(said_pos, said_ori, tol_p, tol_r)
        said = self.claim.format(int(self.restarts[i])) if self.claim and self.success[i] else None
        text = reasons.verified(said, measured)
        if not math.isnan(apart[0]):
            pos, ori = float(self.position_error[i]), float(self.orientation_error[i])
            pos = None if pos != pos else pos  # NaN: a target that holds no position
            if self.errors:  # several tips: the worst tip's measure, every tip's distance
                text = reasons.tips_apart(text, pos, ori)
            else:  # solve's words (``verify.distances``)
                axis = reasons.Cone(self.cone or 0.0, self.looks_at) if self.aims else None
                text = reasons.measured_apart(text, pos, ori, self.weighted, axis)
        if self._pairs[i] >= 0 or not math.isnan(self._distances[i]):  # checked
            pair, distance = self.closest_pair(i), float(self._distances[i])
            text = reasons.and_clear(text, pair, distance, self.margin)
        return text

    def closest_pair(self, i: int) -> tuple[str, str] | None:
        """The names of target ``i``'s closest checked pair; None where not checked."""
        k = int(self._pairs[self._index(i)])
        return None if k < 0 else self.pair_names[k]

    def _index(self, i: int | np.integer[Any]) -> int:
        n = len(self)
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
            raise IndexError(f"a target index is a whole number in [-{n}, {n}), got {i!r:.80}")
        i = int(i)
        if not -n <= i < n:
            raise IndexError(f"target index {i} out of range for a batch of {n}")
        return i + n if i < 0 else i

    @overload
    def __getitem__(self, index: int | np.integer[Any]) -> IKResult: ...

    @overload
    def __getitem__(
        self, index: slice | np.ndarray | Sequence[int] | Sequence[bool]
    ) -> BatchResult: ...

    def __getitem__(
        self, index: int | np.integer[Any] | slice | np.ndarray | Sequence[int] | Sequence[bool]
    ) -> IKResult | BatchResult:
        if isinstance(index, (int, np.integer)) and not isinstance(index, (bool, np.bool_)):
            i = self._index(index)
            ori, code = float(self.orientation_error[i]), int(self.branch_codes(np.array([i]))[0])
            position = float(self.position_error[i])  # NaN: a target with no position
            extra: dict[str, Any] = {"index": i, "batch_time": self.time}
            if self._pairs[i] >= 0 or not math.isnan(self._distances[i]):
                extra["min_distance"] = float(self._distances[i])
                extra["closest_pair"] = self.closest_pair(i)
            if not math.isnan(self._scores[i]):
                extra["score"] = float(self._scores[i])
            if not math.isnan(self._measured[i, 0]):
                pos, rot = self._measured[i].tolist()
                extra["measured"] = (pos, None if math.isnan(rot) else rot)
            if self.errors:  # several tips: each tip's, as ``Arms.solve`` gives them
                extra["errors"] = {
                    tip: tuple(None if math.isnan(x) else x for x in e[i].tolist())
                    for tip, e in self.errors.items()
                    if not np.isnan(e[i]).all()
                }
            return IKResult(
                q=self.q[i],
                success=bool(self.success[i]),
                status=Status.from_code(self.status_code[i]),
                reason=self.reason(i),
                solver=self.solvers.get(i, self.solver.removesuffix(PREFERRED)),  # solve's
                iterations=int(self.iterations[i]),
                position_error=None if math.isnan(position) else position,
                orientation_error=None if math.isnan(ori) else ori,
                time=self.time / max(len(self), 1),
                restarts=int(self.restarts[i]),
                branch=None if code < 0 else self.branch_names[code],
                extra=extra,
            )
        try:  # numpy's indexing, its words replaced by ours
            picked = np.arange(len(self))[index]
        except (IndexError, TypeError, ValueError):
            picked = np.zeros((0, 0), dtype=np.intp)
        if picked.ndim != 1 or isinstance(index, (bool, np.bool_)):
            n = len(self)
            raise IndexError(
                f"index a BatchResult of {n} rows with an int or a list of ints in [-{n}, {n}), "
                f"a slice or a mask of {n} bools, got {index!r:.80}"
            )
        return BatchResult(
            q=self.q[picked],
            success=self.success[picked],
            status_code=self.status_code[picked],
            position_error=self.position_error[picked],
            orientation_error=self.orientation_error[picked],
            iterations=self.iterations[picked],
            restarts=self.restarts[picked],
            solver=self.solver,
            time=self.time * len(picked) / max(len(self), 1),  # its share of the batch's time
            joint_names=self.joint_names,
            arm=self.arm,
            tol_position=self.tol_position,
            tol_orientation=self.tol_orientation,
            **{words: _of(getattr(self, words), picked) for words in _TEXTS},
            margin=self.margin,
            min_distance=self._distances[picked],
            pair_index=self._pairs[picked],
            pair_names=list(self.pair_names),
            score=self._scores[picked],
            region=self.region,
            cone=self.cone,
            looks_at=self.looks_at,
            free=self.free,
            aims=self.aims,
            measured=self._measured[picked],
            claim=self.claim,
            branch_code=self._codes[picked],
            branch_names=list(self.branch_names),
            brancher=self.brancher,
            errors={tip: e[picked] for tip, e in self.errors.items()},
            weighted=self.weighted,
        )

    def __iter__(self) -> Iterator[IKResult]:
        for i in range(len(self)):
            yield self[i]

    def __repr__(self) -> str:
        return f"BatchResult({self.summary()})"

    def summary(self) -> str:
        """One line: how many were solved, by status, the time and the throughput."""
        return batch_summary.summary(self)

    # -- files ------------------------------------------------------------------------

    def save(self, path: str | Path) -> Path:
        """Write the arrays and the metadata to an ``.npz`` file (no pickles;
        ``armik.batch_file``)."""
        return batch_file.save(replace(self, reasons={**self.reasons, **self.said}), path)

    @classmethod
    def load(cls, path: str | Path) -> BatchResult:
        """Read a file written by ``save``; raises ``InputError`` if it is not one."""
        return cls(**batch_file.fields(path))

    # -- building ---------------------------------------------------------------------

    @classmethod
    def empty(cls, n: int, dof: int, **meta: Any) -> BatchResult:
        """Arrays for n answers, to be filled in place (the solvers' failure state)."""
        return cls(
            q=np.zeros((n, dof)),
            success=np.zeros(n, dtype=bool),
            status_code=np.full(n, _NOT_CONVERGED, dtype=np.int8),
            position_error=np.full(n, np.nan),
            orientation_error=np.full(n, np.nan),
            iterations=np.zeros(n, dtype=np.int32),
            restarts=np.zeros(n, dtype=np.int32),
            **meta,
        )

    @classmethod
    def for_arm(
        cls,
        arm: ArmModel,
        n: int,
        solver: str,
        opts: SolverSettings,
        claim: str = "",
        margin: float = 0.0,
        aim: Aim | None = None,
        brancher: Callable[[np.ndarray], np.ndarray] | None = None,
        along: tuple[float, float, float] | None = None,
    ) -> BatchResult:
        """``empty`` rows for n targets of ``arm``, labelled with its joints, tolerances and
        the clearance its successes keep (``claim``: see the field); ``aim``: the targets'
        aim (a cone: a region, as bounds are, its angle named in a success's reason);
        ``along``: their ``armik.Axis``'s, lowered to poses (``Target.along``)."""
        return cls.empty(
            n,
            arm.dof,
            solver=solver,
            time=0.0,
            joint_names=tuple(arm.joint_names),
            arm=arm.name,
            tol_position=opts.tol_position,
            tol_orientation=opts.tol_orientation,
            margin=margin,
            region=opts.bounds is not None or aim is not None,
            cone=None if aim is None else aim.within,
            looks_at=aim is not None and aim.point is not None,
            free=(False, False)
            if opts.weights is None and opts.bounds is None
            else opts.left_free(False, aim is not None),
            aims=along is not None or (aim is not None and aim.sight is not None),
            claim=claim,
            brancher=brancher,
            weighted=opts.weights is not None,
        )

    def put(self, start: int, part: BatchResult) -> None:
        """Copy ``part`` into rows ``start:start + len(part)`` (used while assembling)."""
        stop = start + len(part)
        for name in _ARRAYS:
            getattr(self, name)[start:stop] = getattr(part, name)
        for words in _TEXTS:  # row -> text
            getattr(self, words).update({start + i: t for i, t in getattr(part, words).items()})
        if part.pair_names and part.pair_names != self.pair_names:
            mine = np.array([self._pair(p) for p in part.pair_names] + [-1], dtype=np.int32)
            self._pairs[start:stop] = mine[part._pairs]  # -1 stays -1
        else:
            self._pairs[start:stop] = part._pairs
        codes = part._codes
        if part.branch_names != self.branch_names or self.brancher is None:
            codes = part.branch_codes()  # read where they were, in this batch's names
            if part.branch_names != self.branch_names:
                ours = [_interned(self.branch_names, b) for b in part.branch_names] + [NO_BRANCH]
                codes = np.array(ours, dtype=np.int16)[codes]  # -1 stays -1
        self._codes[start:stop] = codes
        for tip, e in part.errors.items():
            self.tip_errors(tip)[start:stop] = e

    def tip_errors(self, tip: str) -> np.ndarray:
        """``errors[tip]``, (N, 2), made (NaN: not measured) on first use while assembling."""
        e = self.errors.get(tip)
        if e is None:
            e = self.errors[tip] = np.full((len(self), 2), np.nan)
        return e

    def branches_unread(self, start: int, stop: int) -> None:
        """Rows ``start:stop`` label their branch from their q when first read
        (``brancher``): a compiled batch's rows, which compute no label."""
        self._codes[start:stop] = UNREAD

    def put_result(self, i: int, r: IKResult) -> None:
        """Copy one ``IKResult`` into row ``i``."""
        self.q[i] = r.q
        self.success[i] = r.success
        self.status_code[i] = r.status.code
        self.position_error[i] = r.position_error
        self.orientation_error[i] = math.nan if r.orientation_error is None else r.orientation_error
        self.iterations[i] = r.iterations
        self.restarts[i] = r.restarts
        # its label's code, written out here: a path puts every waypoint's result
        names, branch = self.branch_names, r.branch
        code = NO_BRANCH if branch is None else len(names)
        if branch is not None and branch in names:
            code = names.index(branch)
        elif branch is not None:
            names.append(branch)
        cast(np.ndarray, self.branch_code)[i] = code
        s = r.extra.get("score")
        if s is not None:
            self._scores[i] = s
        d = r.extra.get("min_distance")
        if d is not None:
            self.put_distance(i, d, r.extra.get("closest_pair"))
        apart = r.extra.get("measured")
        if apart is not None:
            self._measured[i] = (apart[0], math.nan if apart[1] is None else apart[1])
        for tip, (pos, ori) in (r.extra.get("errors") or {}).items():  # several tips
            self.tip_errors(tip)[i] = tuple(math.nan if e is None else e for e in (pos, ori))
        if r.success:
            self.reasons.pop(i, None)  # a row solved again: its earlier failure's words go
        else:
            self.reasons[i] = r.reason

    def put_distance(self, i: int, distance: float, pair: tuple[str, str] | None) -> None:
        """Row ``i``'s collision check: its closest pair (None: none) and their distance."""
        self._distances[i] = distance
        self._pairs[i] = -1 if pair is None else self._pair(pair)

    def _pair(self, pair: tuple[str, str]) -> int:
        """The index of ``pair`` in ``pair_names``, appended when new."""
        return _interned(self.pair_names, tuple(pair))  # given as any sequence of two names


def _of(words: dict[int, str], picked: np.ndarray) -> dict[int, str]:
    """The texts of ``words`` (row -> text) of the rows ``picked``, by their place in it."""
    if not words:
        return {}
    keys = np.fromiter(words, dtype=np.int64, count=len(words))
    return {j: words[int(picked[j])] for j in np.flatnonzero(np.isin(picked, keys)).tolist()}


def _interned(names: list[Any], name: Any) -> int:
    """The index of ``name`` in ``names``, appended when new."""
    try:
        return names.index(name)
    except ValueError:
        names.append(name)
        return len(names) - 1


_TEXTS = ("reasons", "said", "solvers")  # the texts kept by row, row -> text
_ARRAYS = (
    *("q", "success", "status_code", "position_error", "orientation_error", "iterations"),
    *("restarts", "min_distance", "score", "measured"),
)
