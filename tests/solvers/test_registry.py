"""The solver registry: listing, auto choice, and errors that say what exists."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik import SolverError
from armik.options import Options
from armik.solve.read import options as options_of
from armik.solvers import registry
from armik.targets.aim import aim_of
from armik.targets.pose import Target

from ..conftest import arm, model


def test_registered_solvers():
    ranked = [s for s in armik.solvers() if s in ("planar2r", "dls", "qp")]
    assert ranked == ["planar2r", "dls", "qp"] and armik.solvers()[0] == "planar2r"
    assert "clik" in armik.solvers()
    spec = registry.get("planar2r")
    assert spec.kind == "analytic" and spec.enforces_limits
    assert registry.get("dls").kind == "numeric"


def test_auto_picks_specialist_or_numeric():
    assert arm("planar_2link").solve([1.2, 0.5]).solver == "planar2r"
    assert registry.choose("auto", model("planar_3link")).name == "dls"
    assert registry.choose("auto", model("panda")).name == "dls"


def test_unknown_solver_lists_registered():
    with pytest.raises(SolverError, match="unknown solver 'newton'.*'planar2r'.*'dls'"):
        arm("panda").solve([0.3, 0.0, 0.5], solver="newton")


def test_specialist_that_does_not_apply_says_which_check():
    with pytest.raises(SolverError, match="planar2r.*7 joints.*exactly 2"):
        arm("panda").solve([0.3, 0.0, 0.5], solver="planar2r")
    with pytest.raises(SolverError, match="not parallel|prismatic|joints"):
        arm("scara").solve([0.3, 0.0, 0.2], solver="planar2r")


def test_named_numeric_solver_on_planar_arm():
    r = arm("planar_2link").solve([1.2, 0.5], solver="dls", q0=[0.0, 1.0])
    assert r.solver == "dls" and r.success


def test_register_refuses_duplicates():
    with pytest.raises(ValueError, match="taken"):
        registry.register(registry.get("dls"))


@pytest.mark.parametrize(
    "options, name, words",
    [
        ({"weights": (1, 1, 1, 0, 0, 0)}, "spherical", "per-axis weights are for the numeric"),
        ({"bounds": (0.01,) * 6}, "three_parallel", "bounds are for the numeric solvers (dls, qp)"),
        ({"position_only": True}, "three_parallel", "position_only is for the numeric"),
        ({"cone": (0, 0, 1, 0.1)}, "clik", "a cone around an axis is for the numeric solvers"),
        ({"bounds": (0, 0, 0, 0, 0, 1)}, "three_parallel", "spin_joint"),
        ({}, "spin", "spin needs bounds that free one rotation component"),
    ],
)
def test_what_a_solver_does_not_declare_is_refused_by_the_registry(options, name, words):
    """A solver's ``solves`` and ``needs`` say which forms of a request beyond an exact pose
    it takes: the registry refuses the others in its words, whatever its ``why_not`` says."""
    ur5 = model("ur5")
    spec = registry.get(name)
    asked = options_of(options)  # a cone is the target's aim
    aim = aim_of(options.get("cone"))
    target = None if aim is None else Target(np.zeros(3), np.eye(3), aim=aim)
    assert asked.forms(aim is not None) <= set(registry.FORMS)
    why = registry.why_not(name, ur5, target, asked)
    assert why is not None and words in why
    assert spec.why_not(ur5, None, asked) is None or name == "spherical"  # the arm's own: none


def test_what_auto_takes_follows_the_forms_asked():
    ur5 = model("ur5")
    plain = registry.choose("auto", ur5, None, Options())
    weighted = registry.choose("auto", ur5, None, Options(weights=(1.0,) * 6))
    spun = registry.choose("auto", ur5, None, Options(bounds=(0, 0, 0, 0, 0, 3.2)))
    assert plain.kind == "analytic" and not plain.solves
    assert weighted.kind == "numeric" and "weights" in weighted.solves
    assert spun.name == "spin_joint" and spun.needs == {"spin"}  # the UR5 wrist turns the tool
