"""The solver registry: listing, auto choice, and errors that say what exists."""

from __future__ import annotations

import pytest

import armik
from armik import SolverError
from armik.solvers import registry

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
