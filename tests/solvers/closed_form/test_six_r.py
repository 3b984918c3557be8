"""The closed-form 6R solvers: FK round trips, completeness, branches, singular and
unreachable cases, on the bundled arms and on mounted/tooled variants."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import SolverError
from armik.solvers.closed_form import spherical_wrist, three_parallel
from armik.status import Status

from ...analytic_urdfs import IRB120, MEETING_12, UR5, six_r
from ...conftest import TOL, arm, write_urdf

MOUNTED = dict(mount_xyz="0.1 -0.2 0.3", mount_rpy="0.3 -0.2 1.0")
TOOLED = dict(tool_xyz="0.01 0.02 0.15", tool_rpy="0.5 0.1 -0.3")
FAMILY = {"spherical_wrist": "spherical", "three_parallel": "three_parallel"}


def wrapped(a):
    return np.abs(np.arctan2(np.sin(a), np.cos(a)))


def variant(tmp_path, joints, **kw) -> armik.Arm:
    return armik.load(write_urdf(tmp_path, six_r(joints, **kw)), base="world", tip="tool")


def arms(tmp_path):
    """The bundled arms with a closed form and variants with mounts and tools."""
    yield arm("ur5"), "three_parallel"
    yield arm("ur10"), "three_parallel"
    yield arm("z1"), "three_parallel"
    yield arm("abb_irb120"), "spherical"
    yield arm("kinova"), "spherical"
    yield armik.load("ur5", tip_offset=(0.02, -0.01, 0.12)), "three_parallel"
    yield variant(tmp_path, UR5, **MOUNTED, **TOOLED), "three_parallel"
    yield variant(tmp_path, IRB120, **MOUNTED, **TOOLED), "spherical"
    yield variant(tmp_path, MEETING_12, **MOUNTED, **TOOLED), "spherical"


def pose_error(a, q, T):
    return np.linalg.norm(pin.log6(a.fk(q).inverse() * T).vector)


def test_round_trips_and_completeness(tmp_path):
    """Every target from a random configuration: auto picks the family, every success is
    an FK round trip within the limits, and the generating configuration is among
    solve_all's answers (modulo 2 pi) whenever no answer is singular."""
    rng = np.random.default_rng(3)
    for a, solver in arms(tmp_path):
        complete = 0
        for _ in range(25):
            q = a.random_q(rng)
            T = a.fk(q)
            results = a.solve_all(T)
            assert results[0].solver == solver
            ok = [r for r in results if r.success]
            assert ok, results[0].reason
            for r in ok:
                assert pose_error(a, r.q, T) < 1e-9 and a.within_limits(r.q)
            assert len({r.branch for r in results}) == len(results)
            if any(r.singular for r in results):
                continue
            assert min(wrapped(r.q - q).max() for r in ok) < 1e-7, (a.name, q)
            complete += 1
        assert complete >= 20


def test_solve_nearest_q0_and_its_equivalent(rng):
    """With q0 at the generating configuration, solve returns it (angles beyond pi too)."""
    for name in ("ur5", "abb_irb120", "kinova"):
        a = arm(name)
        for _ in range(20):
            q = a.random_q(rng)
            r = a.solve(a.fk(q), q0=q)
            assert r.success and np.abs(r.q - q).max() < 1e-7, (name, q, r.q)


def test_eight_distinct_solutions_labelled():
    a = arm("ur5")
    q = np.array([0.4, -1.1, 1.3, -0.8, 1.2, 0.3])
    results = a.solve_all(a.fk(q))
    assert len(results) == 8 and all(r.success for r in results)
    assert len({r.branch for r in results}) == 8
    for i, r in enumerate(results):
        for s in results[i + 1 :]:
            assert wrapped(r.q - s.q).max() > 1e-3
    assert all(r.branch.count("/") == 2 for r in results)


def test_branch_labels_describe_the_pose():
    """Labels come from the geometry: the IRB 120 reaching forward with the elbow above
    the shoulder-wrist line and the wrist bent positively; the UR5 in its usual pose."""
    a = arm("abb_irb120")
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    assert a.solve(a.fk(q), q0=q).branch == "shoulder-front/elbow-up/wrist-no-flip"
    flipped = q + np.array([0, 0, 0, math.pi, 0, math.pi])
    flipped[4] = -q[4]
    flipped[3] -= 2 * math.pi
    r = a.solve(a.fk(q), q0=flipped)
    assert r.branch == "shoulder-front/elbow-up/wrist-flip" and r.q[4] < 0
    u = arm("ur5")
    q = np.array([0.1, -1.2, 1.3, -1.5, -1.5, 0.6])
    assert u.solve(u.fk(q), q0=q).branch == "shoulder-front/elbow-up/wrist-flip"
    labels = {r.branch for r in u.solve_all(u.fk(q))}
    assert len(labels) == 8


def test_joint_limits_cut_branches():
    """The IRB 120's axis 3 (-110, +70 deg) excludes some branches: those come back as
    joint_limits failures in solve_all, and solve picks a branch within the limits."""
    a = arm("abb_irb120")
    q = np.array([0.3, 0.2, 0.5, 0.4, 0.6, -0.2])
    results = a.solve_all(a.fk(q))
    assert any(r.status is Status.JOINT_LIMITS for r in results)
    best = a.solve(a.fk(q), q0=np.zeros(6))
    assert best.success and a.within_limits(best.q)


def test_wrist_singularity_keeps_q4_at_q0():
    for name, q, free in [
        ("abb_irb120", [0.2, 0.3, -0.4, 0.5, 0.0, 0.7], 3),  # axes 4 and 6 aligned
        ("ur5", [0.2, -1.0, 1.2, -0.5, 0.0, 0.7], 5),  # axes 2 and 6 aligned
    ]:
        a = arm(name)
        q = np.array(q)
        q0 = q + 0.1
        r = a.solve(a.fk(q), q0=q0)
        assert r.success and r.singular and "singular" in r.reason
        assert r.q[free] == q0[free]
        assert np.isfinite(r.q).all()


def test_wrist_singularity_turns_q6_only_as_far_as_the_elbow_needs():
    """On the UR family at q5 = 0 or pi, keeping q6 at q0 can put the wrist point out of
    the elbow's reach (8 % of such targets with a random q0 came back unreachable): q6
    then turns just enough for the elbow to reach, stretched or folded."""
    rng = np.random.default_rng(12)
    for name in ("ur5", "ur10"):
        a = arm(name)
        kept = turned = 0
        for _ in range(150):
            q = a.random_q(rng)
            q[4] = rng.choice([0.0, math.pi, -math.pi])
            T = a.fk(q)
            q0 = a.random_q(rng)
            r = a.solve(T, q0=q0)
            assert r.success and a.within_limits(r.q), r.reason
            assert pose_error(a, r.q, T) < 1e-6
            if not r.singular:
                continue  # the other shoulder branch is not singular: nearer q0
            if r.q[5] == q0[5]:
                kept += 1
            else:
                turned += 1
                assert abs(math.sin(r.q[2])) < 1e-4, r.q  # the elbow at the edge of its reach
        assert kept > 0 and turned > 0


def test_joints_on_their_limits():
    """A target from a configuration with joints exactly on their limits: the closed
    form's rounding (1e-12) may not put that joint outside its limit."""
    rng = np.random.default_rng(13)
    for name in ("kinova", "abb_irb120"):
        a = arm(name)
        bounded = np.isfinite(a.lower) & np.isfinite(a.upper)
        for _ in range(40):
            q = a.random_q(rng)
            on = bounded & (rng.random(a.dof) < 0.5)
            q[on] = np.where(rng.random(on.sum()) < 0.5, a.lower[on], a.upper[on])
            T = a.fk(q)
            r = a.solve(T, q0=q)
            assert r.success and a.within_limits(r.q), r.reason
            found = [x.q for x in a.solve_all(T, q0=q) if x.success]
            assert any(wrapped(x - q).max() < 1e-6 for x in found)  # its own configuration


def test_elbow_stretched_is_singular_and_branches_merge():
    a = arm("ur5")
    q = np.array([0.2, -1.0, 0.0, -0.5, 0.8, 0.7])  # q3 = 0: upper arm and forearm aligned
    results = a.solve_all(a.fk(q))
    assert all(r.singular for r in results if r.success)
    assert len(results) == 4
    b = arm("abb_irb120")
    q3 = math.atan2(-0.302, 0.07)  # forearm along the upper arm
    q = np.array([0.2, 0.1, q3, 0.5, 0.6, 0.7])
    r = b.solve(b.fk(q), q0=q)
    assert r.success and r.singular and np.abs(r.q - q).max() < 1e-6


def test_shoulder_singularity_keeps_q1_at_q0():
    a = arm("abb_irb120")
    geo = spherical_wrist.classify(a.kinematics)
    R = pin.rpy.rpyToMatrix(0.1, 2.5, 0.3)
    wrist = np.array([0.0, 0.0, 0.8])  # on axis 1
    p = wrist + R @ geo.R_tip0.T @ geo.p[6]
    q0 = np.array([0.4, 0.0, 0.0, 0.0, 0.5, 0.0])
    r = a.solve(pin.SE3(R, p), q0=q0)
    assert r.success and r.singular and r.q[0] == q0[0]


@pytest.mark.parametrize(
    "rpy, height",
    [((-0.39, 2.85, 2.39), 0.64), ((1.08, 2.22, -1.64), 0.66), ((1.84, -1.1, -2.11), 0.58)],
)
def test_a_free_joint_leaves_q0_where_q0s_value_breaks_a_limit(rpy, height):
    # the wrist centre on axis 1: with joint 1 at q0's value every row breaks a limit, at
    # another value of it the pose is reached within them
    a = arm("abb_irb120")
    geo = spherical_wrist.classify(a.kinematics)
    R = pin.rpy.rpyToMatrix(*rpy)
    T = pin.SE3(R, np.array([0.0, 0.0, height]) + R @ geo.R_tip0.T @ geo.p[6])
    q0 = a.middle
    r = a.solve(T, q0=q0)
    assert r.success and r.singular and r.solver == "spherical", r.reason
    assert r.q[0] != q0[0] and abs(r.q[0] - q0[0]) <= math.pi
    good = [x for x in a.solve_all(T, q0=q0) if x.success]
    assert good and all(a.within_limits(x.q) and pose_error(a, x.q, T) < 1e-9 for x in good)
    stuck = a.with_limits({a.joint_names[0]: (q0[0] - 1e-3, q0[0] + 1e-3)})
    assert not any(x.success for x in stuck.solve_all(T, q0=q0))  # q0's value reaches none


def test_a_free_wrist_leaves_q0_where_q0s_value_breaks_a_limit():
    # the UR5's wrists limited: at the wrist singularity joint 6 at q0's value can leave
    # every row outside the limits of a pose q, within them, reaches
    ur5 = arm("ur5")
    names = ur5.joint_names
    a = ur5.with_limits({names[3]: (-1.0, 1.0), names[5]: (-0.8, 0.8), names[0]: (-1.5, 1.5)})
    rng = np.random.default_rng(3)
    moved = 0
    for _ in range(60):
        q = a.random_q(rng)
        q[4] = 0.0
        if not a.within_limits(q):
            continue
        T = a.fk(q)
        good = [r for r in a.solve_all(T) if r.success]
        assert good and all(a.within_limits(r.q) and pose_error(a, r.q, T) < 1e-9 for r in good)
        moved += any(r.singular and r.q[5] != a.middle[5] for r in good)
    assert moved  # the case: q0's joint 6 did not do


def test_unreachable_says_why_and_gives_a_configuration():
    a = arm("abb_irb120")
    R = pin.rpy.rpyToMatrix(0.0, math.pi / 2, 0.0)
    far = a.solve(pin.SE3(R, np.array([2.0, 0.0, 0.5])))
    assert not far.success and far.status is Status.UNREACHABLE
    assert "too far" in far.reason and np.isfinite(far.q).all()
    geo = spherical_wrist.classify(a.kinematics)
    p = np.array([0.02, 0.0, 0.29]) + R @ geo.R_tip0.T @ geo.p[6]  # wrist near axis 2
    close = a.solve(pin.SE3(R, p))
    assert not close.success and "too close" in close.reason and np.isfinite(close.q).all()

    u = arm("ur5")
    geo = three_parallel.classify(u.kinematics)
    R = pin.rpy.rpyToMatrix(0.3, 0.2, 0.1)
    p = np.array([0.01, 0.0, 0.4]) + geo.p[0] + R @ geo.R_tip0.T @ geo.p[6]
    inside = u.solve(pin.SE3(R, p))
    assert not inside.success and inside.status is Status.UNREACHABLE
    assert "shoulder offset" in inside.reason and np.isfinite(inside.q).all()
    assert "too far" in u.solve(pin.SE3(R, np.array([0.0, 2.0, 0.3]))).reason


def test_closest_configuration_when_too_far():
    """Out of reach, q is the arm stretched towards the target: nearer than the
    configurations of random solves."""
    a = arm("ur5")
    target = pin.SE3(np.eye(3), np.array([1.5, 0.3, 0.4]))
    r = a.solve(target)
    d = np.linalg.norm(a.fk(r.q).translation - target.translation)
    assert 1.5 - 1.0 < d < 0.8


def test_position_target_goes_numeric():
    a = arm("ur5")
    assert a.solve([0.4, 0.1, 0.3]).solver == "dls"
    with pytest.raises(SolverError, match="needs a full pose"):
        a.solve([0.4, 0.1, 0.3], solver="three_parallel")
    assert a.solve(a.fk(np.full(6, 0.3)), position_only=True).solver == "dls"


def test_numeric_solvers_still_agree(rng):
    """dls lands on one of the closed form's branches."""
    a = arm("abb_irb120")
    q = a.random_q(rng)
    T = a.fk(q)
    r = a.solve(T, solver="dls", q0=q + 0.05)
    assert r.success
    closed = [s.q for s in a.solve_all(T) if s.success]
    assert min(wrapped(s - r.q).max() for s in closed) < 1e-4
    assert pose_error(a, r.q, T) < TOL["solve"] * 10


def test_run_batch_matches_solve(rng):
    """The compiled batch path returns, per target, the answer ``solve`` picks."""
    from armik.options import Options
    from armik.solvers.closed_form import spherical_wrist as spherical
    from armik.solvers.closed_form import three_parallel
    from armik.targets.batch import TargetBatch

    for name, family in (("ur5", three_parallel), ("abb_irb120", spherical)):
        a = arm(name)
        qs = np.array([a.random_q(rng) for _ in range(30)])
        poses = [a.fk(q) for q in qs]
        targets = TargetBatch(
            np.array([T.translation for T in poses]), np.array([T.rotation for T in poses])
        )
        q0 = np.clip(qs + 0.2, a.lower, a.upper)
        out = family.SPEC.run_batch(a.kinematics, targets, q0, Options())
        assert out.q.shape == (30, 6) and (out.claim == Status.CONVERGED.code).all()
        for T, q, q0i in zip(poses, out.q, q0):
            assert np.abs(q - a.solve(T, q0=q0i).q).max() < 1e-9
        with pytest.raises(SolverError, match="full poses"):
            family.SPEC.run_batch(a.kinematics, TargetBatch(targets.positions), q0, Options())


@pytest.mark.parametrize(
    "name, joint, at",
    [("ur5", 4, 0.0), ("ur5", 2, 0.0), ("abb_irb120", 4, 0.0), ("kinova", 4, math.pi)],
)
def test_near_singular_configurations(name, joint, at):
    """Approaching a singularity (wrist or elbow) the answers stay verified; close enough
    (1e-8 rad) they are flagged singular and the free angle keeps the generating value."""
    a = arm(name)
    rng = np.random.default_rng(11)
    for eps in (1e-4, 1e-6, 1e-7, 1e-8, 1e-10, 0.0):
        for _ in range(10):
            q = a.random_q(rng)
            q[joint] = at + eps
            r = a.solve(a.fk(q), q0=q)
            assert r.success, (eps, r.reason)
            assert pose_error(a, r.q, a.fk(q)) < 1e-6
            if eps <= 1e-8:
                assert r.singular and np.abs(r.q - q).max() < 1e-6, (eps, q, r.q)


def test_base_frame_limits_and_pickling(tmp_path):
    """A base frame below the root (mount), replaced limits and a pickled arm keep the
    closed form exact."""
    import pickle

    path = write_urdf(tmp_path, six_r(UR5, **MOUNTED, **TOOLED))
    a = armik.load(path, base="l0", tip="tool")
    assert three_parallel.classify(a.kinematics).kind == "three_parallel"
    q = np.array([0.3, -0.9, 1.1, -0.4, 0.7, 0.2])
    r = a.solve(a.fk(q), q0=q)
    assert r.solver == "three_parallel" and np.abs(r.q - q).max() < 1e-9
    tight = a.with_limits({"j3": (0.0, 2.0)})  # only the positive elbow stays
    results = tight.solve_all(tight.fk(q))
    assert all(s.q[2] >= 0 for s in results if s.success)
    assert any(s.status is Status.JOINT_LIMITS for s in results)
    b = pickle.loads(pickle.dumps(a))
    assert np.abs(b.solve(b.fk(q), q0=q).q - q).max() < 1e-9


def test_a_batch_passes_writable_seeds_as_the_prepared_solve_does(monkeypatch):
    """``kernel_many`` calls the kernel with each target's seed: a read-only one (an (N, 6)
    q0 broadcast again is a read-only view) would compile the kernel a second time, for
    read-only arrays, where ``solve_into`` passes writable seeds."""
    from armik.options import Options
    from armik.targets.batch import TargetBatch

    a = arm("ur5")
    family = three_parallel.SPEC.run_batch.__self__
    got = []

    def kernel_many(chain, Rs, ps, q0s):
        got.append(q0s)
        return np.zeros((len(ps), 6)), np.zeros(len(ps), np.int8)

    monkeypatch.setattr(family, "kernel_many", kernel_many)
    poses = [a.fk(q) for q in a.random_q(3, n=4)]
    targets = TargetBatch(
        np.array([T.translation for T in poses]), np.array([T.rotation for T in poses])
    )
    for q0 in (a.middle.copy(), np.tile(a.middle, (4, 1))):
        q0.flags.writeable = False
        family.run_batch(a.kinematics, targets, q0, Options())
    assert len(got) == 2
    for q0s in got:
        assert q0s.flags.writeable and q0s.flags.c_contiguous and q0s.shape == (4, 6)


@pytest.mark.parametrize(
    "q",
    [[1.2, 2.6, math.pi, 1.4, 3.3, -1.2], [-0.1, 4.9, math.pi, -0.9, 3.5, -1.1]],
)
def test_kinova_stretched_elbow_is_one_branch_flagged_singular(q):
    # the model's rounding (1e-12 m) split the stretched elbow's double root into two roots
    # ~5e-6 rad apart: 8 answers in 4 pairs, none flagged singular
    a = arm("kinova")
    T = a.fk(np.array(q))
    found = [r for r in a.solve_all(T) if r.success]
    assert len(found) == 4 and all(r.singular for r in found)
    for i, r in enumerate(found):
        assert all(wrapped(r.q - s.q).max() > 1e-3 for s in found[:i])
        got = a.fk(r.q)
        assert np.linalg.norm(got.translation - T.translation) < 1e-12
        assert np.linalg.norm(pin.log3(got.rotation.T @ T.rotation)) < 1e-12


def test_a_span_along_axis_2_leaves_joint_2_free_at_q0s_value():
    # the iiwa with joint 1 held and its elbow stretched: joints 2 to 7 are a spherical wrist
    # whose axes 1 and 2 meet, and the span lies along axis 2 (iiwa joint 3), so that joint
    # is free; SP2 at its degenerate circles gave rows in duplicate, joint 3 at 0 or pi, 1e-10 m off
    a = arm("kuka_iiwa14")
    q = np.array([1.641, 1.0836, 0.7, 0.0, -1.5708, 1.2, -0.5])
    T = a.fk(q)
    hold = {"iiwa_joint_1": float(q[0])}
    found = [r for r in a.solve_all(T, hold=hold, q0=q) if r.success]
    assert len(found) == 2 and all(r.singular and r.q[2] == q[2] for r in found)
    assert wrapped(found[0].q - found[1].q).max() > 1e-3
    for r in found:
        got = a.fk(r.q)
        assert np.linalg.norm(got.translation - T.translation) < 1e-12
        assert np.linalg.norm(pin.log3(got.rotation.T @ T.rotation)) < 1e-12
    r = a.solve(T, hold=hold, q0=q)
    assert r.success and np.abs(r.q - q).max() < 1e-12
