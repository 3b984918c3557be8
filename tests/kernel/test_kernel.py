"""The compiled kernel against Pinocchio, and the solvers that run through it."""

from __future__ import annotations

import math
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import OptionError
from armik.kernel import fk, se3
from armik.kernel.chain import CONTINUOUS, PRISMATIC
from armik.options import Options
from armik.solvers import registry
from armik.solvers.numeric import driver as numeric
from armik.status import Status
from armik.targets.batch import TargetBatch
from armik.targets.pose import parse_target
from armik.verify.measure import measure, measure_batch

from ..conftest import ALL_ROBOTS, SPATIAL, arm, model

EXACT = 1e-12  # the kernel's kinematics against Pinocchio's


def _load(name, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load(name, **kw)


# Every bundled arm, plus a non-root base and tip offsets.
CHAINS = [(name, {}) for name in ALL_ROBOTS] + [
    ("panda", {"base": "panda_link2"}),
    ("ur5", {"tip_offset": (0.05, -0.02, 0.1)}),
    ("kinova", {"base": "j2s6s200_link_2", "tip_offset": (0.0, 0.0, 0.12)}),
    ("ur5", {"tip": "shoulder_link", "tip_offset": (0.3, 0.0, 0.0)}),  # one joint
]


@pytest.mark.parametrize(("name", "kw"), CHAINS)
def test_fk_and_jacobian_match_pinocchio(name, kw):
    a = _load(name, **kw)
    flat = a.kinematics.kernel_chain.flat
    n = a.dof
    R, p = np.empty((3, 3)), np.empty(3)
    origins, axes, J = np.empty((n, 3)), np.empty((n, 3)), np.empty((6, n))
    rng = np.random.default_rng(11)
    for _ in range(200):
        q = a.random_q(rng)
        fk.forward(flat, q, R, p, origins, axes)
        fk.jacobian_local(flat, R, p, origins, axes, J)
        T = a.fk(q)  # Pinocchio, in the base frame
        np.testing.assert_allclose(R, T.rotation, rtol=0, atol=EXACT)
        np.testing.assert_allclose(p, T.translation, rtol=0, atol=EXACT)
        # (Pinocchio hands a one-column Jacobian back as a vector)
        np.testing.assert_allclose(J, np.reshape(a.jacobian(q), (6, n)), rtol=0, atol=EXACT)


@pytest.mark.parametrize(("name", "kw"), CHAINS)
def test_joint_frames_match_pinocchio(name, kw):
    # the collision bounds place the link spheres by these frames
    a = _load(name, **kw).kinematics
    H = np.empty((a.model.njoints, 4, 4))
    rng = np.random.default_rng(12)
    for _ in range(50):
        q = a.random_q(rng)
        fk.joint_frames(a.kernel_chain.flat, q, H)
        pin.forwardKinematics(a.model, a.data, a.to_pin(q))
        for j in range(a.model.njoints):
            want = (a.T_base_world * a.data.oMi[j]).homogeneous
            np.testing.assert_allclose(H[j], want, rtol=0, atol=EXACT)


def test_joint_kinds_read_from_the_model():
    assert list(model("scara").kernel_chain.kind) == [0, 0, PRISMATIC, CONTINUOUS]
    kinds = model("kinova").kernel_chain.kind
    assert sum(k == CONTINUOUS for k in kinds) == 3
    assert _load("panda", base="panda_link2").dof == 5


def _random_pose(rng, angle=None):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    theta = rng.uniform(0, math.pi) if angle is None else angle
    return pin.SE3(pin.exp3(theta * axis), rng.normal(size=3))


@pytest.mark.parametrize("angle", [None, math.pi - 1e-9, math.pi - 1e-4, math.pi - 0.02, 0.3])
def test_log6_and_jlog6_match_pinocchio(angle):
    rng = np.random.default_rng(5)
    out, J, w = np.empty(6), np.empty((6, 6)), np.empty(3)
    for _ in range(100):
        M = _random_pose(rng, angle)
        R, p = M.rotation.copy(), M.translation.copy()
        se3.log6(R, p, out)
        np.testing.assert_allclose(out, pin.log6(M).vector, rtol=0, atol=1e-9)
        np.testing.assert_allclose(pin.exp6(pin.Motion(out)).homogeneous, M.homogeneous, atol=1e-12)
        se3.jlog6(R, p, J, w)
        np.testing.assert_allclose(J, pin.Jlog6(M), rtol=0, atol=1e-8)
        assert se3.rotation_angle(R) == pytest.approx(np.linalg.norm(pin.log3(R)), abs=1e-9)


@pytest.mark.parametrize("angle", [1e-9, 1e-6, 1e-3, 0.049, 0.051])
def test_log6_small_angles_invert_exp6(angle):
    # Pinocchio's own series switch loses digits here; exp6 is the reference.
    rng = np.random.default_rng(6)
    out = np.empty(6)
    for _ in range(50):
        M = _random_pose(rng, angle)
        se3.log6(M.rotation.copy(), M.translation.copy(), out)
        np.testing.assert_allclose(pin.exp6(pin.Motion(out)).homogeneous, M.homogeneous, atol=1e-14)
        assert np.linalg.norm(out[3:]) == pytest.approx(angle, rel=1e-12)


def _batch(a, n, seed, position_only=False):
    rng = np.random.default_rng(seed)
    Q = np.array([a.random_q(rng) for _ in range(n)])
    T = [a.fk(q) for q in Q]
    rotations = None if position_only else np.array([t.rotation for t in T])
    return Q, TargetBatch(np.array([t.translation for t in T]), rotations)


@pytest.mark.parametrize("solver", ["dls", "qp"])
@pytest.mark.parametrize("name", SPATIAL + ["scara", "planar_3link", "double_pendulum"])
def test_batch_round_trip_verified(name, solver):
    a = model(name)
    position_only = name in ("planar_3link", "double_pendulum")
    _, targets = _batch(a, 12, 3, position_only)
    opts = Options(timeout=0.2)
    out = registry.get(solver).run_batch(a, targets, np.tile(a.middle, (12, 1)), opts)
    assert out.q.shape == (12, a.dof) and out.claim.dtype == np.int8
    assert np.all(out.claim == Status.CONVERGED.code)
    c = measure_batch(a, out.q, targets, opts)
    assert c.ok.all(), (c.position_error, c.orientation_error)
    if position_only:
        assert np.isnan(c.orientation_error).all()


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_batch_rows_equal_single_solves(solver):
    a = arm("z1")
    _, targets = _batch(a, 10, 8)
    q0 = np.tile(a.middle, (10, 1))
    kw = dict(timeout=0.05, seed=4)
    out = registry.get(solver).run_batch(a.kinematics, targets, q0, Options(**kw))
    for i in range(10):
        T = pin.SE3(targets.rotations[i], targets.positions[i])
        r = a.solve(T, q0=a.middle, solver=solver, **kw)
        np.testing.assert_array_equal(r.q, out.q[i])
        assert r.iterations == out.iterations[i] and r.restarts == out.restarts[i]


def test_batch_fixed_point_takes_no_iteration():
    a = model("kinova")
    Q, targets = _batch(a, 8, 2)
    out = registry.get("dls").run_batch(a, targets, Q, Options())
    assert np.all(out.iterations == 0) and np.all(out.restarts == 0)
    np.testing.assert_allclose(out.q, Q, atol=1e-12)


def test_qp_batch_stays_inside_limits_near_limits():
    a = model("panda")
    rng = np.random.default_rng(9)
    Q = np.array([a.random_q(rng) for _ in range(10)])
    for k, q in enumerate(Q):
        j = k % a.dof
        q[j] = a.upper[j] - 1e-5 if k % 2 else a.lower[j] + 1e-5
    T = [a.fk(q) for q in Q]
    targets = TargetBatch(np.array([t.translation for t in T]), np.array([t.rotation for t in T]))
    out = registry.get("qp").run_batch(a, targets, np.tile(a.middle, (10, 1)), Options(timeout=0.2))
    assert np.all((out.q >= a.lower) & (out.q <= a.upper))
    assert measure_batch(a, out.q, targets, Options()).ok.all()


def test_a_lying_kernel_is_caught_by_the_fk_check(monkeypatch):
    def liar(real):
        def lying(*args):
            real(*args)
            out_q, info = args[-3], args[-2]
            out_q += 0.05  # off the target, still claimed converged
            info[:, 0] = Status.CONVERGED.code
            info[:, 1] = 1

        return lying

    def pose_liar(real):  # the single-pose entries (armik.plan's route)
        def lying(*args):
            if not real(*args):
                return False
            out_q, info = args[-3], args[-2]
            out_q += 0.05
            info[0] = Status.CONVERGED.code
            info[1] = 1
            return True

        return lying

    monkeypatch.setattr(numeric, "ENTRIES", tuple(liar(e) for e in numeric.ENTRIES))
    monkeypatch.setattr(numeric, "POSE_ENTRIES", tuple(pose_liar(e) for e in numeric.POSE_ENTRIES))
    a = armik.load("ur5")  # a fresh arm: its prepared solves use the lying entries
    q = a.random_q(np.random.default_rng(3))
    T = a.fk(q)
    for solver in ("dls", "qp"):
        for target in (T, (T.translation, T.rotation)):  # prepared and general paths
            r = a.solve(target, q0=a.middle, solver=solver)
            assert not r.success and r.status == "not_converged" and "check failed" in r.reason


def test_threads_give_the_answers_of_one_thread():
    a = arm("panda")
    _, targets = _batch(a, 40, 21)
    q0 = np.tile(a.middle, (40, 1))
    spec, m = registry.get("dls"), a.kinematics
    opts = Options(iteration_budget=400, seed=3)  # deterministic: no clock involved
    alone = spec.run_batch(m, targets, q0, opts)

    def chunk(k):
        part = slice(10 * k, 10 * k + 10)
        return spec.run_batch(m, TargetBatch(targets.positions[part], targets.rotations[part]),
                              q0[part], opts)  # fmt: skip

    with ThreadPoolExecutor(4) as pool:
        parts = list(pool.map(chunk, range(4)))
    np.testing.assert_array_equal(np.vstack([p.q for p in parts]), alone.q)
    np.testing.assert_array_equal(np.concatenate([p.iterations for p in parts]), alone.iterations)
    with ThreadPoolExecutor(4) as pool:  # and single solves from several threads
        qs = list(pool.map(lambda i: a.solve(
            pin.SE3(targets.rotations[i], targets.positions[i]), q0=a.middle,
            iteration_budget=400, seed=3).q, range(40)))  # fmt: skip
    np.testing.assert_array_equal(np.array(qs), alone.q)


def test_iteration_budget_bounds_the_work_and_names_itself():
    a = arm("panda")
    # inside the bound, out of reach
    p = a.kinematics.first_joint_origin + np.array([0.95, 0.0, 0.0])
    r = a.solve(p, iteration_budget=50)
    assert not r.success and r.iterations <= 50 and "iteration budget (50 iterations" in r.reason
    r2 = a.solve(p, iteration_budget=50)
    np.testing.assert_array_equal(r.q, r2.q)
    for bad in (0, -3, 2.5, "10", True):
        with pytest.raises(OptionError, match="iteration_budget"):
            a.solve(p, iteration_budget=bad)


def test_timeout_is_thread_cpu_time():
    """An unreachable point: the budget, not the restart count, ends the solve (a million
    restarts take far longer than 0.01 s, however fast an attempt is)."""
    a = arm("panda")
    p = a.kinematics.first_joint_origin + np.array([0.95, 0.0, 0.0])
    r = a.solve(p, timeout=0.01, max_restarts=1_000_000)
    assert not r.success and "0.01 s of CPU time" in r.reason


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_one_joint_chain(solver):
    a = _load("ur5", tip="shoulder_link", tip_offset=(0.3, 0.0, 0.0))
    assert a.dof == 1
    for angle in (-2.5, 0.4, 3.0):
        T = a.fk(np.array([angle]))
        for target in (T, T.translation):
            r = a.solve(target, solver=solver)
            assert r.success and abs(r.q[0] - angle) < 1e-6
    r = a.solve(T.translation + np.array([0.0, 0.0, 0.05]), solver=solver, timeout=0.01)
    assert not r.success and r.status in ("unreachable", "not_converged")


def test_check_batch_agrees_with_check():
    a = _load("kinova", base="j2s6s200_link_2")
    Q, targets = _batch(a, 30, 4)
    rng = np.random.default_rng(1)
    Q = Q + rng.normal(scale=1e-6, size=Q.shape)
    j = int(np.flatnonzero(np.isfinite(a.upper))[0])
    Q[3, j] = a.upper[j] + 0.1  # outside its limits
    Q[5, 0] = np.nan
    m = a.kinematics
    for opts in (Options(), Options(weights=(1, 1, 0, 1, 0.5, 0)), Options(position_only=True)):
        c = measure_batch(m, Q, targets, opts)
        for i in range(30):
            if i == 5:
                assert np.isnan(c.position_error[i]) and not c.ok[i]
                continue
            one = measure(m, Q[i], parse_target(
                pin.SE3(targets.rotations[i], targets.positions[i])), opts)  # fmt: skip
            assert c.position_error[i] == pytest.approx(one.position_error, abs=1e-15)
            if one.orientation_error is None:
                assert np.isnan(c.orientation_error[i])
            else:
                assert c.orientation_error[i] == pytest.approx(one.orientation_error, abs=1e-15)
            assert c.within_limits[i] == (not one.violations) and c.ok[i] == one.ok
    assert not c.within_limits[3]
    with pytest.raises(ValueError, match="shape"):
        measure_batch(m, Q[:, :2], targets, Options())


def test_bench_times_peers_interleaved_and_judges_them():
    from armik.tools import bench
    from armik.tools.peers import Peer

    class Exact(Peer):  # answers with the configuration the target came from
        def solve(self, T, q0):
            self.iterations.append(0)
            return self.answers[tuple(np.round(T[:3, 3], 12))]

    class Wrong(Exact):
        def solve(self, T, q0):
            return super().solve(T, q0) + 0.1

    a = arm("ur5")
    rng = np.random.default_rng(0)
    Q = [a.random_q(rng) for _ in range(5)]
    poses = [a.fk(q) for q in Q]
    peers = [Exact("exact", a), Wrong("wrong", a)]
    for p in peers:
        p.answers = {tuple(np.round(T.translation, 12)): q for T, q in zip(poses, Q)}
    rows = bench.bench_interleaved(a, ["dls"], poses, peers=peers)
    by = {r.solver: r for r in rows}
    assert by["dls"].success_rate == 100 and by["exact"].success_rate == 100
    assert by["wrong"].success_rate == 0 and by["exact"].n == 5


def test_qp_backend_fallback_from_compiled_code_solves_the_box_qp():
    # The step the kernel hands to qpsolvers when its active set fails (object mode).
    from armik.kernel import box_qp as backend
    from armik.kernel.step import backend_step
    from armik.solvers.numeric import qp as qp_solver

    rng = np.random.default_rng(2)
    for _ in range(5):
        A = rng.normal(size=(6, 7))
        H = A.T @ A + 1e-3 * np.eye(7)
        g = A.T @ rng.normal(size=6)
        lb, ub = -rng.uniform(0.0, 0.3, 7), rng.uniform(0.0, 0.3, 7)
        x = backend_step(H.copy(), g.copy(), lb.copy(), ub.copy(), backend.code("osqp"))
        exact = qp_solver.active_set_guess(np.linalg.inv(H), np.linalg.solve(H, g), lb, ub,
                                           np.linalg.solve(H, g))  # fmt: skip
        assert exact is not None
        np.testing.assert_allclose(np.clip(x, lb, ub), exact, atol=1e-6)


def test_with_limits_rebuilds_the_kernel_chain():
    a = arm("panda")
    narrow = a.with_limits({"panda_joint1": (-0.1, 0.1)})
    assert narrow.kinematics.kernel_chain is not a.kinematics.kernel_chain
    assert narrow.kinematics.kernel_chain.chain.upper[0] == 0.1
    q = a.middle.copy()
    q[0] = 0.05
    r = narrow.solve(narrow.fk(q), q0=narrow.middle)
    assert r.success and -0.1 <= r.q[0] <= 0.1


def test_cholesky6_is_the_general_cholesky_written_out():
    from armik.kernel.linalg import cholesky6, cholesky_solve

    rng = np.random.default_rng(11)
    free = np.ones(6, dtype=np.int64)
    for _ in range(200):
        A = rng.standard_normal((6, 7))
        H = A @ A.T + rng.uniform(1e-9, 1.0) * np.eye(6)
        g = rng.standard_normal(6)
        x6, x, L = np.empty(6), np.empty(6), np.empty((6, 6))
        assert cholesky6(H, g, x6) and cholesky_solve(H, g, free, L, x)
        assert np.array_equal(x6, x)  # the same operations in the same order
        assert np.allclose(H @ x6, g, rtol=1e-9, atol=1e-9 * np.abs(g).max())
    H = np.eye(6)
    H[4, 4] = -1.0  # not positive definite
    assert not cholesky6(H, np.ones(6), np.empty(6))
