"""A picture of an arm without a browser: the stick figure of one configuration, and others
beside it (the branches of ``solve_all``), drawn with matplotlib into a PNG or an axes."""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from armik.errors import InputError, OptionError, ViewerError
from armik.model.arm_model import ArmModel, model_of
from armik.problem.problem import as_problem
from armik.problem.tasks import Pose, Position
from armik.result import IKResult
from armik.targets.pose import parse_target
from armik.view.stick import PRISMATIC_AXIS, REVOLUTE_AXIS, size, skeleton

OTHERS = ["C0", "C1", "C2", "C3", "C4", "C5", "C6", "C8", "C9"]


def plot(
    arm: object,
    q: object,
    path: str | Path | None = None,
    *,
    others: Sequence[object] = (),
    target: object = None,
    title: str | None = None,
    elev: float = 25.0,
    azim: float = -60.0,
    ax=None,
):
    """Draw ``arm`` at joints ``q`` (rad, m, or an ``IKResult``) as a stick figure: links
    as lines, joints as dots with their axes (orange: revolute, blue: prismatic), the tip
    frame as red/green/blue axes. ``others``: more configurations or ``IKResult``s, drawn
    thinner in colours of their own and named in the legend by branch; ``target``: any form
    ``Arm.solve`` takes, a pose marked with dashed axes, a position with a cross; of a task
    list its ``Pose`` and ``Position`` tasks are marked so (the other tasks are not drawn).
    ``elev``/``azim``: the view (deg).

    Writes a PNG to ``path`` and returns its ``Path``, or draws into the matplotlib 3D
    ``ax`` given and returns it. Needs matplotlib (``pip install "armik[plot]"``, in
    ``armik[view]`` too); raises ``InputError`` for a bad ``q``, a PNG in a folder that does
    not exist, an ``ax`` that is not a 3D axes, or neither path nor ax; ``OptionError`` for
    a ``path`` that is no file name, ``others`` that are no list, an angle that is no
    number.
    """
    arm = model_of(arm)
    _check_plain(path, others, elev, azim)
    if path is None and ax is None:
        raise InputError("plot needs a path for the PNG (plot(arm, q, 'arm.png')) or an ax")
    if ax is not None and getattr(ax, "name", None) != "3d":
        raise InputError(
            f"ax must be a matplotlib 3D axes (fig.add_subplot(projection='3d')), got {ax!r}"
        )
    if path is not None and ax is None and Path(path).is_dir():
        raise InputError(
            f"plot: {str(path)!r} is a folder: give the PNG's file name in it "
            f"({str(Path(path) / 'arm.png')!r})"
        )
    if path is not None and ax is None and not Path(path).parent.is_dir():
        raise InputError(
            f"plot: the folder {str(Path(path).parent)!r} of {str(path)!r} does not exist: "
            "create it, or write the PNG elsewhere"
        )
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ViewerError('plotting needs matplotlib: pip install "armik[plot]"') from None
    kind = Path(path).suffix[1:].lower() if path is not None and ax is None else ""
    kinds = Figure().canvas.get_supported_filetypes() if kind else {}
    if kind and kind not in kinds:
        raise InputError(
            f"plot: matplotlib writes no .{kind} file ({str(path)!r}): name it .png, or one "
            f"of {', '.join('.' + k for k in sorted(kinds))}"
        )
    main = _configuration(arm, q, "q")
    rest = [(_configuration(arm, o, f"others[{i}]"), _name(o, i)) for i, o in enumerate(others)]
    fig = None
    if ax is None:
        fig = Figure(figsize=(6.4, 5.6), layout="constrained")
        ax = fig.add_subplot(projection="3d")
    s = size(arm)
    seen = [_draw(ax, arm, main, "0.15", 2.6, "solution" if rest else None, s, joints=True)]
    for k, (qk, name) in enumerate(rest):
        seen.append(_draw(ax, arm, qk, OTHERS[k % len(OTHERS)], 1.4, name, s, joints=False))
    if target is not None:
        for p, R in _marks(target, arm):
            if R is None:
                ax.plot(*p, "x", color="tab:red", ms=8, mew=2)
            else:
                _frame(ax, p, R, 0.14 * s, linestyle="--")
            seen.append(p[None])
    _square(ax, np.vstack(seen))
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title(title if title is not None else arm.name, fontsize=10)
    if rest:
        ax.legend(fontsize=7, loc="upper left")
    if fig is None or path is None:  # path is None only with an ax given: fig is None
        return ax
    path = Path(path)
    if not path.suffix:  # matplotlib writes "name.png": the path returned is the file written
        path = path.with_suffix(".png")
    try:
        fig.savefig(path, dpi=110)
    except OSError as exc:
        raise InputError(f"plot: cannot write {str(path)!r}: {exc.strerror or exc}") from None
    return path


def _check_plain(path: object, others: object, elev: object, azim: object) -> None:
    """``OptionError`` naming ``path``, ``others``, ``elev`` or ``azim`` given in a form
    ``plot`` cannot take (before matplotlib raises a bare ``TypeError`` about it)."""
    if path is not None and not isinstance(path, (str, os.PathLike)):
        raise OptionError(
            f"plot's path must be a file name (a str or a Path), got {path!r}: "
            "plot(arm, q, 'arm.png')",
            option="path",
            value=path,
        )
    if isinstance(others, (str, bytes, IKResult)) or not isinstance(others, Iterable):
        raise OptionError(
            f"others must be a list of configurations or IKResults, got {others!r}: "
            "wrap one in a list, others=[q]",
            option="others",
            value=others,
        )
    for name, angle in (("elev", elev), ("azim", azim)):
        number = isinstance(angle, numbers.Real) and not isinstance(angle, bool)
        if not number or not math.isfinite(float(angle)):  # type: ignore[arg-type]
            raise OptionError(
                f"{name} must be an angle in degrees (a finite number), got {angle!r}",
                option=name,
                value=angle,
            )


def _marks(target: object, arm: ArmModel) -> list[tuple[np.ndarray, np.ndarray | None]]:
    """(position, rotation or None) of each mark of ``target``: a pose or a position, or a
    task list's ``Pose`` and ``Position`` tasks."""
    problem = as_problem(target)
    if problem is None:
        parsed = parse_target(target, arm)
        T = parsed.se3()
        return [(T.translation, None if parsed.rotation is None else T.rotation)]
    marks: list[tuple[np.ndarray, np.ndarray | None]] = []
    for task in problem.tasks:
        if isinstance(task, Pose):
            marks.append((task.T.translation, task.T.rotation))
        elif isinstance(task, Position):
            marks.append((np.asarray(task.p, float), None))
    return marks


def _configuration(arm: ArmModel, value: object, what: str) -> np.ndarray:
    if isinstance(value, IKResult):
        value = value.q
    return arm.check_q(value, what)


def _name(value: object, i: int) -> str:
    if isinstance(value, IKResult) and value.branch:
        return value.branch if value.success else f"{value.branch} ({value.status.value})"
    return f"configuration {i + 1}"


def _draw(ax, arm, q, color, width, label, s, joints: bool) -> np.ndarray:
    sk = skeleton(arm, q)
    p = sk.points
    ax.plot(p[:, 0], p[:, 1], p[:, 2], "-", color=color, lw=width, label=label)
    ax.plot(p[1:-1, 0], p[1:-1, 1], p[1:-1, 2], "o", color=color, ms=4 if joints else 2.5)
    ax.plot(*p[0], "s", color=color, ms=6 if joints else 3)
    if joints:
        half = 0.05 * s
        for origin, axis, slides in zip(p[1:-1], sk.axes, sk.prismatic):
            a, b = origin - half * axis, origin + half * axis
            rgb = np.array(PRISMATIC_AXIS if slides else REVOLUTE_AXIS)[:3] / 255
            ax.plot(*np.stack([a, b]).T, "-", color=rgb, lw=3.0, solid_capstyle="butt")
        T = arm.fk(q)
        _frame(ax, T.translation, T.rotation, 0.1 * s)
    return p


def _frame(ax, origin, R, length, linestyle="-") -> None:
    for k, color in enumerate(("tab:red", "tab:green", "tab:blue")):
        end = origin + length * R[:, k]
        ax.plot(*np.stack([origin, end]).T, linestyle, color=color, lw=1.6)


def _square(ax, points: np.ndarray) -> None:
    """Equal scales on x, y and z around everything drawn."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-3) * 1.1
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
