"""An aim on several tips (``armik.Arms``) as on one arm: an option that frees the rotation
an aim measures (``position_only=True``, a rotation weight of 0) is refused by
``targets.aim.refuse_freed`` on every route, whether the aim is a keyword cone or an
``armik.Axis``/``armik.LookAt`` in a tip's task list or a flat list naming frames, and an
``Axis`` exactly along a direction (lowered to a pose whose spin is free, which carries no
aim) is no exception; an answer outside a tip's aim is never called a success."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from tests.test_arms import dual_irb120

FREEING = [{"position_only": True}, {"weights": (1, 1, 1, 1, 0, 1)}]


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def _routes(robot, targets: dict, q0, options: dict):
    """Each route of ``robot`` called on ``targets`` (one per tip; twice per tip for the
    batch and the path)."""
    twice = {tip: [t, t] for tip, t in targets.items()}
    yield "solve", lambda: robot.solve(targets, q0=q0, **options)
    yield "solve_all", lambda: robot.solve_all(targets, q0=q0, **options)[0]
    yield "solve_batch", lambda: robot.solve_batch(twice, q0=q0, progress=False, **options)
    yield "solve_path", lambda: robot.solve_path(twice, q0, **options)


@pytest.mark.parametrize("within", [0.0, 0.1])
@pytest.mark.parametrize("freeing", FREEING)
def test_an_option_that_frees_an_axis_is_refused_on_every_route(cell, within, freeing):
    """``[Position, Axis]`` on one tip, with ``position_only`` or a rotation weight of 0:
    refused by ``Arm`` and by ``Arms`` on every route, also exactly along the direction
    (``within=0``: lowered to a pose whose spin is free), which took the option and called
    an answer whose axis pointed anywhere a success."""
    q = cell.random_q(np.random.default_rng(3))
    T = cell.fk(q, "l_tool0")
    tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], within)]
    targets = {"l_tool0": tasks, "r_tool0": cell.fk(q, "r_tool0").translation}
    name = next(iter(freeing))
    arm = cell.chain("l_tool0")
    single = [
        lambda: arm.solve(tasks, **freeing),
        lambda: arm.solve_all(tasks, **freeing),
        lambda: arm.solve_batch([tasks, tasks], progress=False, **freeing),
        lambda: arm.solve_path([tasks, tasks], q[:6], **freeing),
    ]
    for call in single:
        with pytest.raises(armik.OptionError, match="frees a rotation the aim measures") as e:
            call()
        assert e.value.option == name
    for route, call in _routes(cell, targets, q, freeing):
        with pytest.raises(armik.OptionError, match="frees a rotation the aim measures") as e:
            call()
        assert e.value.option == name, route
    flat = [
        armik.Position(T.translation, frame="l_tool0"),
        armik.Axis((0, 0, 1), T.rotation[:, 2], within, frame="l_tool0"),
        armik.Position(targets["r_tool0"], frame="r_tool0"),
    ]
    for call in (lambda: cell.solve(flat, **freeing), lambda: cell.solve_all(flat, **freeing)):
        with pytest.raises(armik.OptionError, match="frees a rotation the aim measures"):
            call()
    # a rotation weight that holds the axis is taken, the answer's axis along it
    r = cell.solve(targets, q0=q, weights=(1, 1, 1, 0.5, 0.5, 0.5))
    assert r.success, r.reason
    axis = cell.fk(r.q, "l_tool0").rotation[:, 2]
    assert np.arccos(min(axis @ T.rotation[:, 2], 1.0)) <= within + 1e-6


@pytest.mark.parametrize("freeing", FREEING)
def test_a_keyword_aim_on_several_tips_refuses_what_frees_it(cell, freeing):
    """``cone=`` with ``toward=`` on every tip's position: the same refusal on each route."""
    q = cell.random_q(np.random.default_rng(4))
    targets = {tip: cell.fk(q, tip).translation for tip in cell.tips}
    aim = {"cone": (0, 0, 1, 0.1), "toward": (0, 0, -1)}
    for route, call in _routes(cell, targets, q, {**aim, **freeing}):
        with pytest.raises(armik.OptionError, match="frees a rotation the aim measures") as e:
            call()
        assert e.value.option == next(iter(freeing)), route


def test_an_answer_outside_a_tips_aim_is_refused_on_every_route(cell, aimless):
    """A solver that ignores the aim claims a seed whose tip axis is pi from it: on every
    route, with an ``Axis`` or a ``LookAt`` in a tip's task list or a keyword cone, the tip
    is not called solved and the reason names the cone."""
    q = cell.random_q(np.random.default_rng(2))
    T = {tip: cell.fk(q, tip) for tip in cell.tips}
    left, right = cell.tips
    away = -T[left].rotation[:, 2]
    p = T[left].translation
    for target, options in (
        ([armik.Position(p), armik.Axis((0, 0, 1), away, 0.1)], {}),
        ([armik.Position(p), armik.LookAt((0, 0, 1), p + 0.4 * away, 0.1)], {}),
        (p, {"cone": (0, 0, 1, 0.1), "toward": tuple(away)}),
    ):
        targets = {left: target, right: T[right]}
        for route, call in _routes(cell, targets, q, {"solver": "aimless", **options}):
            r = call()
            if route in ("solve", "solve_all"):
                assert not r.success and f"{left}: not_converged" in r.reason, route
                assert "outside its cone of 0.1 rad" in r.reason, route
            else:
                assert not r.success.any(), route
                assert "outside its cone of 0.1 rad" in r.reason(0), route
