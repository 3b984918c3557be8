"""The viewer's GUI panel: the last answer (status, solver, errors, time, branch, iterations,
the score of a preferred answer, each tip's errors where there are several, the reason of a
failure), the solver, the preference, the ghosts toggle (one arm), the servo mode and one
slider per joint."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from armik.result import IKResult

if TYPE_CHECKING:
    import viser

    from armik.view.robot import Robot

#: Panel rows (label, IKResult field), in order.
FIELDS = (
    ("status", "status"),
    ("solver", "solver"),
    ("position error (m)", "position_error"),
    ("orientation error (rad)", "orientation_error"),
    ("time (ms)", "time"),
    ("branch", "branch"),
    ("iterations", "iterations"),
    ("score (prefer=)", "score"),
)

#: The preferences the panel offers ("none": the first verified answer).
PREFERENCES = ("none", "nearest", "manipulability", "limits")
#: The choice of a viewer opened with its own preference (an ``armik.Posture``, a function).
GIVEN = "as given (prefer=)"


def slider_range(robot: Robot, k: int) -> tuple[float, float]:
    """Joint ``k``'s slider range: its limits, [-pi, pi] (or [-1, 1] m) where unlimited."""
    span = 1.0 if robot.prismatic[k] else math.pi
    lo = robot.lower[k] if math.isfinite(robot.lower[k]) else -span
    hi = robot.upper[k] if math.isfinite(robot.upper[k]) else span
    return float(lo), float(max(hi, lo + 1e-9))


def slider_value(robot: Robot, k: int, value: float) -> float:
    """Joint ``k`` at ``value`` on its slider: a continuous joint's angle wrapped into
    [-pi, pi] (the same pose, where clipping would show another), else clipped."""
    lo, hi = slider_range(robot, k)
    continuous = not robot.prismatic[k] and not (
        math.isfinite(robot.lower[k]) or math.isfinite(robot.upper[k])
    )
    if continuous and math.isfinite(value):
        value = math.remainder(value, 2 * math.pi)  # in [-pi, pi]
    return float(np.clip(value, lo, hi))


class Panel:
    """The panel of one viewer. The callbacks run on viser's threads: ``on_joints(q)`` when
    a slider moves, ``on_solver(name)``, ``on_prefer(name)``, ``on_ghosts(bool)``,
    ``on_position_only(bool)``, ``on_follow(bool)``. ``tip_errors``: tip -> its row, for
    several tips."""

    def __init__(
        self,
        gui: viser.GuiApi,
        robot: Robot,
        *,
        solver: str,
        position_only: bool,
        on_joints: Callable[[np.ndarray], None],
        on_solver: Callable[[str], None],
        on_ghosts: Callable[[bool], None],
        on_position_only: Callable[[bool], None],
        on_prefer: Callable[[object], None] | None = None,
        on_follow: Callable[[bool], None] | None = None,
        prefer: object = "none",
    ) -> None:
        self._robot = robot
        with gui.add_folder("IK answer"):
            self.message = gui.add_text("target", "none yet", disabled=True)
            self._fields = {attr: gui.add_text(label, "", disabled=True) for label, attr in FIELDS}
            self.tip_errors = {
                tip: gui.add_text(f"{tip} (m, rad)", "", disabled=True, hint="this tip's errors")
                for tip in (robot.tips if robot.several else ())
            }
            self.reason = gui.add_text("reason", "", multiline=True, disabled=True)
        with gui.add_folder("IK settings"):
            choices = robot.solver_choices()
            self.solver = gui.add_dropdown(
                "solver", choices, initial_value=solver if solver in choices else "auto"
            )
            # a preference of the viewer's own (not a name) is a choice of its own
            named = prefer is None or (isinstance(prefer, str) and prefer in PREFERENCES)
            self._given = None if named else prefer
            ranks: tuple[str, ...] = PREFERENCES if named else (*PREFERENCES, GIVEN)
            first = str(prefer or "none") if named else GIVEN
            self.prefer = gui.add_dropdown("prefer", ranks, initial_value=first)
            self.ghosts = gui.add_checkbox(
                "all solutions",
                False,
                hint="every solve_all answer as a ghost, by branch",
                visible=not robot.several,  # solve_all is one arm's
            )
            self.position_only = gui.add_checkbox(
                "position only", position_only, hint="drag targets the tip position only"
            )
            self.follow = gui.add_checkbox(
                "servo",
                False,
                hint="a dragged target is followed by the servo, within the joint, velocity "
                "and acceleration limits, instead of solved",
            )
        self.sliders = []
        with gui.add_folder("joints (FK)"):
            for k, name in enumerate(robot.joint_names):
                lo, hi = slider_range(robot, k)
                unit = "m" if robot.prismatic[k] else "rad"
                value = slider_value(robot, k, float(robot.middle[k]))
                self.sliders.append(
                    gui.add_slider(f"{name} ({unit})", lo, hi, (hi - lo) / 1000, value)
                )

        def from_user(callback):
            def handler(event) -> None:
                if event.client is not None:  # not a value the server set itself
                    callback(event.target.value)

            return handler

        for s in self.sliders:
            s.on_update(from_user(lambda _value: on_joints(self.slider_q())))
        self.solver.on_update(from_user(on_solver))
        if on_prefer is not None:  # GIVEN: the viewer's own preference back
            self.prefer.on_update(
                from_user(lambda name: on_prefer(self._given if name == GIVEN else name))
            )
        self.ghosts.on_update(from_user(on_ghosts))
        self.position_only.on_update(from_user(on_position_only))
        if on_follow is not None:
            self.follow.on_update(from_user(on_follow))

    def slider_q(self) -> np.ndarray:
        return np.array([s.value for s in self.sliders], dtype=float)

    # The ``[misc]`` ignores below: viser defines its handles' ``value`` setter apart from
    # the getter, which mypy then reads as a read-only property.

    def set_q(self, q: np.ndarray) -> None:
        """Move the sliders to ``q`` (``slider_value``: a continuous joint's angle wrapped,
        any other clipped into its range); the server's own changes call no callback
        (``from_user``)."""
        for k, s in enumerate(self.sliders):
            s.value = slider_value(self._robot, k, float(q[k]))  # type: ignore[misc]

    def show_result(self, r: IKResult, what: str, tol: tuple = (1e-6, 1e-6)) -> None:
        """Fill the answer rows from ``r``; ``what`` says what was solved."""
        self.message.value = what  # type: ignore[misc]
        for attr, handle in self._fields.items():
            value = r.extra.get("score") if attr == "score" else getattr(r, attr)
            handle.value = _text(attr, value)  # type: ignore[misc]
        results = self._robot.tip_results(r, tol)
        for tip, row in self.tip_errors.items():  # several tips (one: the rows above say it)
            if tip not in results:  # not solved by this answer: no numbers of an older one
                row.value = "no target"  # type: ignore[misc]
                continue
            ok, (pos, ori) = results[tip]
            text = f"{_text('position_error', pos)}, {_text('orientation_error', ori)}"
            row.value = text if ok else f"{text} (failed)"  # type: ignore[misc]
        self.reason.value = "" if r.success else r.reason  # type: ignore[misc]

    def refused_prefer(self, before: object, what: str, reason: str) -> None:
        """A preference chosen was refused: the dropdown back at ``before`` (the viewer's
        preference, None: "none"), and why in the panel."""
        named = before is None or (isinstance(before, str) and before in PREFERENCES)
        self.prefer.value = str(before or "none") if named else GIVEN  # type: ignore[misc]
        self.show_note(what, reason)

    def show_note(self, what: str, reason: str = "") -> None:
        """No answer to show (FK from the sliders, a waypoint, an error): say what instead."""
        self.message.value = what  # type: ignore[misc]
        for handle in [*self._fields.values(), *self.tip_errors.values()]:
            handle.value = ""  # type: ignore[misc]
        self.reason.value = reason  # type: ignore[misc]


def _text(attr: str, value: object) -> str:
    if value is None:
        return "-"
    if attr == "time":
        return f"{1e3 * float(value):.3f}"  # type: ignore[arg-type]
    if attr in ("position_error", "orientation_error", "score"):
        return f"{float(value):.3g}"  # type: ignore[arg-type]
    return str(getattr(value, "value", value))
