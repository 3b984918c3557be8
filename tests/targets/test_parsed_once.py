"""A user's target is parsed once per solve, on every route: the stages below the door
take the parsed ``Target`` (``armik.targets.pose.parsed``), never the raw value again."""

from __future__ import annotations

import sys

import pinocchio as pin
import pytest

import armik
import armik.targets.pose as pose_module
from tests.conftest import arm as bundled


@pytest.fixture
def parses(monkeypatch):
    """The values ``parse_target`` parsed (not those it was handed parsed already), from
    every armik module that calls it."""
    seen: list = []
    original = pose_module.parse_target

    def counting(value, arm=None):
        if type(value) is not pose_module.Target:
            seen.append(type(value).__name__)
        return original(value, arm)

    for module in list(sys.modules.values()):
        name = getattr(module, "__name__", "") or ""
        if name.startswith("armik") and getattr(module, "parse_target", None) is original:
            monkeypatch.setattr(module, "parse_target", counting)
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


def test_several_tips_parse_each_tips_target_once(parses):
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    q = robot.middle + 0.1
    targets = {tip: robot.fk(q, tip) for tip in robot.tips}
    robot.solve(targets)
    assert len(parses) <= len(targets), parses
