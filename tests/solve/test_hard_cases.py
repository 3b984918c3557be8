"""Bad options, hard targets, properties over every arm, threads and repeatability."""

from __future__ import annotations

import math
import threading
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armik
from armik import ArmikWarning, OptionError
from armik.verify.measure import measure

from ..conftest import ALL_ROBOTS, SPATIAL, arm


@pytest.mark.parametrize(
    "options, words",
    [
        ({"timeout": 0}, "timeout must be > 0"),
        ({"timeout": -1.0}, "timeout must be > 0"),
        ({"tol_position": 0.0}, "tol_position must be > 0"),
        ({"tol_orientation": float("nan")}, "finite"),
        ({"max_restarts": -1}, "max_restarts must be >= 0"),
        ({"max_restarts": 1.5}, "integer"),
        ({"max_iterations": 0}, ">= 1"),
        ({"weights": (1, 1, 1)}, "6 finite"),
        ({"weights": (0, 0, 0, 0, 0, 0)}, "not all zero"),
        ({"qp_solver": 3}, "backend name"),
        ({"tolerance": 1e-3}, "unknown option 'tolerance'"),
        ({"seed": 2**63}, "seed must be < 2"),
        ({"seed": -1}, "seed must be >= 0"),
        ({"timeout": 1e300}, "timeout must be at most 1e\\+06 s"),  # overflowed the budget
        ({"timeout": float("inf")}, "timeout must be finite"),
        ({"tol_position": 1e300}, "tol_position must be at most"),
        ({"tol_orientation": 4.0}, "tol_orientation must be at most 3.14"),
    ],
)
def test_bad_options(options, words):
    with pytest.raises(OptionError, match=words):
        arm("ur5").solve([0.4, 0.1, 0.3], **options)


def test_missing_qp_backend_is_named():
    with pytest.raises(armik.SolverError, match="'nosuchqp' is not installed"):
        arm("ur5").solve([0.4, 0.1, 0.3], solver="qp", qp_solver="nosuchqp")


@pytest.mark.parametrize(
    "q0, words",
    [
        ([0.0] * 5, "q0 must have 6"),
        ([0.0] * 5 + [math.nan], "finite"),
        ("abc", "6 numbers"),
    ],
)
def test_bad_q0(q0, words):
    with pytest.raises(OptionError, match=words):
        arm("ur5").solve([0.4, 0.1, 0.3], q0=q0)


def test_q0_outside_limits_is_clipped_with_warning():
    a = arm("panda")
    with pytest.warns(ArmikWarning, match="panda_joint4 = 0 outside"):
        r = a.solve(a.fk(a.middle), q0=np.zeros(7))  # all zeros: joint 4 is outside
    assert r.success
    # a hair outside: six digits read "2.8973 outside [-2.8973, 2.8973]"; the excess says why
    q0 = a.middle.copy()
    q0[0], q0[3] = a.upper[0] + 1e-9, a.lower[3] - 2e-9
    with pytest.warns(ArmikWarning) as caught:
        a.solve(a.fk(a.middle), q0=q0)
    text = str(caught[0].message)
    assert "panda_joint1 is 1e-09 past its upper limit 2.8973; " in text, text
    assert "panda_joint4 is 2e-09 past its lower limit -3.0718" in text, text


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_seed_at_singular_configuration(name):
    a = arm(name)
    q_true = a.random_q(np.random.default_rng(11))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ArmikWarning)
        r = a.solve(a.fk(q_true), q0=np.zeros(a.dof))
    assert r.success and np.all(np.isfinite(r.q))


def test_exact_full_stretch_and_base():
    a = arm("planar_2link")
    r = a.solve([1.8, 0.0])
    assert r.success and r.singular
    r = a.solve([0.0, 0.0])
    assert r.status == "unreachable" and np.all(np.isfinite(r.q))


@pytest.mark.parametrize("name", SPATIAL + ["planar_3link", "scara"])
def test_far_target_is_answered_without_a_search(name):
    """A target 37 m away is refused by the reach bound before any iteration or restart
    (counted, not timed: a loaded machine's clock says nothing of the search)."""
    a = arm(name)
    r = a.solve([30.0, -20.0, 10.0], timeout=0.02)
    assert not r.success and r.status == "unreachable"
    assert r.iterations == 0 and r.restarts == 0 and "beyond the arm's reach" in r.reason


def test_target_reachable_only_outside_limits():
    a = arm("panda")
    q = a.middle.copy()
    q[3] = 0.4  # joint 4 must stay below -0.07: this elbow bend is forbidden
    r = a.solve(a.fk(q), timeout=0.02)
    assert a.within_limits(np.asarray(r.q), tol=0.0)
    if r.success:  # another configuration in the limits may reach the same pose
        assert r.position_error <= 1e-6 and r.orientation_error <= 1e-6
    else:
        assert r.status in ("not_converged", "joint_limits")


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    name=st.sampled_from(ALL_ROBOTS),
    seed=st.integers(0, 2**31 - 1),
    solver=st.sampled_from(["auto", "dls", "qp"]),
)
def test_property_verified_or_honestly_failed(name, seed, solver):
    a = arm(name)
    rng = np.random.default_rng(seed)
    q_true = a.random_q(rng)
    T = a.fk(q_true)
    target = T.translation if a.kinematics.plane is not None else T
    r = a.solve(target, q0=a.random_q(rng), solver=solver, timeout=0.02)
    assert np.all(np.isfinite(r.q))
    if r.success:
        check = measure(
            a.kinematics,
            np.asarray(r.q),
            armik.parse_target(target, a.kinematics),
            armik.options.Options(),
        )
        assert check.ok and a.within_limits(np.asarray(r.q))
    else:
        assert r.status in ("not_converged", "unreachable", "joint_limits") and r.reason


def test_threads_give_the_same_answers():
    a = armik.load("panda")  # its own instance: no other test touches it
    rng = np.random.default_rng(5)
    targets = [a.fk(a.random_q(rng)) for _ in range(40)]
    sequential = [np.asarray(a.solve(T, q0=a.middle).q) for T in targets]
    out: dict[int, list] = {0: [], 1: []}

    def work(k):
        out[k] = [np.asarray(a.solve(T, q0=a.middle).q) for T in targets]

    threads = [threading.Thread(target=work, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in (0, 1):
        for x, y in zip(out[k], sequential):
            np.testing.assert_array_equal(x, y)


def test_same_seed_same_answer_across_calls():
    a = arm("xarm7")
    rng = np.random.default_rng(9)
    T = a.fk(a.random_q(rng))
    q0 = a.random_q(rng)
    answers = {tuple(a.solve(T, q0=q0, seed=3, solver=s).q) for s in ["dls"] * 3}
    assert len(answers) == 1


def test_result_is_frozen_and_keyword_only():
    r = arm("planar_2link").solve([1.2, 0.5])
    with pytest.raises(AttributeError):
        r.success = False  # type: ignore[misc]
    with pytest.raises(ValueError):
        r.q[0] = 1.0
    with pytest.raises(TypeError):
        armik.IKResult(r.q, True)  # type: ignore[misc]
