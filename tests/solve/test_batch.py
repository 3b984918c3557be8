"""solve_batch and BatchResult: the same answers as a loop of solve, every target shape."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

import armik
from armik import BatchResult
from armik.errors import OptionError, TargetError
from armik.status import Status
from armik.targets.batch import TargetBatch, parse_targets

from ..conftest import ALL_ROBOTS, TOL, arm, model


def _poses(a: armik.Arm, n: int, seed: int) -> list[pin.SE3]:
    rng = np.random.default_rng(seed)
    return [a.fk(a.random_q(rng)) for _ in range(n)]


def _planar(a: armik.Arm) -> bool:
    return a.kinematics.plane is not None


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_batch_equals_a_loop_of_solve(name):
    a = arm(name)
    poses = _poses(a, 5, seed=3)
    targets = [T.translation for T in poses] if _planar(a) else [T.homogeneous for T in poses]
    far = np.array([10.0, 10.0, 10.0])  # out of reach: a failure with its own status
    targets.append(far if _planar(a) else pin.SE3(np.eye(3), far).homogeneous)
    q0 = np.array([a.random_q(k) for k in range(len(targets))])
    options = dict(timeout=1.0, max_restarts=50, seed=7)
    loop = [a.solve(t, q0=q, **options) for t, q in zip(targets, q0)]
    batch = a.solve_batch(np.array(targets), q0=q0, workers=2, chunk_size=2, **options)
    assert len(batch) == len(targets)
    assert batch.solver == loop[0].solver
    for i, r in enumerate(loop):
        b = batch[i]
        assert b.success == r.success and b.status is r.status, (i, b, r)
        np.testing.assert_array_equal(b.q, r.q)
        assert b.iterations == r.iterations and b.restarts == r.restarts
        assert b.position_error == r.position_error
        assert b.orientation_error == r.orientation_error
        assert b.reason == r.reason, i  # a success's claim too: its restarts, its branch
    assert batch.success[:-1].all() and batch.status[-1] == "unreachable"


def test_one_seed_for_all_targets_and_default_seed():
    a = arm("ur5")
    poses = _poses(a, 4, seed=1)
    r_default = a.solve_batch(poses, workers=1)
    r_middle = a.solve_batch(poses, q0=a.middle, workers=1)
    np.testing.assert_array_equal(r_default.q, r_middle.q)
    np.testing.assert_array_equal(r_default.q[2], a.solve(poses[2]).q)


class _PoseArray:
    """What armik reads of a spatialmath ``SE3`` holding N poses (spatialmath is not a test
    dependency): ``len()`` and ``.A``, a list of 4x4 arrays (one array when N = 1)."""

    def __init__(self, T: np.ndarray) -> None:
        self.A = [M for M in T] if len(T) > 1 else T[0]

    def __len__(self) -> int:
        return len(self.A) if isinstance(self.A, list) else 1


def _spatialmath(T: np.ndarray) -> _PoseArray:
    return _PoseArray(T)


def test_targets_in_every_shape_give_the_same_batch():
    a = arm("panda")
    poses = _poses(a, 4, seed=5)
    T = np.array([p.homogeneous for p in poses])
    quat = np.array([Rotation.from_matrix(p.rotation).as_quat() for p in poses])  # x y z w
    rows7 = np.hstack([T[:, :3, 3], quat])
    forms = {
        "4x4": T,
        "rows7": rows7,
        "se3 list": poses,
        "pairs": [(p, q) for p, q in zip(T[:, :3, 3], quat)],
        "scaled quaternions": np.hstack([T[:, :3, 3], 3.0 * quat]),
        "spatialmath-like SE3 of N poses": _spatialmath(T),
    }
    ref = parse_targets(T)
    for name, value in forms.items():
        b = parse_targets(value)
        np.testing.assert_allclose(b.positions, ref.positions, atol=0, err_msg=name)
        np.testing.assert_allclose(b.rotations, ref.rotations, atol=1e-12, err_msg=name)
    # each row as parse_target reads it
    for i in range(len(rows7)):
        one = armik.parse_target(rows7[i])
        np.testing.assert_allclose(parse_targets(rows7).rotations[i], one.rotation, atol=1e-15)
    assert len(parse_targets(_spatialmath(T[:1]))) == 1
    positions = parse_targets(T[:, :3, 3])
    assert positions.position_only and positions.rotations is None


def test_near_rotations_are_snapped_and_huge_quaternions_do_not_overflow():
    R = Rotation.from_rotvec([0.1, 0.2, 0.3]).as_matrix()
    T = np.eye(4)[None].repeat(2, axis=0)
    T[0, :3, :3] = R + 1e-8  # within ROTATION_TOL of a rotation
    T[1, :3, :3] = R
    b = parse_targets(T)
    np.testing.assert_allclose(b.rotations[0].T @ b.rotations[0], np.eye(3), atol=1e-14)
    big = parse_targets(np.array([[0, 0, 0, 1e300, 0, 0, 1e300]], dtype=float))
    quarter = Rotation.from_rotvec([np.pi / 2, 0, 0]).as_matrix()
    np.testing.assert_allclose(big.rotations[0], quarter, atol=1e-12)


BAD = [
    ("nan row", lambda T: T.__setitem__((2, 0, 3), np.nan), "target 2"),
    ("last row", lambda T: T.__setitem__((1, 3, 0), 0.5), "target 1: the last row"),
    ("not orthonormal", lambda T: T.__setitem__((3, 0, 0), 2.0), "target 3: rotation is not"),
    ("reflection", lambda T: T.__setitem__((0, slice(0, 3), 0), -T[0, :3, 0]), "determinant"),
]


@pytest.mark.parametrize("label, spoil, words", BAD, ids=[b[0] for b in BAD])
def test_bad_matrices_name_the_index(label, spoil, words):
    T = np.array([p.homogeneous for p in _poses(arm("ur5"), 4, seed=2)])
    spoil(T)
    with pytest.raises(TargetError, match=words):
        parse_targets(T)


@pytest.mark.parametrize(
    "value, words",
    [
        (np.array([[0, 0, 0, 0, 0, 0, 0.0], [0, 0, 0, 0, 0, 0, 0]]), "target 0: quaternion"),
        (np.array([[0, 0, 0.0], [0, np.inf, 0]]), "target 1: position contains NaN or inf"),
        (np.eye(4), r"one target: use Arm.solve"),
        (np.zeros(7), "one target"),
        (np.zeros((5, 4)), r"shape \(5, 4\)"),
        (np.zeros((2, 3, 3)), r"shape \(2, 3, 3\)"),
        (np.zeros((2, 3), dtype=complex), "complex"),
        ([np.zeros(3), np.zeros(4)], "one \\(position, orientation\\) target"),
        ([np.zeros(3), pin.SE3.Identity()], "target 1 is a full pose but target 0 is a position"),
        ([pin.SE3.Identity(), "abc"], "target 1"),
        ("abc", "many targets"),
        (5.0, "many targets"),
        ({"a": 1}, "cannot read targets"),
    ],
)
def test_rejected_inputs(value, words):
    with pytest.raises(TargetError, match=words):
        parse_targets(value)


def test_empty_batch():
    r = armik.Arm(model("ur5")).solve_batch(np.zeros((0, 4, 4)))
    assert len(r) == 0 and r.q.shape == (0, 6) and "0 targets" in r.summary()


def test_q0_checks():
    a = arm("ur5")
    poses = _poses(a, 3, seed=4)
    with pytest.raises(OptionError, match=r"shape \(6,\).*\(3, 6\)"):
        a.solve_batch(poses, q0=np.zeros((2, 6)))
    bad = np.zeros((3, 6))
    bad[1, 2] = np.nan
    with pytest.raises(OptionError, match="target 1 must be finite"):
        a.solve_batch(poses, q0=bad)
    outside = np.zeros((3, 6))
    outside[2, 2] = 10.0
    with pytest.warns(armik.ArmikWarning, match="1 target.*target 2") as said:
        a.solve_batch(poses, q0=outside, workers=1)
    assert said[0].filename == __file__  # the caller's line, not armik's arm.py
    with pytest.warns(armik.ArmikWarning, match="1 target.*target 2") as said:
        a.solve_batch(poses, q0=outside, prefer="nearest")  # row by row: the same words
    assert said[0].filename == __file__
    for workers in (0, 1.5, True):
        with pytest.raises(OptionError, match="workers"):
            a.solve_batch(poses, workers=workers)
    with pytest.raises(OptionError, match="chunk_size"):
        a.solve_batch(poses, chunk_size=0)
    with pytest.raises(armik.OptionError, match="unknown option"):
        a.solve_batch(poses, tolerance=1e-3)


def test_result_api_and_npz_round_trip(tmp_path):
    a = arm("panda")
    poses = _poses(a, 6, seed=9)
    poses[4] = pin.SE3(np.eye(3), np.array([5.0, 0, 0]))
    seen = []
    r = a.solve_batch(poses, workers=1, progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (6, 6)
    assert list(r.status) == ["converged"] * 4 + ["unreachable", "converged"]
    assert (r.status == "converged").sum() == 5 and r.counts() == {"converged": 5, "unreachable": 1}
    assert r.success_rate == pytest.approx(5 / 6)
    one = r[-2]
    assert isinstance(one, armik.IKResult) and not one.success and "reach" in one.reason
    assert r[0].position_error <= TOL["solve"] and r[0].q.shape == (7,)
    solved = r[r.success]
    assert len(solved) == 5 and solved.success.all() and not solved.reasons
    tail = r[3:]
    assert len(tail) == 3 and 1 in tail.reasons and tail[1].status is Status.UNREACHABLE
    assert [x.success for x in r] == r.success.tolist()
    with pytest.raises(IndexError):
        r[6]
    path = r.save(tmp_path / "out.npz")
    back = BatchResult.load(path)
    for name in ("q", "success", "status_code", "position_error", "iterations", "restarts"):
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name))
    np.testing.assert_array_equal(back.orientation_error, r.orientation_error)
    assert back.reasons == r.reasons and back.solver == r.solver and back.arm == "panda"
    assert back.joint_names == tuple(a.joint_names)
    assert "5/6 solved" in back.summary()
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(armik.InputError, match="not a batch result"):
        BatchResult.load(tmp_path / "junk.npz")
    np.save(tmp_path / "array.npy", r.q)  # an array of its own, no archive
    with pytest.raises(armik.InputError, match="not a batch result.*not an .npz archive"):
        BatchResult.load(tmp_path / "array.npy")


def test_position_targets_have_no_orientation_error():
    a = arm("ur5")
    pts = np.array([T.translation for T in _poses(a, 3, seed=6)])
    r = a.solve_batch(pts, workers=1)
    assert r.success.all() and np.isnan(r.orientation_error).all()
    assert r[0].orientation_error is None


def test_arms_pickle_as_their_recipe():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = armik.load("ur5", tip_offset=(0.0, 0.0, 0.1)).with_limits({"elbow_joint": (-1, 1)})
    b = pickle.loads(pickle.dumps(a))
    q = np.array([0.1, -0.5, 0.5, 0.2, 0.3, 0.4])
    assert b.fk(q).isApprox(a.fk(q), 1e-14)
    np.testing.assert_array_equal(b.lower, a.lower)
    poses = _poses(a, 2, seed=8)
    np.testing.assert_array_equal(
        a.solve_batch(poses, workers=1).q, b.solve_batch(poses, workers=1).q
    )


def test_target_batch_indexing():
    b = parse_targets(np.zeros((4, 3)))
    assert len(b[1:3]) == 2 and isinstance(b[1:3], TargetBatch)
    with pytest.raises(TypeError):
        b[0]
    assert b.target(2).rotation is None


def test_progress_bar_on_request(capsys):
    a = arm("ur5")
    a.solve_batch(_poses(a, 3, seed=1), solver="dls", workers=1, progress=True)
    err = capsys.readouterr().err
    assert "ur5/dls" in err and "3/3" in err and "#" * 30 in err
    a.solve_batch(_poses(a, 3, seed=1), workers=1)  # stderr is not a terminal here
    assert capsys.readouterr().err == ""
    with pytest.raises(OptionError, match="progress"):
        a.solve_batch(_poses(a, 1, seed=1), progress="yes")


def test_thread_count_and_chunking_do_not_change_answers():
    a = arm("panda")
    T = np.array([p.homogeneous for p in _poses(a, 40, seed=12)])
    options = dict(iteration_budget=400, seed=5)  # a budget in iterations: deterministic
    one = a.solve_batch(T, workers=1, chunk_size=40, **options)
    two = a.solve_batch(T, workers=2, chunk_size=7, **options)
    for name in ("q", "success", "status_code", "iterations", "restarts", "position_error"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)
    loop = [a.solve(t, **options) for t in T[:5]]
    np.testing.assert_array_equal(one.q[:5], np.array([r.q for r in loop]))


def test_progress_reports_each_chunk_from_the_thread_pool():
    a = arm("ur5")
    seen = []
    a.solve_batch(
        _poses(a, 8, seed=3),
        workers=2,
        chunk_size=2,
        progress=lambda d, t: seen.append(d),
    )
    # one report per finished chunk, whatever order the threads finish in
    assert seen == [2, 4, 6, 8]


def test_a_lying_batch_solver_is_caught_by_the_fk_check(monkeypatch):
    import dataclasses

    from armik.solvers import registry
    from armik.solvers.answers import Answers

    a = arm("ur5")
    rng = np.random.default_rng(4)
    q_true = np.array([a.random_q(rng) for _ in range(3)])
    T = np.array([a.fk(q).homogeneous for q in q_true])
    lies = q_true.copy()
    lies[0] = a.middle  # a wrong configuration, within the limits
    lies[2, 2] = a.upper[2] + 0.5  # outside the elbow's limits

    def liar(arm_, targets, q0, opts, seeds=None):
        n = len(targets)
        return Answers(
            q=lies[:n].copy(),
            claim=np.full(n, Status.CONVERGED.code, dtype=np.int8),
            iterations=np.ones(n, dtype=np.int64),
            restarts=np.zeros(n, dtype=np.int64),
        )

    spec = registry.get("dls")
    monkeypatch.setitem(registry._REGISTRY, "dls", dataclasses.replace(spec, run_batch=liar))
    r = a.solve_batch(T, solver="dls", workers=1)
    assert r.success.tolist() == [False, True, False]
    assert r.status.tolist() == ["not_converged", "converged", "joint_limits"]
    assert "forward-kinematics check failed" in r.reason(0)
    assert "elbow_joint" in r.reason(2) and "outside the joint limits" in r.reason(2)


def test_a_slice_keeps_the_batch_s_margin_and_region():
    """A slice or mask of a batch words its rows as the batch does (the clearance kept)."""
    r = BatchResult.empty(4, 6, solver="dls", time=0.0, margin=0.02, region=True)
    r.put_distance(1, 0.03, ("link_a", "link_b"))
    for part in (r[1:], r[np.array([False, True, True, False])]):
        assert part.margin == 0.02 and part.region
        assert part.reason(0) == r.reason(1) and "0.02" in part.reason(0)


def test_nothing_is_called_to_report_where_nothing_is_reported():
    """``progress.reporter``: None where nothing is reported (False, or None with stderr not
    on a terminal), a reporter otherwise; a batch reports to the caller's callable on every
    route and to nothing without one."""
    from armik.solve.progress import reporter

    assert reporter(False, 3, "x") is None
    assert reporter(None, 3, "x") is None  # stderr is not a terminal here
    seen: list = []
    reporter(lambda d, t: seen.append((d, t)), 3, "x")(1, 3)
    assert seen == [(1, 3)]
    a = arm("ur5")
    poses = _poses(a, 4, seed=2)
    for workers in (1, 2):
        seen.clear()
        r = a.solve_batch(
            poses, workers=workers, chunk_size=2, progress=lambda d, t: seen.append(d)
        )
        assert r.success.all() and seen == [2, 4]
        assert a.solve_batch(poses, workers=workers, chunk_size=2, progress=False).success.all()


def test_a_backends_job_carries_its_own_rows_not_the_batchs():
    # a job pickled to a cluster carried the whole batch's targets and seeds: the traffic
    # of a batch grew as the square of its size
    import cloudpickle

    a = arm("ur5")
    sizes = {}

    def spy(jobs, workers):
        sizes[len(jobs)] = len(cloudpickle.dumps(jobs[0]._replace(arm=None)))
        return [job() for job in jobs]

    for n in (64, 1024):
        Q = a.random_q(1, n=n)
        local = a.solve_batch(a.fk_batch(Q), q0=Q, workers=1, progress=False)
        remote = a.solve_batch(a.fk_batch(Q), q0=Q, backend=spy, chunk_size=32, progress=False)
        np.testing.assert_array_equal(remote.q, local.q)
    assert sizes[32] < 1.1 * sizes[2]  # 16 times the targets, the same job
