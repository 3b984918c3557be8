"""Prepared solves (``armik.plan``) give what the general path gives, field for field.

The general path is taken by adding a check of the user's own that refuses nothing (a
plan takes no such check: ``_RefusesNothing``), so the two results of each case come from
the same solver, seed and options by the two routes.
"""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.errors import ArmikWarning, TargetError
from armik.solve.prepared import Plan, plan_for
from armik.solve.read import settings
from armik.solvers import registry
from armik.solvers.answers import Answers
from armik.targets.aim import aim_of
from armik.targets.pose import parse_target

from ..conftest import arm, assert_same_result, decided_by_verdicts


class _RefusesNothing(Constraint):
    """A check every answer passes: the general path (a plan takes no user's check)."""

    def check(self, arm, Q):
        return Check(np.ones(len(Q), dtype=bool), armik.Status.JOINT_LIMITS, str)


def _general(a: armik.Arm, T, **kw):
    return a.solve(T, constraints=[_RefusesNothing()], **kw)


@pytest.mark.parametrize(
    "name, solver",
    [
        ("panda", "dls"),
        ("panda", "qp"),
        ("kinova", "dls"),  # continuous joints: q is not Pinocchio's configuration
        ("ur5", "auto"),  # three_parallel
        ("ur5", "dls"),
        ("abb_irb120", "auto"),  # spherical wrist
        ("z1", "qp"),
        ("panda", "swept"),  # 7R: joint 7 held, joints 6 to 1 in closed form
    ],
)
def test_plan_result_is_the_general_result(name, solver):
    a = arm(name)
    rng = np.random.default_rng(3)
    for k in range(12):
        q_true = a.random_q(rng)
        T = a.fk(q_true)
        target = T if k % 2 else T.homogeneous
        q0 = None if k % 3 == 0 else a.random_q(rng)
        fast = a.solve(target, q0=q0, solver=solver, seed=k)
        general = _general(a, T, q0=q0, solver=solver, seed=k)
        assert fast.success
        assert_same_result(fast, general)


def test_plan_is_taken_for_plain_input_only():
    a = arm("panda")
    opts, key, _ = settings(a.kinematics, {})
    plan = plan_for(a.kinematics, "dls", key, opts)
    assert isinstance(plan, Plan)
    T = a.fk(a.random_q(np.random.default_rng(0)))
    q0 = a.middle.copy()
    assert plan.solve(T, q0, opts, 0, 0.0) is not None
    assert plan.solve(T.homogeneous, q0, opts, 0, 0.0) is not None
    not_plain = [
        (np.asfortranarray(T.homogeneous), q0),
        (T.homogeneous.astype(np.float32), q0),
        ((T.translation, T.rotation), q0),
        (T, q0.astype(np.float32)),
        (T, list(q0)),
        (T, a.upper + 0.1),  # the general path clips it, with a warning
        (T, np.full(a.dof, np.nan)),
        (pin.SE3(2.0 * T.rotation, T.translation), q0),  # refused by the parser
        (pin.SE3(T.rotation + 1e-9, T.translation), q0),  # snapped by the parser
    ]
    for target, q in not_plain:
        assert plan.solve(target, q, opts, 0, 0.0) is None


def test_not_plain_input_behaves_as_before():
    a = arm("panda")
    T = a.fk(a.random_q(np.random.default_rng(1)))
    with pytest.warns(ArmikWarning, match="clipped"):
        r = a.solve(T, q0=a.upper + 0.1, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert_same_result(r, _general(a, T, q0=a.upper + 0.1, seed=1))
    with pytest.raises(TargetError, match="not orthonormal"):
        a.solve(pin.SE3(2.0 * T.rotation, T.translation))
    H = T.homogeneous
    H[3, 3] = 2.0
    with pytest.raises(TargetError, match="last row"):
        a.solve(H)


def test_failures_take_the_general_verdict():
    a = arm("panda")
    far = pin.SE3(np.eye(3), np.array([3.0, 0.0, 0.5]))  # beyond reach
    r = a.solve(far, seed=0)
    assert not r.success and r.status == "unreachable"
    assert_same_result(r, _general(a, far, seed=0))
    # reachable in position, not converged within one short descent
    T = a.fk(a.random_q(np.random.default_rng(2)))
    kw = dict(solver="dls", max_restarts=0, max_iterations=2, seed=0)
    r = a.solve(T, **kw)
    assert not r.success and r.status == "not_converged"
    assert_same_result(r, _general(a, T, **kw))


def _lie_about_the_first_answer(plan) -> None:
    """Make ``plan``'s runner claim a wrong first answer (joint 1 off by 1e-3 rad); asked
    for every row, it answers honestly."""
    honest = plan.run_pose

    def lying(H, q0, seed, every=False):
        if every:
            return honest(H, q0, seed, every)
        got = honest(H, q0, seed)
        q = got.q.copy()
        q[0] += 1e-3  # claimed converged, is not
        return got._replace(q=q)

    plan.run_pose = lying


def test_a_lying_runner_is_caught_by_the_check():
    a = armik.load("panda")  # a fresh arm: its own plans
    T = a.fk(a.random_q(np.random.default_rng(4)))
    opts, key, _ = settings(a.kinematics, {})
    _lie_about_the_first_answer(plan_for(a.kinematics, "auto", key, opts))
    r = a.solve(T)
    assert not r.success and r.status == "not_converged"
    assert "forward-kinematics check failed" in r.reason
    assert r.position_error > 1e-5


def test_a_refused_closed_form_answer_falls_back_to_every_row():
    # The closed form's first row is the one ``solve`` verifies; when the check refuses it,
    # the other rows are verified nearest first (here the honest first row passes).
    a = armik.load("ur5")  # a fresh arm: its own plans
    q = a.random_q(np.random.default_rng(6))
    T = a.fk(q)
    opts, key, _ = settings(a.kinematics, {})
    plan = plan_for(a.kinematics, "auto", key, opts)
    assert plan.solver == "three_parallel"
    expected = a.solve(T, q0=q)
    assert expected.success
    _lie_about_the_first_answer(plan)
    r = a.solve(T, q0=q)
    assert r.success and r.solver == "three_parallel"
    np.testing.assert_array_equal(r.q, expected.q)
    assert r.branch == expected.branch


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_an_unreached_closed_form_hands_every_row_over_labelled(name):
    # The kernel labels only the first row for ``solve``; when that row is not reached,
    # every row goes to the general verdict and each must carry its own branch, as the
    # general path's rows do.
    a = arm(name)
    q0 = a.random_q(np.random.default_rng(8))
    far = pin.SE3(np.eye(3), np.array([3.0, 0.5, 0.5]))  # beyond reach
    opts, key, _ = settings(a.kinematics, {})
    plan = plan_for(a.kinematics, "auto", key, opts)
    rows = plan.run_pose(far.homogeneous, q0, 0)
    assert type(rows) is Answers and len(rows) > 1
    general = registry.get(plan.solver).run(
        a.kinematics, parse_target(far, a.kinematics), q0, opts, False
    )
    assert rows.branch == general.branch
    assert rows.branch is not None and len(set(rows.branch)) > 1  # not all unlabelled
    assert rows.reasons == general.reasons
    np.testing.assert_array_equal(rows.q, general.q)
    np.testing.assert_array_equal(rows.claim, general.claim)


def test_lazy_reason_pickles_and_compares():
    a = arm("panda")
    T = a.fk(a.random_q(np.random.default_rng(5)))
    r = a.solve(T, seed=0)
    assert "reason" not in r.__dict__  # not written yet
    back = pickle.loads(pickle.dumps(r))
    assert back.reason == r.reason and r.reason.startswith("converged after")
    assert "verified by forward kinematics" in back.reason
    assert r.as_dict()["reason"] == r.reason
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        r.nothing  # noqa: B018


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
def test_plan_solve_all_is_the_general_solve_all(name):
    a = arm(name)
    rng = np.random.default_rng(6)
    seen_failure = False
    for k in range(10):
        T = a.fk(a.random_q(rng))
        q0 = None if k % 2 else a.random_q(rng)
        fast = a.solve_all(T, q0=q0)
        general = a.solve_all(T, q0=q0, constraints=[_RefusesNothing()])
        assert len(fast) == len(general) >= 1 and fast[0].success
        for x, y in zip(fast, general):
            assert_same_result(x, y)
            assert x.time == fast[0].time  # one call, one time
        seen_failure |= not all(r.success for r in fast)
    if name == "abb_irb120":  # some branches leave its limits: failures ranked after
        assert seen_failure


def test_plan_solve_all_ranks_a_verified_answer_the_kernel_did_not_claim():
    # The UR5 at q = 0: elbow stretched, wrist singular. The kernel flags one row as reached
    # only in the least-squares sense; Pinocchio verifies it: a success, ranked among the
    # successes by distance to q0, as the general path ranks it.
    a = arm("ur5")
    T = a.fk(np.zeros(6))
    for q0 in (None, np.full(6, 0.3), np.array([-2.9, -3.0, 0.1, 3.0, -2.8, 0.1])):
        fast = a.solve_all(T, q0=q0)
        general = a.solve_all(T, q0=q0, constraints=[_RefusesNothing()])
        assert sum(r.success for r in fast) >= 2
        assert len(fast) == len(general)
        for x, y in zip(fast, general):
            assert_same_result(x, y)


def test_threads_get_the_answers_of_one_thread():
    # Each thread measures with its own Pinocchio Data (arm.data is per thread).
    from concurrent.futures import ThreadPoolExecutor

    a = arm("panda")
    rng = np.random.default_rng(7)
    poses = [a.fk(a.random_q(rng)) for _ in range(300)]

    def run(i):
        return a.solve(poses[i], seed=i, iteration_budget=2000)

    one = [run(i) for i in range(len(poses))]
    with ThreadPoolExecutor(4) as pool:
        four = list(pool.map(run, range(len(poses))))
    for x, y in zip(one, four):
        assert_same_result(x, y)


@pytest.mark.parametrize(
    "name, load_kw, options",
    [
        ("panda", {"base": "panda_link2", "tip_offset": (0.0, 0.02, 0.1)}, {}),
        ("panda", {"locked": {"panda_finger_joint1": 0.01}}, {"solver": "qp"}),
        ("kinova", {}, {"solver": "dls", "weights": (1, 1, 1, 0.5, 0.5, 0.0)}),
        ("ur5", {"tip_offset": (0.0, 0.0, 0.05)}, {"tol_position": 1e-8}),
        ("panda", {}, {"position_only": True}),
    ],
)
def test_plan_on_variants_and_options(name, load_kw, options):
    a = armik.load(name, **load_kw)
    rng = np.random.default_rng(8)
    for k in range(6):
        T = a.fk(a.random_q(rng))
        q0 = None if k % 2 else a.random_q(rng)
        fast = a.solve(T, q0=q0, seed=k, **options)
        general = _general(a, T, q0=q0, seed=k, **options)
        assert fast.success
        assert_same_result(fast, general)


@pytest.mark.parametrize(
    "name, options",
    [
        ("panda", {}),
        ("ur5", {}),  # auto: the closed form refuses positions, dls is chosen
        ("kinova", {"solver": "qp"}),
        ("planar_3link", {}),
        ("xarm7", {"weights": (1, 1, 0.5, 0, 0, 0), "tol_position": 1e-8}),
    ],
)
def test_position_targets_are_prepared_too(name, options):
    a = arm(name)
    rng = np.random.default_rng(9)
    for k in range(8):
        p = a.fk(a.random_q(rng)).translation.copy()
        q0 = None if k % 2 else a.random_q(rng)
        fast = a.solve(p, q0=q0, seed=k, **options)
        general = _general(a, p, q0=q0, seed=k, **options)
        assert fast.success and fast.orientation_error is None
        assert_same_result(fast, general)
    assert not decided_by_verdicts(fast)  # the prepared path


def test_other_vector_targets_take_the_general_path():
    a = arm("panda")
    T = a.fk(a.random_q(np.random.default_rng(9)))
    p = T.translation
    for target in (list(p), p.astype(np.float32), np.concatenate([p, [0, 0, 0, 1.0]])):
        r = a.solve(target, seed=0)
        assert r.success and decided_by_verdicts(r)  # the general path
    far = np.array([5.0, 0.0, 0.0])
    r = a.solve(far, seed=0)
    assert r.status == "unreachable"
    assert_same_result(r, _general(a, far, seed=0))
    kw = dict(solver="dls", max_restarts=0, max_iterations=1, seed=0)
    near = p + 0.05
    r = a.solve(near, **kw)
    assert r.status == "not_converged" and r.orientation_error is None
    assert_same_result(r, _general(a, near, **kw))


def test_to_pin_on_continuous_joints():
    a = arm("kinova")  # continuous joints: (cos, sin) pairs in Pinocchio's configuration
    rng = np.random.default_rng(10)
    for _ in range(20):
        q = a.random_q(rng) * 3.0  # beyond +-pi too
        qp = a.kinematics.to_pin(q)
        for j in range(a.dof):
            k = a.model.joints[j + 1].idx_q
            if a.model.joints[j + 1].nq == 2:
                assert qp[k] == pytest.approx(np.cos(q[j]), abs=1e-16)
                assert qp[k + 1] == pytest.approx(np.sin(q[j]), abs=1e-16)
            else:
                assert qp[k] == q[j]


def test_plain_pose_agrees_with_the_parser_on_corrupted_matrices():
    # Whatever the plan's compiled checks let through must be what the parser keeps as is;
    # everything else must end as the general path ends (same result or same error).
    from armik.kernel.single import plain_pose

    a = arm("panda")
    rng = np.random.default_rng(12)
    base = a.fk(a.random_q(rng)).homogeneous
    cases = []
    for scale in (1e-16, 1e-15, 5e-15, 1e-14, 2e-14, 1e-13, 1e-9, 1e-3):
        H = base.copy()
        H[:3, :3] += scale * rng.standard_normal((3, 3))
        cases.append(H)
    for row in ((0, 0, 0, 1 + 1e-13), (0, 0, 0, 1 + 1e-11), (1e-13, 0, 0, 1), (0, 0, 0, 2)):
        H = base.copy()
        H[3] = row
        cases.append(H)
    for i, j, v in ((0, 3, np.nan), (1, 1, np.inf), (2, 3, 2e6), (2, 3, 1e6)):
        H = base.copy()
        H[i, j] = v
        cases.append(H)
    H = base.copy()
    H[:3, 0] *= -1.0  # a reflection
    cases.append(H)
    for H in cases:
        try:
            kept = parse_target(H, a.kinematics)
        except TargetError:
            kept = None
        exact = kept is not None and np.array_equal(kept.rotation, H[:3, :3])
        exact = exact and np.array_equal(kept.position, H[:3, 3])
        if plain_pose(H):
            assert exact  # the plan takes only what the parser keeps unchanged
        if kept is None:
            with pytest.raises(TargetError):
                a.solve(H, seed=0)
        else:
            assert_same_result(a.solve(H, seed=0), _general(a, H, seed=0))


@pytest.mark.parametrize("name", ["ur5", "kinova"])  # kinova: continuous joints (to_pin)
def test_tip_views_hold_pinocchio_placement_in_place(name):
    # The plan measures Pinocchio's placement through these views without copying it:
    # after each updateFramePlacement they must hold what Pinocchio returns, and another
    # thread must get views of its own Data.
    import threading

    a = arm(name)
    data, R, p = a.kinematics.tip_views()
    assert a.kinematics.tip_views()[0] is data
    rng = np.random.default_rng(3)
    for _ in range(5):
        qp = a.kinematics.to_pin(a.random_q(rng))
        pin.forwardKinematics(a.model, data, qp)
        got = pin.updateFramePlacement(a.model, data, a.kinematics.tip_frame_id)
        assert np.array_equal(R, got.rotation) and np.array_equal(p, got.translation)
        fresh = a.model.createData()
        pin.framesForwardKinematics(a.model, fresh, qp)
        assert np.array_equal(R, fresh.oMf[a.kinematics.tip_frame_id].rotation)
        assert np.array_equal(p, fresh.oMf[a.kinematics.tip_frame_id].translation)
    other = []
    worker = threading.Thread(target=lambda: other.append(a.kinematics.tip_views()[0]))
    worker.start()
    worker.join()
    assert other[0] is not data


@pytest.mark.parametrize(
    "name, options",
    [
        ("panda", {"bounds": (0.005, 0.005, 0.005, 0.05, 0.05, 0.05)}),
        ("ur5", {"bounds": (0.0, 0.0, 0.0, 0.0, 0.0, np.inf), "solver": "dls"}),
        ("panda", {"cone": (0.0, 0.0, 1.0, 0.05)}),
        ("so101", {"cone": (0.0, 0.0, 1.0, 0.05)}),
        ("ur5", {"cone": (0.6, 0.0, 0.8, 0.0), "solver": "qp"}),
    ],
)
def test_a_region_on_a_numeric_solver_is_prepared_as_the_general_path(name, options):
    """Bounds and cones (what ``armik.Axis`` lowers to) take the plan on the numeric solvers,
    measured outside the region as the general path measures them: the same results."""
    a = arm(name)
    options = dict(options)
    solver = options.pop("solver", "auto")
    plain = {k: v for k, v in options.items() if k != "cone"}
    aim = aim_of(options.get("cone"))  # a cone is the target's, not the options'
    opts, key, _ = settings(a.kinematics, plain)
    assert isinstance(plan_for(a.kinematics, solver, key, opts, aim=aim), Plan)
    rng = np.random.default_rng(8)
    solved = 0
    for k in range(8):
        turn = np.r_[np.zeros(3), rng.normal(scale=0.04, size=3)]  # the point reachable
        T = a.fk(a.random_q(rng)) * pin.exp6(pin.Motion(turn))
        q0 = a.random_q(rng)
        fast = a.solve(T, q0=q0, solver=solver, seed=k, **options)
        general = _general(a, T, q0=q0, solver=solver, seed=k, **options)
        assert fast.solver == ("dls" if solver == "auto" else solver)
        assert_same_result(fast, general)
        solved += fast.success
    assert solved >= 4  # successes compared, not only failures


@pytest.mark.parametrize("name", ["ur5", "abb_irb120"])
@pytest.mark.parametrize("half", [np.inf, 0.3])
def test_a_spin_on_the_last_joint_is_prepared_as_the_general_path(name, half):
    """A free or bounded spin on the UR5 and the IRB 120 (``spin_joint``) takes the plan:
    the same results as the general path, field for field."""
    a = arm(name)
    options = {"bounds": (0.0, 0.0, 0.0, 0.0, 0.0, half)}
    opts, key, _ = settings(a.kinematics, options)
    plan = plan_for(a.kinematics, "auto", key, opts)
    assert isinstance(plan, Plan) and plan.solver == "spin_joint"
    rng = np.random.default_rng(9)
    solved = 0
    for k in range(10):
        spun = pin.SE3(pin.exp3(np.array([0.0, 0.0, rng.uniform(-np.pi, np.pi)])), np.zeros(3))
        T = a.fk(a.random_q(rng)) * spun
        q0 = a.random_q(rng)
        fast = a.solve(T, q0=q0, seed=k, **options)
        general = _general(a, T, q0=q0, seed=k, **options)
        assert fast.solver == "spin_joint"
        assert_same_result(fast, general)
        solved += fast.success
    assert solved >= 5


def test_a_scene_given_as_a_list_is_kept_as_its_shapes():
    """A loop of collision-aware solves passes the same list of shapes: its options are
    validated once and its plain solve takes the prepared plan; a shape added to the list
    is a new scene, checked and kept apart."""
    a = armik.load("panda")  # a fresh arm: its own kept options
    scene = [armik.Sphere(0.05, (2.0, 2.0, 2.0))]
    opts, key, _ = settings(a.kinematics, {"obstacles": scene})
    again, key_again, _ = settings(a.kinematics, {"obstacles": scene})
    assert key is not None and again is opts and key_again == key
    scene.append(armik.Box((0.1, 0.1, 0.1), [2.0, -2.0, 2.0]))
    grown, key_grown, _ = settings(a.kinematics, {"obstacles": scene})
    assert key_grown != key and len(grown.obstacles) == 2 and len(opts.obstacles) == 1
    scene.append(armik.Sphere(0.05, (0.0, 0.0, 0.0)))  # on the base: refused, not kept
    with pytest.raises(armik.CollisionError, match="obstacles\\[2\\]"):
        a.solve(a.fk(a.middle), obstacles=scene)


@pytest.mark.parametrize("name", ["z1", "abb_irb120", "kinova", "ur5"])
def test_plan_solve_all_unreached_rows_are_the_general_paths(name):
    """An unreached branch's closest configuration is the general path's, clipped into the
    limits, whichever route: the plan's compiled verdict kept it outside them, measured
    there (z1: 75 of 300 such calls differed)."""
    a = arm(name)
    rng = np.random.default_rng(11)
    Q = a.random_q(rng, n=60)
    unreached = 0
    for k in range(30):
        T, q0 = a.fk(Q[k]), Q[30 + k]
        fast = a.solve_all(T, q0=q0)
        general = a.solve_all(T, q0=q0, constraints=[_RefusesNothing()])
        assert len(fast) == len(general)
        for x, y in zip(fast, general):
            assert np.array_equal(x.q, y.q), (x.q, y.q, x.reason)
            assert (x.success, x.status, x.position_error, x.orientation_error) == (
                y.success, y.status, y.position_error, y.orientation_error
            )  # fmt: skip
            unreached += x.status is armik.Status.UNREACHABLE
            assert a.within_limits(x.q) or x.status is armik.Status.JOINT_LIMITS
    if name == "z1":
        assert unreached  # the rows this is about
