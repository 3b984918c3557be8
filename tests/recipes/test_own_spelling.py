"""A target spelling of a test's own, added by CONTRIBUTING's recipe: a class (an
``(xyz, rpy)`` dataclass) and a function from one of its objects to a form the parser
reads, registered with ``armik.targets.register_spelling`` and removed after the test.
Every route reads it, and every answer's tip is the pose the test computes from xyz and
rpy itself, by Pinocchio's FK."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.targets import register_spelling, unregister_spelling
from tests.conftest import arm as bundled


@dataclass(frozen=True)
class XyzRpy:
    """A pose as a position (m) and roll, pitch, yaw (rad) about the base's fixed axes."""

    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]


class Point(NamedTuple):
    """A position as a named tuple: a tuple the parser would otherwise read as numbers."""

    x: float
    y: float
    z: float


def _se3(t: XyzRpy) -> pin.SE3:
    return pin.SE3(pin.rpy.rpyToMatrix(*t.rpy), np.array(t.xyz, float))


@pytest.fixture
def spelled():
    register_spelling(XyzRpy, _se3)
    register_spelling(Point, lambda p: np.array([p.x, p.y, p.z]))
    try:
        yield
    finally:
        unregister_spelling(XyzRpy)
        unregister_spelling(Point)


def _as_xyzrpy(T: pin.SE3) -> XyzRpy:
    return XyzRpy(tuple(T.translation), tuple(pin.rpy.matrixToRpy(T.rotation)))


def _reached(arm, q, t: XyzRpy, frame=None) -> None:
    """The tip's placement by Pinocchio (``arm.fk``) is the pose written as xyz and rpy."""
    T = arm.fk(q) if frame is None else arm.fk(q, frame)
    np.testing.assert_allclose(T.translation, t.xyz, atol=1e-6)
    R = pin.rpy.rpyToMatrix(*t.rpy)
    assert np.linalg.norm(pin.log3(R.T @ T.rotation)) < 1e-6


def _poses(arm, n: int, seed: int) -> list[XyzRpy]:
    rng = np.random.default_rng(seed)
    return [_as_xyzrpy(arm.fk(arm.middle + rng.uniform(-0.4, 0.4, arm.dof))) for _ in range(n)]


def test_solve_and_solve_all(spelled):
    ur5 = bundled("ur5")
    for t in _poses(ur5, 3, 1):
        r = ur5.solve(t)
        assert r.success, r.reason
        _reached(ur5, r.q, t)
        found = ur5.solve_all(t)
        assert sum(a.success for a in found) >= 2
        for a in found:
            if a.success:
                _reached(ur5, a.q, t)
    p = ur5.fk(ur5.middle + 0.2).translation
    r = ur5.solve(Point(*p))
    assert r.success and np.allclose(ur5.fk(r.q).translation, p, atol=1e-6)


@pytest.mark.parametrize("workers", [1, 2])
def test_solve_batch(spelled, workers):
    ur5 = bundled("ur5")
    poses = _poses(ur5, 6, 2)
    res = ur5.solve_batch(poses, workers=workers, chunk_size=3)
    assert res.success.all()
    for i, t in enumerate(poses):
        _reached(ur5, res.q[i], t)
    points = [Point(*ur5.fk(ur5.middle + 0.1 * k).translation) for k in range(3)]
    res = ur5.solve_batch(points, workers=workers)
    assert res.success.all()
    for i, p in enumerate(points):
        np.testing.assert_allclose(ur5.fk(res.q[i]).translation, p, atol=1e-6)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_solve_path(spelled, plan):
    ur5 = bundled("ur5")
    q = np.array([0.4, -1.0, 1.2, -0.3, 1.1, -0.5])
    T = ur5.fk(q)
    line = [_as_xyzrpy(pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0])) for k in range(4)]
    path = ur5.solve_path(line, q, plan=plan)
    assert path.success.all()
    for i, t in enumerate(line):
        _reached(ur5, path.q[i], t)


def test_several_tips(spelled):
    robot = armik.load("panda", tips=["panda_hand", "panda_link5"])
    q = robot.middle + 0.1
    hand = _as_xyzrpy(robot.fk(q, "panda_hand"))
    elbow = Point(*robot.fk(q, "panda_link5").translation)
    r = robot.solve({"panda_hand": hand, "panda_link5": elbow}, q0=robot.middle)
    assert r.success, r.reason
    _reached(robot, r.q, hand, "panda_hand")
    np.testing.assert_allclose(robot.fk(r.q, "panda_link5").translation, elbow, atol=1e-6)


def test_unregistered_it_is_refused_by_name(spelled):
    ur5 = bundled("ur5")
    t = _poses(ur5, 1, 3)[0]
    unregister_spelling(XyzRpy)
    try:
        with pytest.raises(armik.TargetError, match="XyzRpy"):
            ur5.solve(t)
    finally:
        register_spelling(XyzRpy, _se3)


def test_bad_spellings_are_named():
    with pytest.raises(armik.TargetError, match="reads itself"):
        register_spelling(tuple, lambda v: v)
    with pytest.raises(armik.TargetError, match="a class"):
        register_spelling("XyzRpy", _se3)  # type: ignore[arg-type]
    with pytest.raises(armik.TargetError, match="has no target spelling"):
        unregister_spelling(XyzRpy)
    register_spelling(XyzRpy, lambda t: (t.xyz, t.rpy))  # rpy is no quaternion
    try:
        with pytest.raises(armik.TargetError, match="has a target spelling already"):
            register_spelling(XyzRpy, _se3)
        ur5 = bundled("ur5")
        bad = XyzRpy((0.3, 0.1, 0.4), (0.0, 0.1, 0.2))
        with pytest.raises(armik.TargetError, match="spelling of XyzRpy gave"):
            ur5.solve(bad)
        with pytest.raises(armik.TargetError, match="target 1: the target spelling of XyzRpy"):
            ur5.solve_batch([_se3(bad), bad])
        with pytest.raises(armik.TargetError, match="one XyzRpy"):
            ur5.solve_batch(bad)
    finally:
        unregister_spelling(XyzRpy)
    register_spelling(XyzRpy, lambda t: 1 / 0)
    try:
        with pytest.raises(armik.TargetError, match="failed on XyzRpy.*ZeroDivisionError"):
            bundled("ur5").solve(XyzRpy((0.3, 0.1, 0.4), (0.0, 0.0, 0.0)))
    finally:
        unregister_spelling(XyzRpy)
