"""A user's target is parsed once per solve, on every route: the stages below the door
take the parsed ``Target`` (``armik.targets.pose.parsed``), never the raw value again."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
import armik.arms  # noqa: F401  (imported before the fixture patches its parser)
import armik.targets.pose as pose_module
from tests.conftest import arm as bundled


@pytest.fixture
def parses(monkeypatch):
    """The values ``parse_target`` parsed (not those it was handed parsed already), and
    the several-tip targets ``parse_by_tip`` parsed, from every armik module that calls
    them."""
    seen: list = []
    original = pose_module.parse_target
    original_by_tip = pose_module.parse_by_tip

    def counting(value, arm=None):
        if type(value) is not pose_module.Target:
            seen.append(type(value).__name__)
        return original(value, arm)

    def counting_by_tip(targets, arms):
        if any(type(v) is not pose_module.Target for v in targets.values()):
            seen.append(f"tips {list(targets)}")
        return original_by_tip(targets, arms)

    for module in list(sys.modules.values()):
        name = getattr(module, "__name__", "") or ""
        if name.startswith("armik") and getattr(module, "parse_target", None) is original:
            monkeypatch.setattr(module, "parse_target", counting)
        if name.startswith("armik") and getattr(module, "parse_by_tip", None) is original_by_tip:
            monkeypatch.setattr(module, "parse_by_tip", counting_by_tip)
    return seen


def _pose(name: str):
    a = bundled(name)
    return a, a.fk(a.middle + 0.1)


@pytest.mark.parametrize(
    "name, options",
    [
        ("ur5", {}),
        ("ur5", {"bounds": (0.01,) * 3 + (0.1,) * 3}),
        ("panda", {"obstacles": [armik.Sphere(0.05, (2.0, 2.0, 2.0))]}),
        ("panda", {"prefer": "manipulability", "iteration_budget": 300}),
        ("panda", {"hold": {"panda_joint7": 0.3}}),
        ("panda", {"weights": (1, 1, 1, 1, 1, 0)}),
    ],
    ids=str,
)
def test_a_solve_parses_its_target_once(parses, name, options):
    a, T = _pose(name)
    for target in (T, (T.translation, pin.Quaternion(T.rotation).coeffs())):
        parses.clear()
        a.solve(target, **options)
        assert len(parses) <= 1, parses


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_solve_all_parses_once(parses, name):
    a, T = _pose(name)
    a.solve_all(T)
    assert len(parses) <= 1, parses


@pytest.mark.parametrize("name", ["ur5", "panda"])  # the Panda's global plan: swept rungs
def test_a_path_parses_each_waypoint_once_at_most(parses, name):
    a, T = _pose(name)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    for plan in ("follow", "global"):
        parses.clear()
        a.solve_path(line, a.middle + 0.1, plan=plan)
        assert len(parses) <= len(line), (plan, parses)


def test_a_batch_parses_each_target_once_at_most(parses):
    a = bundled("panda")
    T = a.fk_batch(a.random_q(0, n=4))
    a.solve_batch(T, workers=1, progress=False)
    a.solve_batch(list(T), workers=1, progress=False)
    assert len(parses) <= len(T), parses


def _talos() -> armik.Arms:
    """TALOS's two hands, whose chains share the torso's two joints."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


@pytest.mark.parametrize("robot", ["panda, two tips", "talos, shared torso"])
def test_several_tips_parse_their_targets_once(parses, robot):
    """The request's target, one pose per tip, is parsed in one call (the chains apart, and
    over the shared torso: one task per tip on the union), in each form a tip's pose takes."""
    if robot.startswith("panda"):
        arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    else:
        arms = _talos()
    q = arms.middle + 0.1
    placed = {tip: arms.fk(q, tip) for tip in arms.tips}
    spelled = {t: (T.translation, pin.Quaternion(T.rotation).coeffs()) for t, T in placed.items()}
    for targets in (placed, spelled):
        parses.clear()
        r = arms.solve(targets, iteration_budget=3000)
        assert r.success, r.reason
        assert len(parses) <= 1, parses


def test_a_tips_bad_target_is_named_by_its_tip():
    arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    with pytest.raises(armik.TargetError, match="tip 'panda_link5'.*NaN"):
        arms.solve({"panda_hand": arms.fk(arms.middle, "panda_hand"), "panda_link5": [np.nan] * 3})
