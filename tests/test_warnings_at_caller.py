"""Every ``ArmikWarning`` names the user's line, whatever route inside armik found it: a
fixed ``stacklevel`` named one of armik's own files on every route but the one it was
counted on (``solve(p, q0=...)`` said ``armik/solve/stages.py``)."""

from __future__ import annotations

import warnings

import pytest

import armik
from tests.conftest import arm, two_link_urdf, write_urdf

UR5_Q0_OUTSIDE = [0.0, -0.5, 4.0, 0.0, 0.0, 0.0]  # the elbow beyond its 3.14 rad limit


def _said(call) -> list[warnings.WarningMessage]:
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        call()
    armik_said = [w for w in said if issubclass(w.category, armik.ArmikWarning)]
    assert armik_said, "no ArmikWarning"
    return armik_said


ROUTES = {
    "solve a position": lambda ur5, T: ur5.solve(T.translation, q0=UR5_Q0_OUTSIDE),
    "solve a pose": lambda ur5, T: ur5.solve(T, q0=UR5_Q0_OUTSIDE),
    "solve by dls": lambda ur5, T: ur5.solve(T, q0=UR5_Q0_OUTSIDE, solver="dls"),
    "solve_all": lambda ur5, T: ur5.solve_all(T, q0=UR5_Q0_OUTSIDE),
    "solve_batch": lambda ur5, T: ur5.solve_batch([T, T], q0=UR5_Q0_OUTSIDE, workers=1),
    "solve_path": lambda ur5, T: ur5.solve_path([T, T], UR5_Q0_OUTSIDE),
}


@pytest.mark.parametrize("route", sorted(ROUTES))
def test_a_clipped_q0_is_said_at_the_callers_line(route):
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.1)
    for w in _said(lambda: ROUTES[route](ur5, T)):
        assert w.filename == __file__, (w.filename, str(w.message))


def test_a_urdf_read_with_a_note_is_said_at_the_callers_line(tmp_path):
    path = write_urdf(tmp_path, two_link_urdf(axis="0 0 2"))  # a non-unit axis: normalised
    for w in _said(lambda: armik.load(str(path))):
        assert w.filename == __file__, (w.filename, str(w.message))
    for w in _said(lambda: armik.load_string(two_link_urdf(axis="0 0 2"))):
        assert w.filename == __file__, (w.filename, str(w.message))


def test_a_clipped_q0_over_several_tips_is_said_at_the_callers_line():
    from tests.test_arms import talos

    robot = talos()
    q = robot.random_q(3)
    T = {t: robot.fk(q, t) for t in robot.tips}
    outside = q.copy()
    outside[0] = robot.upper[0] + 1.0
    for call in (
        lambda: robot.solve(T, q0=outside),
        lambda: robot.solve_batch({t: [T[t], T[t]] for t in T}, q0=outside, workers=1),
    ):
        for w in _said(call):
            assert w.filename == __file__, (w.filename, str(w.message))


def test_a_path_held_row_by_row_says_a_clipped_q0_once():
    # the path by rows read its q0 three times (its first seed, the move from the start,
    # the turns), and said the clipped q0 each time
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.1)
    P = [T.translation, T.translation + [0.0, 0.01, 0.0]]
    said = _said(lambda: ur5.solve_path(P, UR5_Q0_OUTSIDE, hold={"wrist_3_joint": None}))
    assert len(said) == 1, [str(w.message) for w in said]
    assert said[0].filename == __file__


@pytest.mark.parametrize("score", ["nearest", "limits", "manipulability"])
@pytest.mark.parametrize(("name", "every"), [("ur5", False), ("ur5", True), ("panda", False)])
def test_a_preference_says_a_clipped_q0_once(score, name, every):
    # the rank stage read q0, and each stage under it (the search's load, its run, the
    # descents near q0) read it again: said two to four times
    a = arm(name)
    T = a.fk(a.middle + 0.1)
    q0 = a.middle.copy()
    q0[2] = 4.0  # beyond joint 3's limits on both arms
    call = a.solve_all if every else a.solve
    said = _said(lambda: call(T, q0=q0, prefer=score))
    assert len(said) == 1, [str(w.message) for w in said]
    assert said[0].filename == __file__
    if name == "panda":  # a position's search too
        assert len(_said(lambda: a.solve(T.translation, q0=q0, prefer=score))) == 1
