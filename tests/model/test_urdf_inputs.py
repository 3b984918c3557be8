"""Inputs around a solve (issue items 3, 4, 6, 7, 8, 11, 12, 18): no false success and no
raw exception, whatever the caller passes."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pinocchio as pin
import pytest
import spatialmath as sm
from scipy.spatial.transform import Rotation

import armik
from armik.errors import (
    ArmikError,
    ArmikWarning,
    FrameError,
    JointError,
    OptionError,
    SolverError,
    TargetError,
)
from armik.targets.pose import parse_target

from ..conftest import arm, write_urdf
from ..urdf_cases import chain, joint

# -- 3. a task must measure something; flags are bools ------------------------------------


@pytest.mark.parametrize(
    "options",
    [
        {"weights": (0, 0, 0, 1, 1, 1)},
        {"weights": (0, 0, 0, 1, 1, 1), "position_only": True},
    ],
)
def test_weights_that_measure_nothing_are_refused(options):
    ur5 = arm("ur5")
    target = ur5.fk(ur5.middle + 0.3).translation + [0.3, 0, 0]
    with pytest.raises(OptionError, match="nothing to measure") as info:
        ur5.solve(target, **options)
    assert info.value.option == "weights"


def test_weights_on_orientation_of_a_pose_target_still_work():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.3)
    r = ur5.solve(T, weights=(0, 0, 0, 1, 1, 1))
    assert r.success and r.orientation_error <= 1e-6


@pytest.mark.parametrize("flag", ["False", "True", 0, 1, None, [True]])
def test_position_only_must_be_a_bool(flag):
    with pytest.raises(OptionError, match="position_only must be True or False"):
        arm("ur5").solve([0.3, 0.2, 0.4], position_only=flag)


def test_numpy_bool_is_a_bool():
    r = arm("ur5").solve([0.3, 0.2, 0.4], position_only=np.bool_(True))
    assert r.success


# -- 4. targets that overflow or lose information ------------------------------------------


@pytest.mark.parametrize(
    "value, words",
    [
        ([1e308, 1e308, 0.0], "beyond"),
        (np.diag([1e308, 1e308, 1e308, 1.0]), "not orthonormal"),
        ([0.3, np.nan, 0.4], "NaN or inf"),
        (np.diag([1.0, np.inf, 1.0, 1.0]), "NaN or inf"),
    ],
)
def test_huge_or_non_finite_numbers_get_the_right_message(value, words):
    with pytest.raises(TargetError, match=words):
        parse_target(value)


def test_huge_quaternion_is_normalised_without_overflow():
    s = 1e200
    t = parse_target(([0.3, 0.2, 0.4], [0.0, 0.0, s, s]))
    expected = pin.utils.rpyToMatrix(0, 0, math.pi / 2)
    np.testing.assert_allclose(t.rotation, expected, atol=1e-12)
    tiny = parse_target(([0.3, 0.2, 0.4], [0.0, 0.0, 1e-5, 1e-5]))
    np.testing.assert_allclose(tiny.rotation, expected, atol=1e-12)


@pytest.mark.parametrize("q", [np.array([0.1 + 1j, 0, 0, 0, 0, 0]), [1j, 0, 0, 0, 0, 0], "abcdef"])
def test_complex_or_text_joint_values_are_refused(q):
    ur5 = arm("ur5")
    with pytest.raises(OptionError, match="must be 6 numbers"):
        ur5.fk(q)
    with pytest.raises(OptionError, match="must be 6 numbers"):
        ur5.solve([0.3, 0.2, 0.4], q0=q)


@pytest.mark.parametrize(
    "value",
    [
        [0.3 + 1j, 0.2, 0.4],
        np.array([0.3, 0.2, 0.4], dtype=complex),
        ([0.3, 0.2, 0.4], [0, 0, 0, 1 + 0j]),
        np.eye(4, dtype=complex),
    ],
)
def test_complex_targets_are_refused(value):
    with pytest.raises(TargetError, match="complex"):
        parse_target(value)


# -- 18. targets from neighbouring libraries; several poses point to the batch API --------


def test_position_with_matrix_or_scipy_rotation():
    R = Rotation.from_euler("xyz", [0.3, -0.2, 1.1])
    p = np.array([0.3, 0.2, 0.4])
    expected = parse_target(pin.SE3(R.as_matrix(), p))
    for value in ((p, R.as_matrix()), (p, R), (p.tolist(), R.as_quat())):
        t = parse_target(value)
        np.testing.assert_allclose(t.rotation, expected.rotation, atol=1e-12)
        np.testing.assert_allclose(t.position, p, atol=0)
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.2)
    r = ur5.solve((T.translation, Rotation.from_matrix(T.rotation)))
    assert r.success and r.orientation_error <= 1e-6


def test_position_with_a_pinocchio_quaternion():
    """pin.Quaternion, whose coeffs() are (x, y, z, w), is read as that quaternion (it was
    called "not numeric" in a message broken over two lines), pin.AngleAxis as its turn;
    what is not numeric is named on one line."""
    R = Rotation.from_euler("xyz", [0.3, -0.2, 1.1])
    p = np.array([0.3, 0.2, 0.4])
    t = parse_target((p, pin.Quaternion(R.as_matrix())))
    np.testing.assert_allclose(t.rotation, R.as_matrix(), atol=1e-12)
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.2)
    r = ur5.solve((T.translation, pin.Quaternion(T.rotation)))
    assert r.success and np.allclose(ur5.fk(r.q).rotation, T.rotation, atol=1e-6)
    turn = pin.AngleAxis(0.7, np.array([0.0, 0.6, 0.8]))
    t = parse_target((p, turn))
    np.testing.assert_allclose(t.rotation, turn.toRotationMatrix(), atol=1e-12)

    class Lines:
        def __repr__(self) -> str:
            return "first\nsecond"  # as Eigen's objects print

    with pytest.raises(TargetError, match="target rotation first second is not numeric"):
        parse_target((p, Lines()))


def test_spatialmath_single_pose_is_accepted():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle + 0.2)
    r = ur5.solve(sm.SE3(T.homogeneous))
    assert r.success and r.orientation_error <= 1e-6


def several_pose_values():
    values = [
        np.tile(np.eye(4), (2, 1, 1)),
        np.zeros((5, 7)),
        np.zeros((4, 3)),
        [pin.SE3.Identity(), pin.SE3.Identity()],
        ([0.3, 0.2, 0.4], Rotation.from_euler("z", [[0.1], [0.2]])),
    ]
    values.append(sm.SE3([sm.SE3(0.3, 0.2, 0.4), sm.SE3(0.1, 0.2, 0.3)]))
    return values


@pytest.mark.parametrize("value", several_pose_values())
def test_several_poses_point_to_solve_batch(value):
    with pytest.raises(TargetError, match="solve_batch"):
        arm("ur5").solve(value)


# -- 6. limits on continuous joints are angles ------------------------------------------


def roll_arm(kind: str, limits: tuple[float, float]) -> str:
    lo, hi = limits
    lim = f'<limit lower="{lo}" upper="{hi}" effort="1" velocity="1"/>'
    return chain(
        joint("j1", "base", "l1", jtype=kind, limit=lim),
        joint("j2", "l1", "l2", xyz="0 0 0.3", axis='<axis xyz="0 1 0"/>'),
        joint("j3", "l2", "l3", jtype=kind, xyz="0.3 0 0", axis='<axis xyz="1 0 0"/>', limit=lim),
        joint("j4", "l3", "l4", xyz="0.1 0 0", axis='<axis xyz="0 1 0"/>'),
        joint("tool_joint", "l4", "tool", jtype="fixed", xyz="0.1 0.05 0"),
    )


@pytest.mark.parametrize("limits", [(-1.0, 1.0), (2.0, 4.0)])
def test_with_limits_on_continuous_joints_clips_angles(tmp_path, limits):
    cont = armik.load(write_urdf(tmp_path, roll_arm("continuous", (-1, 1)), "c.urdf"))
    cont = cont.with_limits({"j1": limits, "j3": limits})
    rev = armik.load(write_urdf(tmp_path, roll_arm("revolute", limits), "r.urdf"))
    lo, hi = limits
    # clip_pin works on the angle, not on (cos, sin).
    m = cont.kinematics
    qp = m.to_pin(np.array([hi + 0.5, 0.0, lo - 0.3, 0.0]))
    m.clip_pin(qp)
    np.testing.assert_allclose(m.from_pin(qp)[[0, 2]], [hi, lo], atol=1e-12)
    rng = np.random.default_rng(5)
    counts = {"cont": 0, "rev": 0}
    for k in range(15):
        q = rev.random_q(rng)
        T = rev.fk(q)
        for name, a in (("cont", cont), ("rev", rev)):
            r = a.solve(T, seed=k, timeout=0.2)
            if r.success:
                counts[name] += 1
                assert lo - 1e-9 <= r.q[0] <= hi + 1e-9 and lo - 1e-9 <= r.q[2] <= hi + 1e-9
                assert (a.fk(r.q).translation - T.translation).max() < 1e-6
    assert counts["cont"] >= counts["rev"] - 1 and counts["rev"] >= 13, counts


# -- 7. tip_offset, 12. argument types --------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, error, words",
    [
        ({"tip_offset": (np.nan, 0, 0)}, OptionError, "tip_offset"),
        ({"tip_offset": (np.inf, 0, 0)}, OptionError, "tip_offset"),
        ({"tip_offset": (1e300, 0, 0)}, OptionError, "tip_offset"),
        ({"tip_offset": (1, 2)}, OptionError, "3 values"),
        ({"tip_offset": "abc"}, OptionError, "numbers"),
        ({"tip_offset": ("a", "b", "c")}, OptionError, "numbers"),
        ({"tip_offset": (1j, 0, 0)}, OptionError, "numbers"),
        ({"tip": 123}, FrameError, "tip must be a frame name"),
        ({"base": 5}, FrameError, "base must be a frame name"),
        ({"locked": "abc"}, JointError, "locked must map"),
        ({"locked": {1: 0.0}}, JointError, "joint names"),
    ],
)
def test_load_arguments_are_checked(kwargs, error, words):
    with pytest.raises(error, match=words):
        armik.load("ur5", **kwargs)


@pytest.mark.parametrize("solver", [["dls"], None, 3, ("dls",)])
def test_solver_must_be_a_name(solver):
    ur5 = arm("ur5")
    for call in (ur5.solve, ur5.solve_all):
        with pytest.raises(SolverError, match="solver must be one name"):
            call([0.3, 0.2, 0.4], solver=solver)


@pytest.mark.parametrize(
    "limits, words",
    [
        ({"elbow_joint": "ab"}, "pair"),
        ({"elbow_joint": (0, "x")}, "must be numbers"),
        ({"elbow_joint": (np.nan, 1)}, "must be numbers"),
        ({"elbow_joint": (-1e308, 1)}, "within"),
        ({"elbow_joint": 1.0}, "pair"),
        ({3: (0, 1)}, "str"),
        ([("elbow_joint", (0, 1))], "map joint names"),
    ],
)
def test_with_limits_arguments_are_checked(limits, words):
    with pytest.raises(JointError, match=words):
        arm("ur5").with_limits(limits)


def test_with_limits_accepts_infinite_sides():
    a = arm("ur5").with_limits({"elbow_joint": (-math.inf, 1.0)})
    assert a.lower[2] == -math.inf and a.upper[2] == 1.0
    assert np.isfinite(a.random_q(0)).all()


# -- 8. one-joint chains ---------------------------------------------------------------


def test_one_joint_chain_solves_with_every_solver():
    a = armik.load("ur5", tip="shoulder_link", tip_offset=(0.3, 0, 0))
    assert a.dof == 1 and a.jacobian([0.2]).shape == (6, 1)
    target = a.fk([0.3]).translation
    for solver in ("dls", "qp", "clik"):
        # clik's fixed step shrinks the error by 0.9 per iteration: Pinocchio's example cap
        opts = {"max_iterations": 1000} if solver == "clik" else {}
        r = a.solve(target, solver=solver, **opts)
        assert r.success and abs(r.q[0] - 0.3) < 1e-5, (solver, r.reason)
        results = a.solve_all(target, solver=solver, **opts)
        assert results[0].success
    assert a.solve(a.fk([0.3])).success


def test_linear_axis_is_an_arm(tmp_path):
    lim = '<limit lower="0" upper="1.5" effort="1" velocity="1"/>'
    text = chain(
        joint("rail", "base", "carriage", jtype="prismatic", axis='<axis xyz="1 0 0"/>', limit=lim)
    )
    a = armik.load(write_urdf(tmp_path, text))
    r = a.solve([0.7, 0, 0.1])
    assert r.success and abs(r.q[0] - 0.7) < 1e-9
    far = a.solve([2.0, 0, 0.1])
    assert not far.success


# -- 11. sizes that overflow -------------------------------------------------------------


@pytest.mark.parametrize(
    "target, options",
    [
        ([1e300, 0, 0], {"weights": (1, 1, 0, 0, 0, 0)}),
        ([1e300, 0, 0], {}),
        ([0, 0, -1e7], {"solver": "qp"}),
        (np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 1e300, {}),
    ],
)
def test_absurd_target_positions_are_refused(target, options):
    with pytest.raises(TargetError, match="beyond 1e\\+06 m"):
        arm("ur5").solve(target, **options)
    with pytest.raises(TargetError, match="beyond"):
        arm("planar_2link").solve([1e300, 0.0])


@pytest.mark.parametrize("value", ["1e-3", True, b"1"])
def test_numeric_options_refuse_strings_and_bools(value):
    with pytest.raises(OptionError, match="tol_position must be a number"):
        arm("ur5").solve([0.3, 0.2, 0.4], tol_position=value)


@pytest.mark.parametrize("weights", [(1e200, 1, 1, 1, 1, 1), (1, 1, 1, 1, 1, 1e7)])
def test_absurd_weights_are_refused(weights):
    with pytest.raises(OptionError, match="at most"):
        arm("ur5").solve([0.3, 0.2, 0.4], weights=weights)


@pytest.mark.parametrize(
    "options",
    [
        dict(iteration_budget=2**63),
        dict(max_restarts=2**63),
        dict(max_iterations=2**64),
        dict(max_solutions=10**10),
    ],
)
def test_absurd_counts_are_refused(options):
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle)
    with pytest.raises(OptionError, match="at most"):
        ur5.solve(T, solver="dls", **options)
    with pytest.raises(OptionError, match="at most"):
        ur5.solve_all(T, solver="dls", **options)


@pytest.mark.parametrize("solver", ["auto", "dls", "qp"])
def test_infinite_seed_on_a_continuous_joint_is_refused(solver):
    # Its limits are +-inf: the range test alone let the compiled entries take inf.
    kinova = arm("kinova")
    assert math.isinf(kinova.upper[-1])
    q0 = kinova.middle.copy()
    q0[-1] = np.inf
    T = kinova.fk(kinova.middle)
    for call in (kinova.solve, kinova.solve_all):
        with pytest.raises(OptionError, match="q0 must be finite"):
            call(T, q0=q0, solver=solver)


def test_complex_batch_seeds_are_refused():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle)
    for q0 in (ur5.middle + 0.5j, np.tile(ur5.middle + 0.5j, (2, 1))):
        with pytest.raises(OptionError, match="real numbers"):
            ur5.solve_batch([T, T], q0=q0, progress=False)


def test_within_limits_takes_a_list():
    ur5 = arm("ur5")
    assert ur5.within_limits(list(ur5.middle)) and not ur5.within_limits([99.0] * 6)


def test_largest_accepted_limits_keep_the_arithmetic_finite(tmp_path):
    big = '<limit lower="-1e6" upper="1e6" effort="1" velocity="1"/>'
    text = chain(
        joint("j1", "base", "l1", limit=big),
        joint("slide", "l1", "l2", jtype="prismatic", axis='<axis xyz="1 0 0"/>', limit=big),
        joint("j3", "l2", "l3", xyz="0.3 0 0", axis='<axis xyz="0 1 0"/>', limit=big),
        joint("tool_joint", "l3", "tool", jtype="fixed", xyz="0.2 0 0"),
    )
    with pytest.warns(ArmikWarning, match="beyond four turns") as said:
        a = armik.load(write_urdf(tmp_path, text))
    assert sorted(str(w.message).split("'")[1] for w in said) == ["j1", "j3"]  # not in m
    assert np.isfinite(a.random_q(1)).all()
    target = a.fk(np.array([0.3, 0.5, -0.2]))
    for solver in ("dls", "qp"):
        r = a.solve(target, solver=solver, timeout=0.05)  # no exception, success or not
        assert r.success or r.reason
        r = a.solve(target.translation + [1e5, 0, 0], solver=solver, timeout=0.02)
        assert np.isfinite(r.q).all()


def test_every_error_here_is_an_armik_error():
    assert issubclass(OptionError, ArmikError) and issubclass(TargetError, ValueError)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        armik.load("ur5")  # a bundled arm loads without warnings
