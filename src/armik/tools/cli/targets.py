"""``armik solve``'s target flags as targets, one per ``--tip`` in the order given.

Each tip takes ``--xyz`` with ``--rpy`` or ``--quat`` (a pose), with ``--axis``,
``--toward`` and ``--within`` (a point and a direction of the tip's axis, within a cone:
``[armik.Position, armik.Axis]``) or ``--look-at`` instead of ``--toward`` (the axis aimed at
a point: ``[armik.Position, armik.LookAt]``; ``--bounds`` with rotation bounds 0 0 0: the
position within their box, ``armik.Position(xyz, bounds=...)``), or alone (a position). A pose with
``--bounds`` is an ``armik.Pose`` with those bounds (and ``--weights``, which then weigh the
error in the target frame, as without a task list).
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np
import pinocchio as pin

from armik.errors import InputError, OptionError, TargetError
from armik.problem.tasks import Axis, LookAt, Pose, Position, Task

# the flags given once per tip (argparse ``append``), matched to the tips in order
PER_TIP = ("xyz", "rpy", "quat", "axis", "toward", "look_at", "within")


def flag_targets(args: argparse.Namespace, options: dict, several: bool) -> list[object]:
    """One target per tip (a single one without ``--tip`` or with one). Takes out of
    ``options`` what the targets say themselves (``bounds`` and ``weights`` in a Pose).
    With ``several`` tips, a region or a dropped orientation is always said by a task, as
    tips that share joints are solved together and take no such option."""
    tips = args.tip or []
    n = max(len(tips), 1)
    given = {name: getattr(args, name) or [] for name in PER_TIP}
    _check_counts(tips, given, n)
    bounds = options.get("bounds")
    if bounds is not None:
        _check_bounds(bounds)
    box = None  # with --axis: the position's box (base frame), the direction --within's
    if given["axis"] and bounds is not None:
        if any(bounds[3:]):
            shown = " ".join(f"{b:g}" for b in bounds[3:])
            raise InputError(
                f"--bounds' rotation bounds {shown} do not go with --axis: --within bounds "
                "the axis, and its spin is free; give 0 0 0 for BRX BRY BRZ (BX BY BZ: the "
                "position's box, base frame)"
            )
        box = bounds[:3]
    # --weights and --position-only go to the library with --axis, which refuses those
    # that free the rotation the axis measures (``targets.aim.refuse_freed``): ``for_flags``
    for rpy in given["rpy"]:
        shown = " ".join(f"{a:g}" for a in rpy)
        if not all(math.isfinite(a) for a in rpy):  # not taken for degrees: refused by name
            raise InputError(f"--rpy {shown} is not 3 finite angles: give roll, pitch, yaw (rad)")
        if any(abs(a) > 2 * math.pi for a in rpy):  # taken as given: a warning, no refusal
            print(
                f"armik: warning: --rpy {shown} looks like degrees; --rpy takes radians",
                file=sys.stderr,
            )
    rotations = given["rpy"] or given["quat"]
    # several tips drop the orientation for --position-only here: no option says it there;
    # nor one with --bounds (a pose's region is a Pose task, whose rotation the option
    # would drop): the position within the box, as without --rpy
    dropped = options.get("position_only") and (several or bounds is not None)
    posed = bool(rotations) and not dropped
    # a box with --position-only and a rotation: the box in the target's frame (--bounds'
    # help), the rotation free
    freed = bool(rotations) and bool(dropped) and bounds is not None
    targets: list[object] = []
    for i in range(n):
        xyz = np.array(given["xyz"][i], dtype=float)
        if given["axis"]:
            within = given["within"][i] if given["within"] else 0.0
            if given["look_at"]:
                point = given["look_at"][i]
                targets.append(_point_and_look(xyz, given["axis"][i], point, within, box))
            else:
                toward = given["toward"][i]
                targets.append(_point_and_axis(xyz, given["axis"][i], toward, within, box))
        elif posed or freed:
            if given["rpy"]:
                pose: object = pin.SE3(pin.rpy.rpyToMatrix(*given["rpy"][i]), xyz)
            else:
                pose = (xyz, np.array(given["quat"][i], dtype=float))
            if bounds is None:
                targets.append(pose)
            else:
                box6 = (*bounds[:3], math.inf, math.inf, math.inf) if freed else bounds
                targets.append([Pose(pose, bounds=box6, weights=options.get("weights"))])
        elif several and bounds is not None:
            targets.append([Position(xyz, bounds=bounds[:3])])
        else:
            targets.append(xyz)
    if (posed or freed) and bounds is not None:
        options.pop("bounds", None)
        options.pop("weights", None)
    if freed:
        options.pop("position_only", None)
    if box is not None:  # in the Position: the weights go on to the library (``for_flags``)
        options.pop("bounds", None)
    if several:  # said by the targets (a Position with bounds, a position for a pose)
        options.pop("bounds", None)
        if not given["axis"]:  # with --axis, the library's to refuse (above)
            options.pop("position_only", None)
    return targets


def task_names(target: object) -> list[str]:
    """The names of a target's tasks (empty for a pose or a position)."""
    if isinstance(target, list):
        return [type(t).__name__ for t in target if isinstance(t, Task)]
    return []


def _check_counts(tips: list[str], given: dict[str, list], n: int) -> None:
    """Each per-tip flag once per tip (``--xyz`` always; the others, if given), in order."""
    twice = [t for i, t in enumerate(tips) if t in tips[:i]]
    if twice:
        raise InputError(f"--tip {twice[0]} is given twice: give each tip once")
    xyz = len(given["xyz"])
    flat = [name for name in ("rpy", "quat", "axis") if given[name]]
    if any(len(p) == 2 for p in given["xyz"]) and flat:
        raise InputError(
            f"--xy (a point on a planar arm's plane) does not go with --{flat[0]}: give "
            f"--xyz X Y Z with --{flat[0]}, or --xy alone"
        )
    if len(tips) <= 1 and xyz > 1:
        raise InputError(
            f"--xyz is given {xyz} times for one tip: for several tips give each its --tip "
            "before its target (--tip A --xyz X Y Z --tip B --xyz X Y Z)"
        )
    if xyz != n:
        raise InputError(_count_message("xyz", xyz, n, optional=False))
    for name in ("rpy", "quat", "axis"):
        count = len(given[name])
        if count not in (0, n):
            raise InputError(_count_message(name, count, n, optional=True))
    if given["axis"] and (given["rpy"] or given["quat"]):
        which = "--rpy" if given["rpy"] else "--quat"
        raise InputError(
            f"--axis does not go with {which}: --axis, --toward and --within leave the spin "
            f"about the axis free, {which} gives the whole orientation; give one of them"
        )
    axes = len(given["axis"])
    if given["toward"] and given["look_at"]:
        raise InputError(
            "--toward and --look-at both say where --axis points: give one of them (a "
            "direction, or a point to aim at)"
        )
    aim = "look_at" if given["look_at"] else "toward"
    for name in ("toward", "look_at", "within"):
        count = len(given[name])
        flag = "--" + name.replace("_", "-")
        if count and not axes:
            raise InputError(
                f"{flag} goes with --axis: give the tip's axis too (--axis 0 0 1 --toward "
                "0 0 -1 for the tool's z pointing down)"
            )
        if name == aim and count != axes:
            raise InputError(
                f"{flag} is given {count} time(s) for {axes} --axis: give one direction "
                "(--toward DX DY DZ) or point (--look-at PX PY PZ, base frame) after each "
                "--axis"
            )
        if name == "within" and count not in (0, axes):
            raise InputError(
                f"--within is given {count} time(s) for {axes} --axis: give it once per "
                "--axis, in the same order, or leave it out (0: exactly along --toward)"
            )


def _count_message(name: str, count: int, n: int, optional: bool) -> str:
    times = "time" if count == 1 else "times"
    extra = ", or not at all" if optional else ""
    return (
        f"--{name} is given {count} {times} for {n} --tip: give one --{name} per --tip, in "
        f"the same order{extra} (--tip A --xyz X Y Z --rpy R P Y --tip B --xyz X Y Z "
        "--rpy R P Y)"
    )


def _check_bounds(bounds: tuple[float, ...]) -> None:
    if any(math.isnan(b) or b < 0 for b in bounds):
        raise InputError(
            f"--bounds must be 6 numbers >= 0 (m, m, m, rad, rad, rad: how far each component "
            f"of the error may lie on either side; inf frees it), got {list(bounds)}"
        )


def _point_and_look(xyz: np.ndarray, axis, point, within: float, box=None) -> list[Task]:
    """``[Position(xyz, bounds=box), LookAt(point, axis, within)]``, each value checked
    under its flag."""
    if not all(math.isfinite(v) for v in point):
        raise TargetError(
            f"--look-at {' '.join(f'{v:g}' for v in point)} is no point: give 3 finite "
            "numbers (m, base frame)"
        )
    _check_direction("axis", axis, "0 0 1")
    _check_within(within)
    return [Position(xyz, bounds=box), LookAt(point, axis, within)]


def _point_and_axis(xyz: np.ndarray, axis, toward, within: float, box=None) -> list[Task]:
    """``[Position(xyz, bounds=box), Axis(axis, toward, within)]``, each vector checked
    under its flag."""
    _check_direction("axis", axis, "0 0 1")
    _check_direction("toward", toward, "0 0 -1")
    _check_within(within)
    return [Position(xyz, bounds=box), Axis(axis, toward, within)]


def _check_direction(flag: str, vector, example: str) -> None:
    if not all(math.isfinite(v) for v in vector) or not any(vector):
        raise TargetError(
            f"--{flag} {' '.join(f'{v:g}' for v in vector)} is no direction: give 3 finite "
            f"numbers, not all 0 (such as --{flag} {example})"
        )


def _check_within(within: float) -> None:
    if not 0.0 <= within <= math.pi:  # NaN too
        raise TargetError(
            f"--within {within:g} is no angle between two directions: give one in [0, pi] "
            "rad (0: exactly along --toward or --look-at)"
        )


def task_errors(result, names: list[str]) -> list[dict] | None:
    """A result's task errors (``extra["task_errors"]``) as JSON rows named by ``names``;
    None where the result has none (a pose the compiled path solved)."""
    errors = result.extra.get("task_errors")
    if errors is None:
        return None
    names = names if len(names) == len(errors) else [f"task {i}" for i in range(len(errors))]
    return [
        {
            "task": name,
            "position_error": e.position,
            "orientation_error": e.orientation,
            "within": e.within,
        }
        for name, e in zip(names, errors)
    ]


def task_lines(result, names: list[str], indent: str) -> list[str]:
    """The text of ``task_errors``: one line, each task's distance outside its region."""
    rows = task_errors(result, names) if names else None
    if not rows:
        return []
    parts = []
    for row in rows:
        words = []
        if row["position_error"] is not None:
            words.append(f"{row['position_error']:.2e} m")
        if row["orientation_error"] is not None:
            words.append(f"{row['orientation_error']:.2e} rad")
        state = "holds" if row["within"] else "misses"
        parts.append(f"{row['task']} {', '.join(words)} ({state})")
    return [f"{indent}tasks    : {'; '.join(parts)}"]


def for_flags(exc: OptionError) -> OptionError:
    """The library's refusal of an option a task list does not take, or of one that frees
    the rotation an aim measures (``targets.aim.refuse_freed``), in the words of the flags
    (the CLI's task lists come from --axis and from regions)."""
    if "frees a rotation the aim measures" in str(exc):
        flag = "--" + exc.option.replace("_", "-")
        value = exc.value
        shown = " ".join(f"{w:g}" for w in value) if isinstance(value, tuple) else ""
        return OptionError(
            f"{flag}{' ' + shown if shown else ''} does not go with --axis: it frees the "
            "rotation --axis measures (the tip's axis within --within of its direction); "
            f"leave {flag} out to hold the axis (the spin about it stays free), or leave "
            "--axis out to leave the orientation free",
            option=exc.option,
            value=exc.value,
        )
    if "list of tasks" not in str(exc):
        return exc
    flag = "--" + exc.option.replace("_", "-")
    what = f"--solver {exc.value}" if exc.option == "solver" else flag
    return OptionError(
        f"{what} does not apply to this target: it is solved as tasks (--axis, or a region "
        f"on several tips) by the task solver, which takes no {flag} (yet); leave it out, "
        "or give a pose (--rpy or --quat)",
        option=exc.option,
        value=exc.value,
    )
