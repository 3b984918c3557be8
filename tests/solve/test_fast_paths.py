"""The fast paths of one solve's fixed cost give what the general paths give.

Each fast path (an SE3 target, a float64 q0 within the limits, the limit check on plain
floats, results and answers built without the frozen ``__init__``, ``check_batch``
without per-row conversions) is compared with the general path on the same input.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import ArmikWarning, OptionError, SolverError, TargetError
from armik.options import Options
from armik.result import IKResult
from armik.solvers import registry
from armik.status import Status
from armik.targets.batch import TargetBatch
from armik.targets.pose import _pose, parse_target
from armik.verify import measure as verify


@pytest.fixture(scope="module")
def panda():
    return armik.load("panda")


@pytest.fixture(scope="module")
def kinova():  # three continuous joints: to_pin is not the identity
    return armik.load("kinova")


def _same_target(a, b) -> None:
    assert np.array_equal(a.position, b.position)
    assert (a.rotation is None) == (b.rotation is None)
    if a.rotation is not None:
        assert np.array_equal(a.rotation, b.rotation)
    assert a.planar_xy is None and b.planar_xy is None


def test_se3_target_is_the_general_pose(panda):
    rng = np.random.default_rng(0)
    for _ in range(50):
        T = panda.fk(panda.random_q(rng))
        fast = parse_target(T, panda.kinematics)
        _same_target(fast, _pose(T.rotation, T.translation))
        _same_target(fast, parse_target(T.homogeneous, panda.kinematics))
        _same_target(fast, parse_target((T.translation, T.rotation), panda.kinematics))
        assert fast.rotation.flags.c_contiguous and fast.rotation.flags.writeable
        # the target owns its arrays: changing the SE3 afterwards changes nothing
        R = fast.rotation.copy()
        T.rotation[0, 0] += 1.0
        assert np.array_equal(fast.rotation, R)


def test_se3_target_outside_the_fast_path_goes_through_pose():
    R = pin.utils.rpyToMatrix(0.3, -0.2, 1.1)
    # a rotation off by 1e-9: the general path snaps it to the nearest rotation
    off = pin.SE3(R + 1e-9 * np.ones((3, 3)), np.array([0.1, 0.2, 0.3]))
    t = parse_target(off)
    _same_target(t, _pose(off.rotation, off.translation))
    assert np.abs(t.rotation.T @ t.rotation - np.eye(3)).max() < 1e-14
    bad = [
        pin.SE3(np.diag([1.0, 1.0, -1.0]), np.zeros(3)),  # a reflection
        pin.SE3(2.0 * R, np.zeros(3)),  # not orthonormal
        pin.SE3(R, np.array([np.nan, 0.0, 0.0])),
        pin.SE3(R, np.array([2e6, 0.0, 0.0])),  # beyond MAX_POSITION
    ]
    nan_R = R.copy()
    nan_R[1, 1] = np.inf
    bad.append(pin.SE3(nan_R, np.zeros(3)))
    for T in bad:
        with pytest.raises(TargetError) as fast:
            parse_target(T)
        with pytest.raises(TargetError) as general:
            _pose(T.rotation, T.translation)
        assert str(fast.value) == str(general.value)


def _reference_within(arm, q, tol=armik.tolerances.LIMIT_TOL) -> bool:
    return all(lo - tol <= v <= hi + tol for v, lo, hi in zip(q, arm.lower, arm.upper))


def test_within_limits_matches_its_definition(panda, kinova):
    rng = np.random.default_rng(1)
    narrow = panda.with_limits({"panda_joint1": (-0.5, 0.5)})
    for arm in (panda.kinematics, kinova.kinematics, narrow.kinematics):
        lo, hi = arm.sampling_box()
        for _ in range(200):
            q = rng.uniform(lo - 0.3, hi + 0.3)
            for tol in (armik.tolerances.LIMIT_TOL, 0.1):
                assert arm.within_limits(q, tol) == _reference_within(arm, q, tol)
        edge = np.where(np.isfinite(arm.upper), arm.upper, 0.0)
        assert arm.within_limits(edge + 0.5e-12)
        if np.isfinite(arm.upper).any():
            assert not arm.within_limits(edge + 2e-12)
        q = arm.middle.copy()
        q[0] = np.nan
        assert not arm.within_limits(q)
    # the clone's bounds are its own, not the cached ones of the arm it came from
    q = panda.middle.copy()
    q[0] = 0.9
    assert panda.within_limits(q) and not narrow.within_limits(q)
    assert narrow.kinematics.limit_violations(q) and not panda.kinematics.limit_violations(q)


def _general_seed(arm, q0):
    """ArmModel.seed's general path, spelled out."""
    q = arm.check_q(q0, "q0")
    if not arm.within_limits(q):
        return np.clip(q, arm.lower, arm.upper), True
    return q, False


def test_seed_fast_path_is_the_general_path(panda, kinova):
    rng = np.random.default_rng(2)
    for arm in (panda.kinematics, kinova.kinematics):
        lo, hi = arm.sampling_box()
        for _ in range(100):
            q0 = rng.uniform(lo - 0.2, hi + 0.2)
            expected, warns = _general_seed(arm, q0)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                got = arm.seed(q0)
            assert np.array_equal(got, expected)
            assert any(issubclass(w.category, ArmikWarning) for w in caught) == warns
            for other in (q0.tolist(), q0.astype(np.float32).astype(float)):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ArmikWarning)
                    assert np.array_equal(arm.seed(other), _general_seed(arm, other)[0])
    q0 = panda.middle.copy()
    assert panda.kinematics.seed(q0) is q0  # as check_q gives it: no copy
    for bad in (np.nan, np.inf, -np.inf):
        q = kinova.middle.copy()
        q[0] = bad  # joint 0 of the kinova is continuous: no limit stops an inf
        with pytest.raises(OptionError, match="finite"):
            kinova.kinematics.seed(q)
    huge = np.full(panda.dof, 1e308)  # finite, but its sum overflows
    with pytest.warns(ArmikWarning):
        assert np.array_equal(panda.kinematics.seed(huge), panda.upper)
    with pytest.raises(OptionError):
        panda.kinematics.seed(np.zeros(panda.dof + 1))


def test_a_result_built_fast_equals_its_init():
    q = np.array([0.1, 0.2, 0.3])
    q.flags.writeable = False
    row = dict(
        q=q,
        success=True,
        status=Status.CONVERGED,
        reason="r",
        iterations=3,
        position_error=1e-9,
        orientation_error=None,
        branch="b",
        singular=False,
        restarts=1,
        solver="dls",
        time=1e-5,
    )
    fast, init = IKResult._from_fields(dict(row)), IKResult(**{**row, "q": [0.1, 0.2, 0.3]})
    assert vars(fast).keys() == vars(init).keys()
    for f in dataclasses.fields(IKResult):
        a, b = getattr(fast, f.name), getattr(init, f.name)
        assert type(a) is type(b)
        assert np.array_equal(a, b) if f.name == "q" else a == b
    assert not fast.q.flags.writeable and fast.q.dtype == float
    with pytest.raises(dataclasses.FrozenInstanceError):
        fast.success = False  # type: ignore[misc]
    # a reason written on first read, as prepared solves and the verdict's successes do
    lazy = {k: v for k, v in row.items() if k != "reason"}
    late = IKResult._from_fields({**lazy, "_reason": (str.upper, ("words",))})
    assert late.reason == "WORDS" and late.as_dict()["reason"] == "WORDS"


def test_results_compare_field_for_field():
    ur5 = armik.load("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(4)))
    a, b = ur5.solve(T, q0=ur5.kinematics.middle), ur5.solve(T, q0=ur5.kinematics.middle)
    same = dataclasses.replace(b, time=a.time)  # two solves differ in their time only
    assert a == same and not a != same
    assert a != b  # another time
    other = dataclasses.replace(same, q=same.q + 1e-3)
    assert a != other and (a == "converged") is False
    assert dataclasses.replace(same, extra={"score": 1.0}) == a  # extra is not compared
    with pytest.raises(TypeError):
        hash(a)


def test_check_batch_equals_check_row_by_row(panda, kinova):
    rng = np.random.default_rng(3)
    opts = Options()
    for arm in (panda.kinematics, kinova.kinematics):
        lo, hi = arm.sampling_box()
        Q = rng.uniform(lo - 0.1, hi + 0.1, size=(20, arm.dof))
        Q_t = rng.uniform(lo, hi, size=(20, arm.dof))
        poses = [arm.fk(q) for q in Q_t]
        Q[0] = Q_t[0]  # one exact answer
        Q[3, 1] = np.nan  # one non-finite row
        batch = TargetBatch(
            np.array([T.translation for T in poses]), np.array([T.rotation for T in poses])
        )
        got = verify.measure_batch(arm, Q, batch, opts)
        for i in range(len(Q)):
            if i == 3:
                assert math.isnan(got.position_error[i]) and not got.within_limits[i]
                continue
            c = verify.measure(arm, Q[i], parse_target(poses[i]), opts)
            assert got.position_error[i] == pytest.approx(c.position_error, abs=1e-15)
            assert got.orientation_error[i] == pytest.approx(c.orientation_error, abs=1e-14)
            assert bool(got.within_limits[i]) == (not c.violations)
        assert got.ok[0] and not got.ok[3]


def test_solve_gives_the_same_answer_on_every_path(panda):
    rng = np.random.default_rng(4)
    for _ in range(10):
        q = panda.random_q(rng)
        T = panda.fk(q)
        results = [
            panda.solve(T, q0=q, seed=1),  # SE3 target, float64 q0: the fast paths
            panda.solve(T.homogeneous, q0=q.tolist(), seed=1),
            panda.solve((T.translation, T.rotation), q0=tuple(q), seed=1, timeout=0.2),
        ]
        for r in results[1:]:
            assert np.array_equal(r.q, results[0].q)
            assert (r.success, r.status, r.reason) == (
                results[0].success,
                results[0].status,
                results[0].reason,
            )
            assert r.position_error == results[0].position_error
        assert results[0].success


def test_registry_refuses_a_name_that_is_not_a_str(panda):
    for bad in (["dls"], None, 3, ("dls",)):
        with pytest.raises(SolverError, match="one name"):
            registry.get(bad)  # type: ignore[arg-type]
        with pytest.raises(SolverError, match="one name"):
            registry.choose(bad, panda.kinematics)  # type: ignore[arg-type]
        with pytest.raises(SolverError, match="one name"):
            registry.why_not(bad, panda.kinematics)  # type: ignore[arg-type]
    with pytest.raises(SolverError, match="unknown solver"):
        registry.get("nope")
    assert registry.get(np.str_("dls")).name == "dls"
    with pytest.raises(SolverError):
        panda.solve(panda.fk(panda.middle), solver=["dls"])


def test_check_many_is_check_one_by_one(panda, kinova):
    rng = np.random.default_rng(5)
    for arm in (panda.kinematics, kinova.kinematics):
        lo, hi = arm.sampling_box()
        qs = list(rng.uniform(lo - 0.2, hi + 0.2, size=(9, arm.dof)))
        qs[0] = arm.middle.copy()  # within the limits
        qs[1] = np.where(np.isfinite(arm.upper), arm.upper + 0.5, 0.0)  # outside
        qs[2] = qs[2].tolist()  # not an array: converted as check converts it
        T = arm.fk(arm.random_q(rng))
        for target, opts in (
            (parse_target(T), Options()),
            (parse_target(T.translation), Options()),
            (parse_target(T), Options(weights=(1, 1, 0, 1, 0, 1))),
            (parse_target(T), Options(position_only=True)),
        ):
            qs_arr = [np.asarray(q, dtype=float) for q in qs]
            many = verify.measure_many(arm, qs_arr, target, opts)
            one = [verify.measure(arm, q, target, opts) for q in qs_arr]
            assert len(many.position_error) == len(one) == len(qs)
            # several answers placed by the compiled FK, one by Pinocchio's: to 1e-12
            alone = [m.position_error for m in one]
            np.testing.assert_allclose(many.position_error, alone, rtol=0, atol=1e-12)
            assert many.rotation == (one[0].orientation_error is not None)
            if many.rotation:
                alone = [m.orientation_error for m in one]
                np.testing.assert_allclose(many.orientation_error, alone, rtol=0, atol=1e-12)
            else:
                assert np.isnan(many.orientation_error).all()
            assert many.within_limits.tolist() == [not m.violations for m in one]
            assert many.ok.tolist() == [m.ok for m in one]
            assert not many.within_limits.all() and many.within_limits.any()


def test_solve_all_verifies_like_solve(panda):
    ur5 = armik.load("ur5")
    rng = np.random.default_rng(6)
    for _ in range(5):
        T = ur5.fk(ur5.random_q(rng))
        every = ur5.solve_all(T)
        assert len(every) > 1 and every[0].success
        one = ur5.solve(T)
        assert np.array_equal(one.q, every[0].q)
        # solve's answer is placed by Pinocchio's FK, solve_all's by the compiled FK (all
        # branches in one call): the same errors to 1e-12, the same verdicts
        assert one.success == every[0].success and one.status == every[0].status
        assert abs(one.position_error - every[0].position_error) < 1e-12
        assert abs(one.orientation_error - every[0].orientation_error) < 1e-12
        for r in every:
            c = verify.measure(ur5.kinematics, r.q, parse_target(T), Options())
            assert abs(r.position_error - c.position_error) < 1e-12
            assert abs(r.orientation_error - c.orientation_error) < 1e-12
            assert r.success == c.ok


def test_check_takes_any_float_q_as_a_copy_would(panda, kinova):
    rng = np.random.default_rng(7)
    for arm in (panda.kinematics, kinova.kinematics):
        q = arm.random_q(rng)
        target = parse_target(arm.fk(arm.random_q(rng)))
        strided = np.zeros((arm.dof, 2))
        strided[:, 0] = q
        readonly = q.copy()
        readonly.flags.writeable = False
        expected = vars(verify.measure(arm, q.copy(), target, Options()))
        for other in (strided[:, 0], readonly, q.copy()[::-1][::-1]):
            assert vars(verify.measure(arm, other, target, Options())) == expected
