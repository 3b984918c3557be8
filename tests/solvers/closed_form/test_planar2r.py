"""The closed-form 2-link specialist against the textbook formula and Pinocchio FK."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armik
from armik.solvers.closed_form import planar2r

from ...conftest import TOL, arm, model, two_link_urdf, write_urdf

L1, L2 = 1.0, 0.8


def textbook(x: float, y: float, sign: float) -> tuple[float, float]:
    """The lesson's formula, written independently of the solver."""
    c2 = (x * x + y * y - L1 * L1 - L2 * L2) / (2 * L1 * L2)
    q2 = sign * math.acos(c2)
    q1 = math.atan2(y, x) - math.atan2(L2 * math.sin(q2), L1 + L2 * math.cos(q2))
    return q1, q2


def test_worked_example_both_branches():
    a = arm("planar_2link")
    results = a.solve_all([1.2, 0.5])
    assert [r.branch for r in results] == ["elbow-up", "elbow-down"] or sorted(
        r.branch for r in results
    ) == ["elbow-down", "elbow-up"]
    by_branch = {r.branch: r for r in results}
    for branch, sign in (("elbow-up", -1.0), ("elbow-down", 1.0)):
        r = by_branch[branch]
        assert r.success and r.solver == "planar2r" and r.status == "converged"
        np.testing.assert_allclose(r.q, textbook(1.2, 0.5, sign), atol=TOL["closed_form"])
        assert r.position_error < 1e-14
    assert by_branch["elbow-up"].q[1] < 0 < by_branch["elbow-down"].q[1]


def mixed_axes_urdf() -> str:
    """The 2-link arm with joint 2 turning about -z, joint 1 about +z."""
    text = two_link_urdf()
    head, tail = text.split('<joint name="j2"')
    return head + '<joint name="j2"' + tail.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 -1"/>')


@pytest.mark.parametrize(
    "axis, text",
    [
        ("0 0 1", two_link_urdf()),
        ("0 0 -1", two_link_urdf(axis="0 0 -1")),
        ("0 1 0", two_link_urdf(axis="0 1 0")),
        ("0 -1 0", two_link_urdf(axis="0 -1 0")),
        ("0 0 1", mixed_axes_urdf()),
    ],
)
def test_elbow_up_is_left_of_the_line_to_the_target_seen_down_joint_1s_axis(
    tmp_path, rng, axis, text
):
    """'elbow-up' was q2 > 0: on the 2-link arm reaching (1.2, 0.5) its elbow sat below the
    line from the shoulder to the target. Elbow-up is the elbow on the left of that line seen
    with joint 1's axis toward the viewer (above it for +z axes and a target to the right),
    in solve_all, the prepared solve and the vectorised closed form alike."""
    a = armik.load(write_urdf(tmp_path, text), tip="tip")
    up = np.array([float(v) for v in axis.split()])  # joint 1's axis in the base frame

    def side(q, target) -> float:  # > 0: the elbow left of shoulder -> target
        shoulder = a.fk(q, "l1").translation  # link 1's frame is on joint 1's axis
        elbow = a.fk(q, "l2").translation
        return float(np.cross(target - shoulder, elbow - shoulder) @ up)

    for _ in range(10):
        target = a.fk(a.random_q(rng)).translation
        results = a.solve_all(target, solver="planar2r")
        assert sorted(r.branch for r in results) == ["elbow-down", "elbow-up"]
        for r in results:
            assert r.success and side(r.q, target) * (1 if r.branch == "elbow-up" else -1) > 0
            assert a.solve(target, q0=r.q).branch == r.branch  # the prepared solve's label
        xy = a.kinematics.plane.to_2d(target)[None]
        q_up, q_down, _ = planar2r.solve_many(a.kinematics, xy)
        assert side(q_up[0], target) > 0 > side(q_down[0], target)
    if axis == "0 0 1":  # the worked example: the elbow above the line to (1.2, 0.5)
        r = next(r for r in a.solve_all([1.2, 0.5]) if r.branch == "elbow-up")
        elbow = a.fk(r.q, "l2").translation
        assert elbow[1] > 0.5 / 1.2 * elbow[0]


def test_solve_picks_branch_nearest_q0():
    a = arm("planar_2link")
    up = a.solve([1.2, 0.5], q0=[1.0, -1.0])
    down = a.solve([1.2, 0.5], q0=[0.0, 1.0])
    assert up.branch == "elbow-up" and down.branch == "elbow-down"


def test_joint_limits_exclude_one_branch():
    a = arm("planar_2link").with_limits({"joint2": (0.0, math.pi)})
    with pytest.warns(armik.ArmikWarning, match="clipped"):
        r = a.solve([1.2, 0.5], q0=[1.0, -1.0])  # q0 prefers elbow-up, limits forbid it
    assert r.success and r.branch == "elbow-down"
    results = a.solve_all([1.2, 0.5])
    assert [r.success for r in results] == [True, False]
    assert results[1].status == "joint_limits"


def test_both_branches_outside_limits():
    a = arm("planar_2link").with_limits({"joint2": (-0.1, 0.1)})
    r = a.solve([1.2, 0.5])
    assert not r.success and r.status == "joint_limits" and "joint2" in r.reason


def test_wrap_uses_equivalent_angle_within_wide_limits():
    a = arm("planar_2link").with_limits({"joint1": (0.0, 2 * math.pi)})
    r = a.solve([1.2, 0.5], q0=[6.0, 1.0])
    assert r.success and r.branch == "elbow-down"
    assert r.q[0] == pytest.approx(textbook(1.2, 0.5, 1.0)[0] + 2 * math.pi, abs=1e-12)


@pytest.mark.parametrize(
    "target, words",
    [
        ([3.0, 0.0], "too far"),
        ([0.0, 1.9], "too far"),
        ([0.1, 0.0], "inner dead zone"),
        ([0.0, 0.0], "inner dead zone"),
    ],
)
def test_unreachable_reports_reason_and_closest_configuration(target, words):
    a = arm("planar_2link")
    r = a.solve(target)
    assert not r.success and r.status == "unreachable" and words in r.reason
    assert np.all(np.isfinite(r.q))
    # q is the closest reachable configuration: the arm points at the target
    tip = a.fk(r.q).translation[:2]
    d = np.linalg.norm(target)
    expected = (L1 + L2) if d > L1 + L2 else (L1 - L2)
    assert np.linalg.norm(tip) == pytest.approx(expected, abs=1e-12)
    if d > 0:
        assert r.position_error == pytest.approx(abs(d - expected), abs=1e-12)


@pytest.mark.parametrize(
    "radius, branch, q2", [(L1 + L2, "stretched", 0.0), (L1 - L2, "folded", math.pi)]
)
def test_singular_boundary_single_solution(radius, branch, q2):
    a = arm("planar_2link")
    angle = 0.3
    target = [radius * math.cos(angle), radius * math.sin(angle)]
    results = a.solve_all(target)
    assert len(results) == 1
    r = results[0]
    assert r.success and r.singular and r.branch == branch and "singular" in r.reason
    assert abs(abs(r.q[1]) - q2) < 1e-12 and np.all(np.isfinite(r.q))


def test_no_nan_just_beyond_the_boundary():
    a = arm("planar_2link")
    r = a.solve([L1 + L2 + 1e-15, 0.0])
    assert np.all(np.isfinite(r.q)) and r.success and r.singular


def test_degenerate_equal_links_target_at_base(tmp_path):
    urdf = two_link_urdf(l1=0.7, l2=0.7, limits2=(-3.2, 3.2))
    a = armik.load(write_urdf(tmp_path, urdf), tip="tip")
    r = a.solve([0.0, 0.0], q0=[0.4, 2.0])
    assert r.success and r.singular and "free" in r.reason
    assert r.q[0] == pytest.approx(0.4)  # kept at q0
    assert abs(r.q[1]) == pytest.approx(math.pi)
    # the same arm whose elbow cannot fold that far says so instead of pretending
    tight = a.with_limits({"j2": (-3.0, 3.0)})
    r = tight.solve([0.0, 0.0], q0=[0.4, 2.0])
    assert not r.success and r.status == "joint_limits"


@pytest.mark.parametrize(
    "origin, rpy", [("0.3 -0.2 0.5", "0.4 -0.3 1.2"), ("1 2 3", "3.0 0.1 -2.0")]
)
def test_rotated_and_translated_arm(tmp_path, origin, rpy, rng):
    a = armik.load(
        write_urdf(tmp_path, two_link_urdf(origin=origin, rpy=rpy, tool="0.1 0.05 0.2")), tip="tip"
    )
    assert planar2r.applies(a.kinematics) is None
    geo = planar2r.geometry(a.kinematics)
    assert geo.l1 == pytest.approx(1.0) and geo.l2 == pytest.approx(math.hypot(0.9, 0.05))
    for _ in range(20):
        q = a.random_q(rng)
        p = a.fk(q).translation  # a 3-vector in the base frame
        results = a.solve_all(p)
        assert len(results) == 2 and all(r.success for r in results)
        assert min(np.linalg.norm(r.q - q) for r in results) < 1e-9
        assert all(r.position_error < 1e-12 for r in results)


def test_off_plane_target_is_unreachable(tmp_path):
    a = arm("planar_2link")
    r = a.solve([1.0, 0.5, 0.2])
    assert r.status == "unreachable" and "off the arm's plane" in r.reason


def test_full_pose_orientation_consistency():
    a = arm("planar_2link")
    q = np.array([0.3, 0.9])
    T = a.fk(q)
    results = a.solve_all(T)
    ok = [r for r in results if r.success]
    assert len(ok) == 1 and np.allclose(ok[0].q, q, atol=1e-12)
    other = [r for r in results if not r.success][0]
    assert other.status == "unreachable" and "cannot choose both" in other.reason
    tilted = T * pin.SE3(pin.rpy.rpyToMatrix(0.2, 0, 0), np.zeros(3))
    r = a.solve(tilted)
    assert r.status == "unreachable" and "tilted" in r.reason


def test_double_pendulum_axes_along_x(rng):
    a = arm("double_pendulum")
    assert planar2r.applies(a.kinematics) is None
    np.testing.assert_allclose(np.abs(a.kinematics.plane.normal), [1, 0, 0], atol=1e-12)
    for _ in range(20):
        q = a.random_q(rng)
        results = a.solve_all(a.fk(q).translation)
        assert all(r.success and r.solver == "planar2r" for r in results)
        assert min(np.linalg.norm(r.q - q) for r in results) < 1e-9


def test_zero_length_link_is_refused_with_reason(tmp_path):
    a = armik.load(write_urdf(tmp_path, two_link_urdf(l2=0.0)), tip="tip")
    assert "zero length" in planar2r.applies(a.kinematics)
    r = a.solve([1.0, 0.0, 0.0])  # auto falls back to a numeric solver
    assert r.solver == "dls" and r.success


def test_vectorised_matches_scalar(rng):
    a = model("planar_2link")
    xy = rng.uniform(-2.0, 2.0, size=(500, 2))
    q_up, q_down, ok = planar2r.solve_many(a, xy)
    r = np.linalg.norm(xy, axis=1)
    np.testing.assert_array_equal(ok, (r <= L1 + L2) & (r >= L1 - L2))

    def wrapped(a, b):
        d = np.asarray(a) - np.asarray(b)
        return np.abs(np.arctan2(np.sin(d), np.cos(d))).max()

    for i in np.flatnonzero(ok)[:50]:
        assert wrapped(q_up[i], textbook(*xy[i], -1.0)) < TOL["closed_form"]
        assert wrapped(q_down[i], textbook(*xy[i], 1.0)) < TOL["closed_form"]
    geo = planar2r.geometry(a)
    np.testing.assert_allclose(geo.forward(q_up[ok, 0], q_up[ok, 1]), xy[ok], atol=1e-12)
    np.testing.assert_allclose(geo.forward(q_down[ok, 0], q_down[ok, 1]), xy[ok], atol=1e-12)
    assert np.all(np.isnan(q_up[~ok]))


annulus = st.tuples(st.floats(L1 - L2 + 1e-6, L1 + L2 - 1e-6), st.floats(-math.pi, math.pi))


@settings(max_examples=200, deadline=None)
@given(annulus)
def test_property_every_reachable_point_reached_by_both_branches(polar):
    radius, angle = polar
    a = arm("planar_2link")
    target = [radius * math.cos(angle), radius * math.sin(angle)]
    results = a.solve_all(target)
    assert len(results) == 2 and {r.branch for r in results} == {"elbow-up", "elbow-down"}
    for r in results:
        assert r.success and np.linalg.norm(a.fk(r.q).translation[:2] - target) < 1e-12


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 5.0), st.floats(-math.pi, math.pi))
def test_property_outside_the_annulus_is_unreachable(radius, angle):
    a = arm("planar_2link")
    if L1 - L2 + 1e-9 <= radius <= L1 + L2 - 1e-9:
        return
    r = a.solve([radius * math.cos(angle), radius * math.sin(angle)])
    if radius > L1 + L2 + 1e-6:
        assert r.status == "unreachable" and "too far" in r.reason
    elif radius < L1 - L2 - 1e-6:
        assert r.status == "unreachable" and "dead zone" in r.reason
    else:
        assert r.singular  # within tolerance of the boundary: merged branches


@pytest.mark.parametrize("limit", [3.14159, 3.1415, 3.0])
def test_a_target_made_on_the_elbow_limit_near_the_fold(limit):
    # acos near -1 loses digits: the elbow came back 1e-11 rad past a limit the target was
    # made on, both rows failed as joint_limits though q is a solution within the limits
    a = arm("planar_2link").with_limits({"joint2": (-limit, limit)})
    for q1 in (0.3, -1.2, 2.5):
        q = np.array([q1, limit])
        p = a.fk(q).translation
        r = a.solve(p, q0=q)
        assert r.success and np.abs(r.q - q).max() < 1e-6, (q, r.q, r.status)
        assert a.within_limits(r.q)
        assert any(s.success and np.abs(s.q - q).max() < 1e-6 for s in a.solve_all(p))


@pytest.mark.parametrize(
    ("distance", "said"),
    [
        (L1 + L2 + 2e-6, "beyond the reach l1 + l2 = 1.8 m (by 2e-06 m)"),
        (L1 - L2 - 2e-7, "closer than |l1 - l2| = 0.2 m (by 2e-07 m)"),
        (L1 + L2 + 1e-3, "beyond the reach l1 + l2 = 1.8 m;"),  # apart: no "by"
    ],
)
def test_a_target_out_of_reach_by_a_hair_says_by_how_much(distance, said):
    """2e-6 m past the 2-link arm's reach, beyond tol_position: it said 'target at distance
    1.8 m from the shoulder is too far: beyond the reach l1 + l2 = 1.8 m'."""
    r = arm("planar_2link").solve([distance, 0.0], solver="planar2r", tol_position=1e-9)
    assert r.status == "unreachable" and said in r.reason, r.reason
    assert r.position_error == pytest.approx(abs(distance - (L1 + L2 if distance > 1 else 0.2)))


def test_an_elbow_short_by_a_hair_says_by_how_much():
    """The 6R closed forms' elbow span, 2e-7 m too long under a tolerance of 1e-9 m: it
    said 'the elbow must span 0.82597 m, at most 0.82597 m is reachable'."""
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.0, 0.0, -0.5, 1.2, 0.4]))  # joint 3 at 0: the elbow stretched
    out = T.translation - ur5.kinematics.first_joint_origin
    far = pin.SE3(T.rotation, T.translation + 2e-7 * out / np.linalg.norm(out))
    said = [r.reason for r in ur5.solve_all(far, solver="three_parallel", tol_position=1e-9)]
    short = [s for s in said if "span 0.82597 m, at most 0.82597 m is reachable" in s]
    assert short and all("(by 2e-07 m)" in s for s in short), said
