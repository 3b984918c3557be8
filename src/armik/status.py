"""The status of an answer: one type for the solvers' claims, results and batches.

``Status`` is a ``str`` enum, so ``result.status == "converged"`` keeps working and a
status prints as its plain word. ``code`` is the small integer the compiled kernel and
batch arrays use; ``FAILURE_RANK`` orders failed answers from most to least useful.
"""

from __future__ import annotations

from enum import Enum

from armik.errors import OptionError, did_you_mean, listing


class Status(str, Enum):
    CONVERGED = "converged"  # verified: within tolerance and within the limits
    UNREACHABLE = "unreachable"  # no configuration reaches the target (reason says why)
    NOT_CONVERGED = "not_converged"  # none found within the budget; may still exist
    JOINT_LIMITS = "joint_limits"  # reached, but only outside the joint limits
    DISCONTINUOUS = "discontinuous"  # a path waypoint reachable only by a jump
    COLLISION = "collision"  # reached within the limits, but only closer than the margin

    def __str__(self) -> str:
        return self.value

    @property
    def code(self) -> int:
        return _CODES[self]

    @classmethod
    def from_code(cls, code: int) -> Status:
        return _BY_CODE[int(code)]

    @classmethod
    def parse(cls, value: object) -> Status:
        """A ``Status`` from itself or its word; ``OptionError`` listing the words otherwise."""
        return cls(value)

    @classmethod
    def _missing_(cls, value: object) -> Status:
        # ``Status("ok")``: an armik error naming the statuses, not the enum's bare ValueError
        words = [s.value for s in cls]
        raise OptionError(
            f"status {value!r} is none of armik's statuses; {did_you_mean(value, words)}they are "
            f"{listing(words)}, each also armik.Status.<WORD> (armik.Status.CONVERGED, ...)",
            option="status",
            value=value,
        )


_BY_CODE: tuple[Status, ...] = tuple(Status)  # code = position in the declaration
_CODES = {s: i for i, s in enumerate(_BY_CODE)}

# Failed answers, most useful first: reached but off-limits, then near misses, then the rest.
FAILURE_RANK = {
    Status.JOINT_LIMITS: 0,
    Status.COLLISION: 1,
    Status.DISCONTINUOUS: 2,
    Status.NOT_CONVERGED: 3,
    Status.UNREACHABLE: 4,
}
