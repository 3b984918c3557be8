"""The geometry the swept 7R closed form (``swept_7r``) sweeps over: a 7R arm read as joints
6 to 1 from the tip (a 6R chain in the spherical-wrist class) and joint 7's axis line in
the tip frame at q = 0, or the reason an arm is not in the class; derived once per arm."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.geometry import Axes, axis_lines
from armik.solvers.closed_form import sixr
from armik.solvers.closed_form import spherical_wrist as spherical


@dataclass(frozen=True)
class Swept:
    """A 7R arm read as joints 6 to 1 from the tip (a 6R chain) and joint 7's axis line in
    the tip frame at q = 0."""

    geo: sixr.Chain6R
    variant: int  # spherical.kernel's: 0 axes 2, 3 parallel, 1 axes 1, 2 meeting
    c: np.ndarray  # a point on joint 7's axis (tip frame at q = 0), m
    u: np.ndarray  # joint 7's unit axis (tip frame)

    @property
    def description(self) -> str:
        return f"joint 7 held, joints 6 to 1 read from the tip: {self.geo.description}"


def classify(arm: ArmModel, ax: Axes | None = None) -> Swept | str:
    """The geometry the swept solver sweeps over (see the module), or the reason this 7R arm is not
    in the class: joint 7 held, joints 6 to 1 read from the tip form a spherical wrist."""
    why = sixr.not_revolute(arm, 7)
    if why is not None:
        return why
    ax = ax or axis_lines(arm)
    Rt = ax.tip_rotation.T
    t = ax.tip_position
    order = (5, 4, 3, 2, 1, 0)  # joints 6 to 1
    reversed_axes = Axes(
        np.array([Rt @ (ax.points[j] - t) for j in order]),
        np.array([-(Rt @ ax.directions[j]) for j in order]),
        np.ones(6, dtype=bool),
        -(Rt @ t),
        Rt.copy(),
    )
    geo = spherical.classify_axes(reversed_axes)
    if isinstance(geo, str):
        return f"with joint 7 held, joints 6 to 1 from the tip are not a spherical wrist: {geo}"
    variant = 0 if geo.variant == "parallel_23" else 1
    return Swept(geo, variant, Rt @ (ax.points[6] - t), Rt @ ax.directions[6])
