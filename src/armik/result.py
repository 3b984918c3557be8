"""The result of an IK solve: one frozen, keyword-only type for every solver."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any

import numpy as np

from armik.status import Status

_new = object.__new__
STATUSES: tuple[str, ...] = tuple(s.value for s in Status)


@dataclass(frozen=True, kw_only=True, eq=False)
class IKResult:
    """One IK answer, verified by forward kinematics: Pinocchio's, or for several answers of
    one target (``solve_all``) armik's compiled FK, held to Pinocchio's to 1e-12.

    ``q``: joint values (rad, m), one per joint, read-only. ``success`` is True only if the
    FK errors are within tolerance and every joint is within its limits. ``position_error``
    (m, to the target's position; None for a target that holds no position: an
    ``armik.Axis`` or ``armik.LookAt`` alone) and ``orientation_error`` (rad, geodesic to
    the target's rotation; for a target without a rotation of its own that aims, the tip
    axis' angle to its direction; None for a position-only target without one) are the
    true distances of ``q``'s tip to the target, whatever the weights and bounds; where
    the request measured other than them (weights, a region), ``measured`` gives what its
    verdict measured. ``time`` (s) covers the whole call including verification.
    """

    q: np.ndarray
    success: bool
    status: Status
    reason: str
    solver: str
    iterations: int
    position_error: float | None
    orientation_error: float | None
    time: float
    branch: str | None = None
    singular: bool = False
    restarts: int = 0
    extra: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        q = np.array(self.q, dtype=float)
        q.flags.writeable = False
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "status", Status.parse(self.status))

    @classmethod
    def _from_fields(cls, fields: dict[str, Any]) -> IKResult:
        """The one constructor of armik's own results: ``fields`` holds every field but
        ``extra``, ``q`` a read-only float array and ``status`` a ``Status``; instead of
        ``reason``, ``_reason`` may hold (function, arguments), the text written on first
        read (prepared solves). Built as ``frozen`` builds, inline: a solve makes one."""
        self = _new(cls)
        d = self.__dict__
        d.update(fields)
        d["extra"] = {}
        return self

    @property
    def measured(self) -> tuple[float, float | None] | None:
        """(position, orientation): what the verdict measured where the request measures
        other than the distances to the target (weights on the axes: the weighted error; a
        region: the distances outside it), else None (``armik.verify.distances``)."""
        return self.extra.get("measured")

    if not TYPE_CHECKING:  # to a type checker the fields are all there is: a typo is an error

        def __getattr__(self, name: str) -> str:
            # Results built by ``armik.solve.prepared`` carry their reason as (function,
            # arguments) and write the text on first read: formatting it costs a microsecond
            # that a loop of solves rarely needs. Only called for attributes not found the
            # usual way.
            if name == "reason":
                d = self.__dict__
                parts = d.get("_reason")
                if parts is not None:
                    text = parts[0](*parts[1])
                    d["reason"] = text
                    return text
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __eq__(self, other: object) -> bool:
        """Field for field, ``q`` element-wise, ``extra`` not compared (the dataclass's own
        comparison would ask numpy for the truth of an array)."""
        if type(other) is not IKResult:
            return NotImplemented
        return np.array_equal(self.q, other.q) and all(
            getattr(self, name) == getattr(other, name) for name in _COMPARED
        )

    __hash__ = None  # type: ignore[assignment]  # equal results need not hash alike: mutable extra

    @property
    def min_distance(self) -> float | None:
        """The distance (m) of the closest checked pair at ``q`` (negative: their depth of
        overlap); None when collisions were not checked (no ``obstacles``, no
        ``self_collision``)."""
        return self.extra.get("min_distance")

    @property
    def closest_pair(self) -> tuple[str, str] | None:
        """The names of the closest checked pair (a link, and a link or
        ``obstacles[i] (Shape)``); None when collisions were not checked."""
        return self.extra.get("closest_pair")

    @property
    def errors(self) -> dict[str, tuple[float, float | None]] | None:
        """Per tip of several (``armik.load(..., tips=[...])``): its (position m,
        orientation rad or None) error at ``q``, by Pinocchio's FK; None for one tip."""
        return self.extra.get("errors")

    @property
    def score(self) -> float | None:
        """The answer's score with ``prefer=`` (lower is better); None without."""
        return self.extra.get("score")

    def __repr__(self) -> str:
        ori = "n/a" if self.orientation_error is None else f"{self.orientation_error:.2e} rad"
        pos = "n/a" if self.position_error is None else f"{self.position_error:.2e} m"
        branch = f", branch={self.branch!r}" if self.branch else ""
        return (
            f"IKResult(success={self.success}, status={self.status.value!r}, solver="
            f"{self.solver!r}{branch}, q={np.round(self.q, 6).tolist()}, "
            f"position_error={pos}, orientation_error={ori}, "
            f"iterations={self.iterations}, time={self.time * 1e3:.3f} ms, "
            f"reason={self.reason!r})"
        )

    def as_dict(self) -> dict[str, Any]:
        """Plain JSON-ready dictionary; with ``min_distance`` and ``closest_pair`` when
        collisions were checked, ``score`` with a preference, ``errors`` per tip with
        several, ``measured`` (position, orientation) where the verdict measured other
        than the distances (weights, a region)."""
        out = {
            "q": self.q.tolist(),
            "success": self.success,
            "status": self.status.value,
            "reason": self.reason,
            "solver": self.solver,
            "iterations": self.iterations,
            "position_error": self.position_error,
            "orientation_error": self.orientation_error,
            "time": self.time,
            "branch": self.branch,
            "singular": self.singular,
            "restarts": self.restarts,
        }
        if self.min_distance is not None:
            out["min_distance"] = self.min_distance
            out["closest_pair"] = None if self.closest_pair is None else list(self.closest_pair)
        if self.score is not None:
            out["score"] = self.score
        if self.errors is not None:
            out["errors"] = {tip: list(e) for tip, e in self.errors.items()}
        if self.measured is not None:
            out["measured"] = list(self.measured)
        return out


_COMPARED = tuple(f.name for f in fields(IKResult) if f.compare and f.name != "q")
