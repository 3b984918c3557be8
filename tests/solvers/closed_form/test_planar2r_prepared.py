"""The planar 2-link closed form through the prepared path (``armik.solve.prepared``) gives
what the general path gives, field for field: (x, y), 3-vector and full-pose targets,
reachable, unreachable, singular and outside the joint limits, for ``solve`` and
``solve_all``.

The general path is taken by passing the already parsed ``Target`` (the plan takes only
plain arrays and SE3s), so that the two results of each case come from the same solver and
seed by the two routes.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solve.prepared import Plan, plan_for
from armik.solve.read import settings
from armik.solvers.closed_form import planar2r_kernel
from armik.targets.pose import parse_target

from ...conftest import arm, assert_same_result, decided_by_verdicts, two_link_urdf, write_urdf

L1, L2 = 1.0, 0.8  # planar_2link


def _both(a: armik.Arm, target, q0, **kw):
    """(prepared, general) results of ``solve`` and of ``solve_all``, checked equal."""
    general_target = parse_target(target, a.kinematics)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a q0 outside the limits: clipped, said on both
        fast = a.solve(target, q0=q0, **kw)
        assert_same_result(fast, a.solve(general_target, q0=q0, **kw))
        every = a.solve_all(target, q0=q0, **kw)
        general = a.solve_all(general_target, q0=q0, **kw)
    assert len(every) == len(general)
    for x, y in zip(every, general):
        assert_same_result(x, y)
    return fast, every


def _polar(radius: float, angle: float) -> np.ndarray:
    return np.array([radius * math.cos(angle), radius * math.sin(angle)])


def _seeds(a: armik.Arm, rng) -> list:
    at_limit = np.minimum(a.upper, 3.0)  # on the upper limits (an unbounded joint's: 3)
    return [None, a.random_q(rng), a.random_q(rng).tolist(), a.middle + 0.3, at_limit]


def _targets(a: armik.Arm, rng, n: int) -> list:
    """Targets of every form and kind on ``a`` (planar_2link's geometry)."""
    out = []
    for _ in range(n):
        T = a.fk(a.random_q(rng))
        out += [T.translation[:2].copy(), T.translation.copy(), T, T.homogeneous]
    for radius in (L1 + L2, L1 - L2, L1 + L2 + 1e-8, L1 - L2 - 1e-8, 3.0, 0.1, 0.0, 1e-12):
        for angle in (0.0, 0.3, -2.0, math.pi):
            out.append(_polar(radius, angle))
    p = a.fk(a.random_q(rng)).translation
    out.append(p + np.array([0.0, 0.0, 0.2]))  # off the plane
    out.append(p + np.array([0.0, 0.0, 1e-8]))  # off by less than the tolerance
    T = a.fk(a.random_q(rng))
    out.append(T * pin.SE3(pin.rpy.rpyToMatrix(0.2, 0.0, 0.0), np.zeros(3)))  # tilted
    out.append(T * pin.SE3(pin.rpy.rpyToMatrix(0.0, 0.0, 0.7), np.zeros(3)))  # angle missed
    stretched = pin.SE3(pin.rpy.rpyToMatrix(0.0, 0.0, 0.3), np.r_[_polar(L1 + L2, 0.3), 0.0])
    out.append(stretched)
    out.append(stretched * pin.SE3(pin.rpy.rpyToMatrix(0.0, 0.0, 0.5), np.zeros(3)))  # missed
    return out


def test_the_plan_is_taken_for_xy_positions_and_poses():
    a = armik.load("planar_2link")  # a fresh arm: its own plans
    opts, key, _ = settings(a.kinematics, {})
    for position in (False, True):
        plan = plan_for(a.kinematics, "auto", key, opts, position)
        assert isinstance(plan, Plan) and plan.solver == "planar2r"
    T = a.fk(np.array([0.4, 1.1]))
    for target in (T.translation[:2].copy(), T.translation.copy(), T, T.homogeneous):
        r = a.solve(target, q0=np.array([0.3, 1.0]))
        assert r.success and r.solver == "planar2r" and r.branch == "elbow-down"
        assert not decided_by_verdicts(r)  # the prepared path
        assert r.reason.startswith("closed form; verified by forward kinematics")


@pytest.mark.parametrize("name", ["planar_2link", "double_pendulum"])
def test_prepared_is_general_on_many_targets(name):
    a = arm(name)
    rng = np.random.default_rng(11)
    statuses = set()
    for target in _targets(a, rng, 40):
        for q0 in _seeds(a, rng):
            fast, every = _both(a, target, q0)
            statuses.add((fast.status.value, fast.singular))
            statuses.update((r.status.value, r.singular) for r in every)
    if name == "planar_2link":
        assert {
            ("converged", False),
            ("converged", True),
            ("unreachable", False),
            ("unreachable", True),
        } <= statuses


def test_prepared_is_general_within_joint_limits():
    rng = np.random.default_rng(12)
    base = arm("planar_2link")
    arms = [
        base.with_limits({"joint2": (0.0, math.pi)}),  # elbow-up outside the limits
        base.with_limits({"joint2": (-0.1, 0.1)}),  # both outside, but near stretched
        base.with_limits({"joint1": (0.0, 2 * math.pi)}),  # 2 pi equivalents
        base.with_limits({"joint1": (-0.5, 0.5), "joint2": (-2.0, 2.0)}),
    ]
    seen = set()
    for a in arms:
        for target in _targets(a, rng, 15):
            for q0 in _seeds(a, rng):
                fast, every = _both(a, target, q0)
                seen.add(fast.status.value)
                seen.update(r.status.value for r in every)
    assert {"converged", "joint_limits", "unreachable"} <= seen


def test_seed_halfway_between_the_branches():
    # q0 as near one elbow branch as the other: the general verdict decides the tie
    a = arm("planar_2link")
    rng = np.random.default_rng(13)
    for _ in range(50):
        xy = _polar(rng.uniform(0.3, 1.7), rng.uniform(-math.pi, math.pi))
        for q0 in (np.array([math.atan2(xy[1], xy[0]), 0.0]), np.zeros(2)):
            _both(a, xy, q0)
            _both(a, xy.copy(), q0 + 1e-13)


def test_equal_links_target_at_the_shoulder(tmp_path):
    a = armik.load(write_urdf(tmp_path, two_link_urdf(l1=0.7, l2=0.7, limits2=(-3.2, 3.2))))
    tight = a.with_limits({"j2": (-3.0, 3.0)})
    for q0 in (np.array([0.4, 2.0]), None, np.array([-3.0, -3.1])):
        fast, _ = _both(a, np.zeros(2), q0)
        assert fast.success and fast.singular and "free" in fast.reason
        fast, _ = _both(tight, np.zeros(2), q0)
        assert fast.status == "joint_limits"
        _both(a, np.zeros(3), q0)


@pytest.mark.parametrize(
    "origin, rpy, tool",
    [("0.3 -0.2 0.5", "0.4 -0.3 1.2", "0.1 0.05 0.2"), ("1 2 3", "3 .1 -2", "0 0 0")],
)
def test_rotated_and_translated_arm(tmp_path, origin, rpy, tool):
    a = armik.load(
        write_urdf(tmp_path, two_link_urdf(origin=origin, rpy=rpy, tool=tool)), tip="tip"
    )
    rng = np.random.default_rng(14)
    for _ in range(30):
        T = a.fk(a.random_q(rng))
        # a 2-vector: the base coordinates across the (tilted) plane (``Plane.from_base``)
        k = int(np.argmax(np.abs(a.kinematics.plane.normal)))
        xy = T.translation[[m for m in range(3) if m != k]].copy()
        for target in (xy, T.translation.copy(), T, T.homogeneous):
            for q0 in (None, a.random_q(rng)):
                fast, _ = _both(a, target, q0)
                assert fast.success


@pytest.mark.parametrize("options", [{"tol_position": 1e-9}, {"position_only": True}])
def test_options(options):
    a = arm("planar_2link")
    rng = np.random.default_rng(15)
    for target in _targets(a, rng, 10):
        _both(a, target, a.random_q(rng), **options)


def test_a_refused_answer_falls_back_to_every_row():
    # The runner's first answer is wrong (joint 1 off by 1e-3 rad): the check refuses it and
    # every row goes to the general verdict, which verifies the other branch.
    a = armik.load("planar_2link")
    opts, key, _ = settings(a.kinematics, {})
    plan = plan_for(a.kinematics, "auto", key, opts, position=True)
    honest = plan.run_pose

    def lying(H, q0, seed, every=False, xy=None):
        got = honest(H, q0, seed, every, xy)
        if every:
            return got
        q = got.q.copy()
        q[0] += 1e-3
        return got._replace(q=q)

    lying.takes_xy = True
    plan.run_pose = lying
    xy = np.array([1.2, 0.5])
    q0 = np.array([0.0, 1.0])  # nearest the elbow-down branch
    r = a.solve(xy, q0=q0)
    assert r.success and r.branch == "elbow-down"  # the honest row, verified
    assert decided_by_verdicts(r)
    assert_same_result(r, a.solve(parse_target(xy, a.kinematics), q0=q0))


def test_other_spellings_take_the_general_path():
    a = arm("planar_2link")
    xy = np.array([1.2, 0.5])
    expected = a.solve(xy)
    strided = np.array([1.2, 0.0, 0.5])[::2]
    for target in ([1.2, 0.5], (1.2, 0.5), xy.astype(np.float32), strided):
        r = a.solve(target)
        assert decided_by_verdicts(r)  # the general path
        assert r.success and r.branch == expected.branch
    for bad in (np.array([np.nan, 0.5]), np.array([np.inf, 0.5]), np.array([2e6, 0.5])):
        with pytest.raises(armik.errors.TargetError):
            a.solve(bad)


def test_hypot_is_pythons():
    rng = np.random.default_rng(16)
    a = rng.uniform(-3.0, 3.0, 200_000) * 10.0 ** rng.integers(-12, 3, 200_000)
    b = rng.uniform(-3.0, 3.0, 200_000) * 10.0 ** rng.integers(-12, 3, 200_000)
    extra = [(0.0, 0.0), (-0.0, 3.0), (3.0, 4.0), (1e-320, 3e-321), (1e300, 1e300), (2.0, math.inf)]
    for x, y in list(zip(a.tolist(), b.tolist())) + extra:
        assert planar2r_kernel.hypot(x, y) == math.hypot(x, y), (x, y)
