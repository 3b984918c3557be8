"""A prismatic joint without limits (a rail whose URDF limits read "0 0", or widened by
``with_limits``): restarts along it start where it brings the tip nearest the target, so a
target tens or hundreds of metres along it is reached; they started within [-pi, pi] m and
a step moves at most 1 m, so it never was (``solvers/numeric/rails.py``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers.numeric import rails

from .test_long_rail import GANTRY
from .test_slides import XYZ


def _arms():
    xyz = armik.load_string(XYZ).with_limits({"px": (-np.inf, np.inf)})
    arm = armik.load_string(GANTRY.replace("RAIL", "10")).with_limits({"px": (0.0, np.inf)})
    return (("xyz", xyz, "px"), ("gantry with a wrist", arm, "px"))


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_targets_far_along_an_unlimited_rail_are_reached(solver):
    """At 50, 150 and 500 m along the rail, by ``solve`` (its prepared plan and the general
    path), ``solve_all`` and ``solve_batch``: each answer checked by Pinocchio's FK."""
    for _, arm, rail in _arms():
        i = arm.joint_names.index(rail)
        targets = []
        for d in (50.0, 150.0, 500.0):
            q = np.asarray(arm.middle).copy()
            q[~np.isfinite(q)] = 0.0
            q[i] = d
            targets.append(arm.fk(q))
        for T in targets:
            for target in (T, (T.translation.copy(), T.rotation.copy())):
                r = arm.solve(target, solver=solver, seed=0)
                assert r.success, r.reason
                assert np.linalg.norm(pin.log6(arm.fk(r.q).actInv(T)).vector) < 1e-5
            every = arm.solve_all(T, solver=solver, seed=0)
            assert every and all(x.success for x in every)
        b = arm.solve_batch(targets, solver=solver, seed=0, workers=1, progress=False)
        assert b.success.all()
        for k, T in enumerate(targets):
            assert np.linalg.norm(pin.log6(arm.fk(b.q[k]).actInv(T)).vector) < 1e-5


def test_the_restart_box_is_centred_toward_the_target_and_others_untouched():
    """The rail's box is 2 pi wide around the value that brings the tip nearest the target
    (the other joints at q0), inside a one-sided limit; an arm without such a joint keeps
    its chain."""
    _, arm, _ = _arms()[1]
    kin = arm.kinematics
    joints = rails.UNLIMITED(kin)
    assert joints.tolist() == [arm.joint_names.index("px")]
    q0 = np.asarray(arm.middle).copy()
    q0[~np.isfinite(q0)] = 0.0
    q = q0.copy()
    q[joints[0]] = 321.0
    p = arm.fk(q).translation
    assert rails.centres(kin, p, q0, joints) == pytest.approx([321.0], abs=1e-9)
    flat = rails.toward(kin, p, q0, joints)
    ch = kin.kernel_chain.chain
    at = 15 * len(ch.joint_kind) + 12 + 2 * arm.dof
    assert flat.packed[at + joints[0]] == pytest.approx(321.0 - np.pi)
    assert flat.packed[at + arm.dof + joints[0]] == pytest.approx(2 * np.pi)
    rest = np.ones(len(flat.packed), dtype=bool)
    rest[[at + joints[0], at + arm.dof + joints[0]]] = False
    np.testing.assert_array_equal(flat.packed[rest], kin.kernel_chain.flat.packed[rest])
    q[joints[0]] = -50.0  # beyond the lower limit 0: the box starts at it
    low = rails.toward(kin, arm.fk(q).translation, q0, joints)
    assert low.packed[at + joints[0]] == 0.0
    for name in ("ur5", "kinova", "scara"):
        assert len(rails.UNLIMITED(armik.load(name).kinematics)) == 0


def test_a_batch_s_centres_come_from_one_call_of_the_kernel_s_fk(monkeypatch):
    """``solve_batch`` on a rail arm: every row's centre from one ``kernel.fk_many`` call
    (the kernel's FK, not one written again, nor one a row), each the single solve's
    ``centres``, and every row solved (checked by Pinocchio's FK)."""
    _, arm, _ = _arms()[1]
    kin = arm.kinematics
    joints = rails.UNLIMITED(kin)
    calls = []
    real = rails.fk_many

    def counted(*args):
        calls.append(len(args[3]))
        return real(*args)

    monkeypatch.setattr(rails, "fk_many", counted)
    rng = np.random.default_rng(2)
    Q = np.array([arm.random_q(rng) for _ in range(6)])
    Q[:, joints[0]] = [3.0, 40.0, 90.0, 250.0, 0.5, 700.0]
    targets = [arm.fk(q) for q in Q]
    b = arm.solve_batch(targets, solver="dls", seed=0, workers=1, progress=False)
    assert calls == [6 * (1 + len(joints))]
    assert b.success.all()
    for k, T in enumerate(targets):
        assert np.linalg.norm(pin.log6(arm.fk(b.q[k]).actInv(T)).vector) < 1e-5
    q0 = np.tile(np.where(np.isfinite(arm.middle), arm.middle, 0.0), (6, 1))
    P = np.array([T.translation for T in targets])
    many = rails.centres_many(kin, P, q0, joints)
    for k in range(6):
        np.testing.assert_allclose(many[k], rails.centres(kin, P[k], q0[k], joints), atol=1e-9)
    np.testing.assert_allclose(many[:, 0], Q[:, joints[0]], atol=0.5)  # the wrist's reach


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_the_centre_holds_with_q0_far_along_the_rails(solver):
    """q0 1e6 to 1e300 m along one rail, and along two: the centres come from the rails at
    0 and 1 m, not from q0 plus 1 m (which rounds back to q0 beyond 1e16 m, a division by
    0 and a NaN box); the target near the origin is reached (checked by Pinocchio's FK)."""
    one = armik.load_string(XYZ).with_limits({"px": (-np.inf, np.inf)})
    two = one.with_limits({"py": (-np.inf, np.inf)})
    for arm, p in ((one, [5.0, 0.2, -0.1]), (two, [50.0, -30.0, -0.2])):
        joints = rails.UNLIMITED(arm.kinematics)
        for far in (1e6, 1e17, 1e300):
            q0 = np.array([0.0, 0.0, 0.1])
            q0[joints] = far
            got = rails.centres(arm.kinematics, np.array(p), q0, joints)
            np.testing.assert_allclose(got, np.array(p)[joints], atol=1e-9)
            r = arm.solve(np.array(p), q0=q0, solver=solver, seed=0)
            assert r.success, r.reason
            assert np.linalg.norm(arm.fk(r.q).translation - p) < 1e-6
