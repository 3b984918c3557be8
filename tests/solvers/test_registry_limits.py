"""What ``SolverSpec.enforces_limits`` does: "auto" takes, among the solvers that apply to
an arm with a limited joint, one whose steps keep the joint limits before one that does
not, whatever their priorities; on an arm without limits priority alone decides; by name
the solver runs all the same, and the verdict checks the limits whatever it declares."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import armik
from armik.solvers import registry
from armik.solvers.answers import Answers
from armik.solvers.registry import SolverSpec
from armik.status import Status

from ..conftest import arm as bundled

NAME = "toy2r_unlimited"
ARM = "planar_2link"  # two revolute joints about z within +-pi, l1 = 1.0 m, l2 = 0.8 m
ROOT = Path(__file__).resolve().parents[2]


def _why_not(arm, _target=None, _opts=None):
    return None if arm.name == ARM else f"arm {arm.name!r} is not {ARM!r}"


def _run(arm, target, q0, opts, every):
    """The elbow-down branch of the position, joint 1 turned by 2 pi beyond the limits: the
    same pose, an answer outside them, claimed converged (it keeps no limits)."""
    x, y = float(target.position[0]), float(target.position[1])
    c = (x * x + y * y - 1.0 - 0.64) / 1.6
    q2 = math.acos(min(1.0, max(-1.0, c)))
    q1 = math.atan2(y, x) - math.atan2(0.8 * math.sin(q2), 1.0 + 0.8 * math.cos(q2))
    q1 += 2 * math.pi if q1 < 0 else -2 * math.pi  # beyond +-pi either way
    return Answers.of(np.array([[q1, q2]]), [Status.CONVERGED], ["toy, no limits"], 2)


@pytest.fixture
def unlimited_family():
    spec = registry.register(
        SolverSpec(
            name=NAME,
            kind="analytic",
            enforces_limits=False,
            priority=1000,  # above planar2r (100)
            why_not=_why_not,
            run=_run,
            summary="a test's closed form that keeps no joint limits",
            solves=frozenset({"position_only"}),
        )
    )
    try:
        yield spec
    finally:
        registry.unregister(NAME)


def _continuous() -> armik.Arm:
    """The planar 2-link arm with both joints continuous: no limit to keep (same name)."""
    text = (ROOT / "robots" / f"{ARM}.urdf").read_text().replace('"revolute"', '"continuous"')
    return armik.load_string(text)


def test_auto_takes_a_solver_keeping_the_limits_first(unlimited_family):
    arm = bundled(ARM)
    q = np.array([0.4, 1.1])
    p = arm.fk(q).translation
    assert registry.choose("auto", arm.kinematics).name == "planar2r"
    r = arm.solve(p, q0=q)
    assert r.success and r.solver == "planar2r"
    np.testing.assert_allclose(arm.fk(r.q).translation, p, atol=1e-9)
    assert arm.within_limits(r.q)
    # by name it runs, and its answer beyond the limits is no success (the verdict)
    named = arm.solve(p, q0=q, solver=NAME)
    assert named.solver == NAME and not named.success
    assert named.status == Status.JOINT_LIMITS


def test_without_limits_priority_decides(unlimited_family):
    arm = _continuous()
    assert arm.name == ARM and len(arm.kinematics.bounded) == 0
    q = np.array([0.4, 1.1])
    p = arm.fk(q).translation
    r = arm.solve(p, q0=q)
    assert r.solver == NAME and r.success
    np.testing.assert_allclose(arm.fk(r.q).translation, p, atol=1e-9)


def test_the_bundled_solvers_all_keep_the_limits():
    """Every built-in solver declares it keeps the limits: the order is their priorities'
    (no bundled arm's choice depends on the declaration)."""
    assert all(registry.get(name).enforces_limits for name in armik.solvers())


@pytest.mark.parametrize("robot", ["panda", "kinova", "scara"])
def test_clik_keeps_what_it_declares(robot):
    """``clik`` clips every step into the limits: each answer, a success or not, within
    the limits, joint 1 narrowed to (-1, 1)."""
    arm = bundled(robot)
    narrow = arm.with_limits({arm.joint_names[0]: (-1.0, 1.0)})
    for s in range(6):
        T = arm.fk(arm.random_q(s))
        r = narrow.solve(T, solver="clik", q0=narrow.random_q(100 + s), max_iterations=100)
        assert narrow.within_limits(r.q), (s, r.q)
