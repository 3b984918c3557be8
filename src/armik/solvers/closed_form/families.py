"""The closed-form families, each classified by its own file: what ``armik info`` prints.

A new family adds its line here and its classifier in its own file.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from armik.model.geometry import axis_lines
from armik.model.mimic import reason as mimic_reason
from armik.solvers.closed_form import (
    elimination_6r,
    general_6r,
    planar2r,
    spherical_general,
    spherical_shoulder,
    spherical_wrist,
    srs,
    swept_7r,
    three_parallel,
    three_parallel_general,
    two_intersecting,
    two_parallel,
)

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel

FAMILIES = {
    "planar": planar2r.classify,
    "spherical_wrist": spherical_wrist.classify,
    "three_parallel": three_parallel.classify,
    "spherical_general": spherical_general.classify,
    "three_parallel_general": three_parallel_general.classify,
    "spherical_shoulder": spherical_shoulder.classify,
    "two_parallel": two_parallel.classify,
    "two_intersecting": two_intersecting.classify,
    "srs": srs.classify,
    "swept_7r": swept_7r.classify,
    "elimination_6r": elimination_6r.classify,
    "general_6r": general_6r.classify,
}


def classify(arm: ArmModel) -> dict[str, object]:
    """Each family name -> its geometry (a ``Plane``, ``Chain6R``, ``Srs`` or ``Swept``) or the
    reason it does not apply (a string)."""
    if arm.mimics:
        return {name: mimic_reason(arm.mimics) for name in FAMILIES}
    ax = axis_lines(arm)
    return {name: classifier(arm, ax) for name, classifier in FAMILIES.items()}
