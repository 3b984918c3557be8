"""``Aim``: where a target wants the tip's axis, carried by the parsed target.

A target with an aim asks for a tip axis (unit, tip frame) within an angle of a
direction instead of the target's whole rotation: the direction is the target rotation's
image of the axis (``R_t a``), or the line from the tip to a point (``point``: an
``armik.LookAt``), or a base-frame direction whatever the target's rotation (``toward``:
an ``armik.Axis`` with a box around a position). It is what those tasks lower to
(``armik.problem.problem.lower``) and what the keywords ``cone=``, ``look_at=`` and
``toward=`` spell (``aim_of``, read once by ``armik.solve.read``); the compiled step and
the verdict read it from the target (``Target.aim``, ``TargetBatch.aim``), never from the
options.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from armik.checked import numbers
from armik.errors import OptionError
from armik.reasons import Cone
from armik.tolerances import MAX_POSITION

Vector = tuple[float, float, float]


class Aim(NamedTuple):
    axis: Vector  # the tip's axis, unit, in the tip frame
    within: float  # rad, in [0, pi]
    point: Vector | None = None  # look at this point (m, base frame)
    toward: Vector | None = None  # or along this unit direction (base frame)

    @property
    def cone(self) -> tuple[float, float, float, float]:
        """(ax, ay, az, within): the cone as the region's measure takes it."""
        a = self.axis
        return (a[0], a[1], a[2], self.within)

    @property
    def shape(self) -> tuple:
        """What plans and packed settings are kept under: the cone and which sight, not
        the point or direction (new at each of a loop of targets, written in per call;
        ``armik.solve.read`` writes the same four values out)."""
        return (self.axis, self.within, self.point is None, self.toward is None)

    @property
    def sight(self) -> Vector | None:
        """The point or direction the kernel reads per call, or None."""
        return self.point if self.point is not None else self.toward

    def centred(self) -> Aim:
        """This aim 0 wide: the angle of the axis from its direction is then measured."""
        return self._replace(within=0.0)


def cone_words(aim: Aim | None) -> Cone | None:
    """What a verdict's words name of ``aim`` (None: none): its angle, and whether it
    looks at a point."""
    return None if aim is None else _new(Cone, (aim.within, aim.point is not None))


_new = tuple.__new__  # (no Python call: the verdicts of a loop of aimed solves)


def aim_of(cone: object = None, look_at: object = None, toward: object = None) -> Aim | None:
    """The aim the keywords ``cone=(ax, ay, az, within)``, ``look_at=(px, py, pz)`` and
    ``toward=(dx, dy, dz)`` spell (None: none given); an ``OptionError`` naming the bad
    value and the way to say it.

    ``cone=`` alone points the axis where the target's rotation takes it (``R_t a``), so it
    needs a pose: on a position target it is refused (``refuse_without_direction``), not
    read as the identity's (the base frame's own axis, "up" for a tool's z)."""
    if cone is None:
        if look_at is not None or toward is not None:
            name, value = ("look_at", look_at) if toward is None else ("toward", toward)
            if look_at is not None and toward is not None:
                raise OptionError(_BOTH, option="toward", value=toward)
            raise OptionError(
                f"{name} needs cone=(ax, ay, az, within): the tip's axis that points there "
                "(say it with armik.LookAt or armik.Axis)",
                option=name,
                value=value,
            )
        return None
    axis_within = _cone(cone)
    aim = Aim(axis_within[:3], axis_within[3])  # type: ignore[arg-type]
    if look_at is None and toward is None:
        return aim
    if look_at is not None and toward is not None:
        raise OptionError(_BOTH, option="toward", value=toward)
    if toward is None:
        return aim._replace(point=_sight("look_at", look_at))
    return aim._replace(toward=_sight("toward", toward))


_BOTH = "look_at and toward both say where the cone points: give one of them"


def _cone(value: object) -> tuple[float, float, float, float]:
    """(ax, ay, az, within): a non-zero axis (made unit) and an angle in [0, pi]."""
    c = numbers(value)
    length = _length(c[:3]) if c.shape == (4,) and np.isfinite(c).all() else math.nan
    if not (1e-9 < length and 0.0 <= c[3] <= math.pi):  # (NaN: not numbers, not finite)
        raise OptionError(
            "cone must be (ax, ay, az, within): a non-zero axis of the tip frame and an angle "
            f"within [0, pi] rad (say it with armik.Position and armik.Axis); got {value!r}",
            option="cone",
            value=value,
        )
    a = _unit(c[:3])
    return (float(a[0]), float(a[1]), float(a[2]), float(c[3]))


_HUGE = 1e150  # a component beyond this: the sum of squares may overflow, the vector scaled


def _length(v: np.ndarray) -> float:
    """The length of a finite vector (inf beyond a float's range), scaled first where its
    squares overflow, as ``armik.Axis`` reads it (``problem.tasks.base.unit``): (1e308,
    1e308, 0) is a direction, not a zero or an infinite one, and no numpy warning."""
    big = float(np.abs(v).max())
    return big * float(np.linalg.norm(v / big)) if big > _HUGE else float(np.linalg.norm(v))


def _unit(v: np.ndarray) -> np.ndarray:
    """The finite vector ``v`` (longer than 1e-9) made unit, scaled first where its squares
    overflow."""
    big = float(np.abs(v).max())
    if big > _HUGE:
        v = v / big
    out: np.ndarray = v / np.linalg.norm(v)
    return out


def _sight(name: str, value: object) -> Vector:
    """The point (``look_at``) or the direction, made unit (``toward``), as three floats."""
    if (  # a task's point or direction, three floats already: checked without numpy
        type(value) is tuple
        and len(value) == 3
        and type(value[0]) is float
        and type(value[1]) is float
        and type(value[2]) is float
        and math.isfinite(value[0] + value[1] + value[2])
        and (
            -MAX_POSITION <= value[0] <= MAX_POSITION
            and -MAX_POSITION <= value[1] <= MAX_POSITION
            and -MAX_POSITION <= value[2] <= MAX_POSITION
            if name == "look_at"
            # (products, not ** 2: a float's ** overflows into an OverflowError)
            else abs(value[0] * value[0] + value[1] * value[1] + value[2] * value[2] - 1) < 1e-12
        )
    ):
        return value  # type: ignore[return-value]
    p = numbers(value)
    length = _length(p) if p.shape == (3,) and np.isfinite(p).all() else math.nan
    if name == "look_at" and length == length and not np.abs(p).max() <= MAX_POSITION:
        raise OptionError(_far("look_at", p.tolist()), option=name, value=value)
    if not (length == length and (name == "look_at" or length > 1e-9)):  # NaN: not numbers
        what = "a point (px, py, pz) in m" if name == "look_at" else "a non-zero direction"
        raise OptionError(
            f"{name} must be {what}, base frame (say it with armik.LookAt or armik.Axis); "
            f"got {value!r}",
            option=name,
            value=value,
        )
    if name == "toward":
        p = _unit(p)
    return (float(p[0]), float(p[1]), float(p[2]))


def _far(what: str, point: list) -> str:
    """Why a look-at point beyond ``MAX_POSITION`` is refused: its line of sight from the
    tip overflows, and measured as no direction at all any axis "looks at" it."""
    return (
        f"{what} {point} is beyond {MAX_POSITION:g} m from the base: give it in metres; a "
        "point that far away is a direction: say it with toward=(dx, dy, dz) (armik.Axis)"
    )


def refuse_freed(aim: Aim, opts, aimed: bool = True) -> None:
    """An ``OptionError`` for an option that frees the orientation an aim measures:
    ``position_only=True`` or ``weights`` with a rotation weight of 0, on a target with an
    aim (a cone by keywords, ``armik.Axis`` or ``armik.LookAt`` in a task list: one rule
    for either spelling). The verdict measures the aim whatever they say, so they would
    be silently overruled; the message says how to ask for either. Where the target
    carries the aim (``aimed``; not an ``Axis`` lowered to a pose whose spin its bounds
    free), ``bounds`` holding a rotation component within a finite width too: the cone
    replaces the rotation's components, which they would bound unread (0, no width, and
    inf, free, say nothing beside a cone)."""
    bounds = getattr(opts, "bounds", None) if aimed else None
    if bounds is not None and any(0.0 < b < math.inf for b in bounds[3:]):
        raise OptionError(
            f"bounds={tuple(bounds)!r} bound the rotation's components beside an aim "
            "(cone=, look_at=, toward=, armik.Axis, armik.LookAt), which measures the tip's "
            "axis within its cone in their place: give the cone's angle as its within and "
            "the rotation's bounds 0 (or inf), or drop the aim to bound the rotation",
            option="bounds",
            value=bounds,
        )
    if opts.position_only:
        name, value = "position_only", True
    elif opts.weights is not None and min(opts.weights[3:]) == 0.0:
        name, value = "weights", opts.weights
    else:
        return
    raise OptionError(
        f"{name} does not apply to a target with an aim (cone=, look_at=, toward=, "
        f"armik.Axis, armik.LookAt): {name}={value!r} frees a rotation the aim measures (the "
        "tip's axis within its cone); drop it to hold the axis (the cone leaves the spin "
        "about it free), or drop the aim (armik.Position alone) to leave the orientation "
        "free",
        option=name,
        value=value,
    )


def refuse_without_direction(aim: Aim, rotated: bool) -> None:
    """An ``OptionError`` for a cone with nothing to point along: no look-at, no direction
    and a target without a rotation (``rotated`` False: a position). Its axis would be
    held about the base frame's axis of the same name, which no one asks for by saying
    nothing (a tool's z "up"); the message says how to ask for that or anything else."""
    if rotated or aim.point is not None or aim.toward is not None:
        return
    a = ", ".join(f"{x:g}" for x in aim.axis)
    raise OptionError(
        f"cone=({a}, {aim.within:g}) on a position target points the tip's axis nowhere: a "
        "position has no rotation to carry the axis onto a direction; say where it points "
        f"with toward=(dx, dy, dz) (a base-frame direction: toward=({a}) for the base "
        "frame's own axis) or look_at=(px, py, pz), or give a pose whose rotation takes "
        "the axis there",
        option="cone",
        value=aim.cone,
    )
