"""solve_path: in order, warm-started, and never a silent jump."""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError
from armik.model.catalogue import entry

from ..conftest import arm


@functools.cache
def ur3() -> armik.Arm:
    """The UR3 of example-robot-data (not in the catalogue), next to the catalogue's UR5."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ur3 = entry("ur5").urdf_path().parent / "ur3_robot.urdf"
        return armik.load(str(ur3), tip="tool0")


def _moves(q0: np.ndarray, r) -> np.ndarray:
    """How far each answer moved from the one before it (the first: from q0), max over
    joints, counting only the answers the path went on from."""
    prev, out = q0, []
    for i in range(len(r)):
        if r.success[i] or r.status[i] == "discontinuous":
            out.append(np.abs(r.q[i] - prev).max())
            prev = r.q[i]
        else:
            out.append(0.0)
    return np.array(out)


def _line(a: armik.Arm, q: np.ndarray, direction, length: float, n: int) -> list[pin.SE3]:
    T0 = a.fk(q)
    d = np.asarray(direction, float)
    return [pin.SE3(T0.rotation, T0.translation + s * d) for s in np.linspace(0, length, n)]


def _check_no_silent_jump(q0, r, step):
    moves = _moves(q0, r)
    silent = r.success & (moves > step + 1e-12)
    assert not silent.any(), f"silent jumps at {np.flatnonzero(silent)}: {moves[silent]}"


@pytest.mark.parametrize("name, length", [("ur3", 0.2), ("ur5", 0.4)])
def test_line_into_the_elbow_singularity_reports_the_jump(name, length):
    a = ur3() if name == "ur3" else arm(name)
    q0 = np.array([0.3, -1.2, 0.1, -1.5, -1.2, 0.4])  # elbow nearly stretched
    poses = _line(a, q0, (0, -1, 0), length, 41)
    # A loop of solve, each from the previous answer, flips branch silently here...
    q, loop_moves = q0, []
    for T in poses:
        s = a.solve(T, q0=q)
        assert s.success
        loop_moves.append(np.abs(s.q - q).max())
        q = np.array(s.q)
    assert max(loop_moves) > 2.0
    # ... and the path reports it.
    r = a.solve_path(poses, q0, max_joint_step=0.5)
    _check_no_silent_jump(q0, r, 0.5)
    flagged = np.flatnonzero(r.status == "discontinuous")
    assert len(flagged) >= 1
    i = flagged[0]
    assert not r.success[i] and "jump" in r.reason(i) and "max_joint_step 0.5" in r.reason(i)
    assert r[i].position_error <= 1e-6  # the answer is a verified pose, but not a smooth one
    assert r.success.sum() + len(flagged) == len(poses)


@pytest.mark.parametrize("name", ["ur5", "ur3"])
def test_line_through_the_wrist_singularity_is_never_silent(name):
    a = ur3() if name == "ur3" else arm(name)
    q0 = np.array([0.3, -1.2, 1.2, -1.5, 0.05, 0.4])  # wrist 2 near zero: wrist singular
    poses = _line(a, q0, (0, 1, 0), 0.06, 25)
    r = a.solve_path(poses, q0, max_joint_step=0.3)
    _check_no_silent_jump(q0, r, 0.3)
    ok = r.success | (r.status == "discontinuous")
    assert ok.all(), r.counts()


def _spin(a: armik.Arm, q: np.ndarray, turns: float, n: int) -> list[pin.SE3]:
    """The tool turned about the last joint's axis by ``turns`` full turns."""
    out = []
    for angle in np.linspace(0.0, 2 * np.pi * turns, n):
        qq = q.copy()
        qq[-1] += angle
        out.append(a.fk(qq))
    return out


def test_tool_spin_unwraps_a_two_pi_joint():
    a = arm("ur5")  # wrist_3 in [-2 pi, 2 pi]
    q0 = np.array([0.3, -1.2, 1.2, -1.5, -1.2, -np.pi + 0.1])
    r = a.solve_path(_spin(a, q0, 1.0, 73), q0)
    assert r.success.all(), r.counts()
    assert _moves(q0, r).max() < 0.1
    assert r.q[-1, -1] == pytest.approx(q0[-1] + 2 * np.pi, abs=1e-6)  # turned on, no snap


def test_tool_spin_beyond_the_limit_is_reported_once():
    a = arm("ur5")
    q0 = np.array([0.3, -1.2, 1.2, -1.5, -1.2, 0.0])
    r = a.solve_path(_spin(a, q0, 2.0, 145), q0)  # 720 degrees: wrist_3 stops at 2 pi
    _check_no_silent_jump(q0, r, 0.5)
    flagged = np.flatnonzero(r.status == "discontinuous")
    assert len(flagged) == 1 and "wrist_3_joint" in r.reason(flagged[0])
    assert r.success.sum() == len(r) - 1


def test_tool_spin_on_continuous_joints_turns_on():
    a = arm("kinova")  # last joint continuous
    assert a.joint_types[-1] == "continuous"
    q0 = a.middle.copy()
    q0[[1, 2, 4]] += 0.4
    r = a.solve_path(_spin(a, q0, 2.0, 97), q0)
    assert r.success.all(), r.counts()
    assert _moves(q0, r).max() < 0.3
    assert r.q[-1, -1] == pytest.approx(q0[-1] + 4 * np.pi, abs=1e-6)


def test_unreachable_waypoint_keeps_its_status_and_the_path_goes_on():
    a = arm("ur5")
    q0 = np.array([0.3, -1.2, 1.2, -1.5, -1.2, 0.4])
    poses = _line(a, q0, (0, 0, 0.01), 0.02, 3)
    poses.insert(1, pin.SE3(np.eye(3), np.array([3.0, 0, 0])))
    r = a.solve_path(poses, q0)
    assert list(r.status) == ["converged", "unreachable", "converged", "converged"]
    assert _moves(q0, r).max() < 0.1


def test_first_waypoint_far_from_q0_is_reported():
    a = arm("ur5")
    q_far = np.array([2.0, -1.2, 1.2, -1.5, -1.2, 0.4])
    q0 = np.array([-1.0, -1.2, 1.2, -1.5, -1.2, 0.4])
    r = a.solve_path([a.fk(q_far)], q0, max_joint_step=0.5)
    assert r.status[0] == "discontinuous" and "q0" in r.reason(0)


def test_max_joint_step_checks():
    a = arm("ur5")
    q0 = a.middle
    for bad in (0.0, -1, np.nan, [0.1, 0.2], "x", True, [1.0, 1.0, 1.0, 1.0, 1.0, True]):
        with pytest.raises(OptionError, match="max_joint_step"):
            a.solve_path([a.fk(q0)], q0, max_joint_step=bad)
        for plan in ("global",) if bad is True else ():
            with pytest.raises(OptionError, match="max_joint_step"):
                a.solve_path([a.fk(q0)], q0, max_joint_step=bad, plan=plan)
    r = a.solve_path([a.fk(q0)], q0, max_joint_step=np.full(6, 0.2))
    assert r.success.all()


def _few(a: armik.Arm, seed: int, planar: bool) -> list:
    """Three waypoints 2 mm apart about a random configuration (positions on the planar
    arm, poses on the others)."""
    T = a.fk(a.random_q(seed))
    if planar:
        return [T.translation + [0.002 * k, 0.0, 0.0] for k in range(3)]
    return [pin.SE3(T.rotation, T.translation + [0.0, 0.002 * k, 0.0]) for k in range(3)]


@pytest.mark.parametrize("name", ["ur5", "panda", "planar_2link"])
def test_without_q0_the_first_waypoint_is_free(name):
    """No q0: the first waypoint is solved from mid-limits as a seed but judged against no
    start (before, it was reported a jump from mid-limits the user never gave); the others
    follow it. With q0 = mid-limits given, that first step is checked as before."""
    a = arm(name)
    poses = _few(a, 3, name == "planar_2link")
    r = a.solve_path(poses)
    assert r.success.all(), [r.reason(i) for i in range(len(r))]
    assert _moves(r.q[0], r).max() <= 0.5
    for T, q in zip(poses, r.q):
        if isinstance(T, pin.SE3):
            assert np.linalg.norm(pin.log6(T.actInv(a.fk(q))).vector) <= 1e-6
        else:
            assert np.linalg.norm(a.fk(q).translation - T) <= 1e-6
    given = a.solve_path(poses, a.middle)
    assert given.status[0] == "discontinuous" and "from q0 (the start)" in given.reason(0)
    assert given.success[1:].all()
    _check_no_silent_jump(a.middle, given, 0.5)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_free_spin_stays_on_the_start_branch_at_a_singular_start(plan):
    """The UR5's zero configuration (a wrist with two parallel axes) already on a point
    with its z axis along a direction: the pose spelled with a free spin at another
    rotation (an ``Axis`` with ``within=0`` lowers to one) is solved at the tip's own spin,
    so the path stays at q0, as the same pose at the tip's rotation does; it used to move
    wrist_1 by pi and call waypoint 0 discontinuous."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle)
    turned = pin.SE3(T.rotation @ pin.exp3(np.array([0.0, 0.0, np.pi])), T.translation)
    tasks = [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], within=0)]
    for poses, kw in (([tasks] * 2, {}), ([turned] * 2, {"bounds": (0, 0, 0, 0, 0, np.inf)})):
        r = ur5.solve_path(poses, ur5.middle, plan=plan, **kw)
        assert r.success.all(), r.reason(0)
        assert np.abs(r.q - ur5.middle).max() < 1e-3  # was pi on wrist_1
        for q in r.q:
            assert np.allclose(ur5.fk(q).translation, T.translation, atol=1e-9)
            assert np.allclose(ur5.fk(q).rotation[:, 2], T.rotation[:, 2], atol=1e-9)
