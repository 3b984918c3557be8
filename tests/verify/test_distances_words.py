"""A success measured apart says what its verdict measured, then its distances to the
target, whatever the region frees and the weights (``armik.verify.distances``)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm

# z free: the verdict leaves it out, the distances do not
BOUNDS = (0.01, 0.01, np.inf, 0.1, 0.1, 0.1)
WEIGHTS = (1, 1, 1, 1, 1, 0.5)


def _target(a) -> pin.SE3:
    T = a.fk(a.random_q(np.random.default_rng(1)))
    return pin.SE3(T.rotation, T.translation + T.rotation @ np.array([0.003, 0.0, 0.2]))


@pytest.mark.parametrize("solver", ["auto", "qp"])
def test_weights_with_bounds_say_the_distance_to_the_target(solver):
    ur5 = arm("ur5")
    T = _target(ur5)
    r = ur5.solve(T, bounds=BOUNDS, weights=WEIGHTS, solver=solver)
    assert r.success, r.reason
    # 0.2 m along the free z: the tip is that far from the target, and that is reported
    far = np.linalg.norm(ur5.fk(r.q).translation - T.translation)
    assert far > 0.1 and r.position_error == pytest.approx(far, abs=1e-12)
    assert r.reason.endswith(
        f"the tip is {far:.3g} m, {r.orientation_error:.3g} rad from the target"
    ), r.reason
    assert "region's centre" not in r.reason and "(on the weighted axes)" in r.reason


def test_weights_with_bounds_say_the_distance_to_the_target_on_every_answer():
    ur5 = arm("ur5")
    T = _target(ur5)
    rs = ur5.solve_all(T, bounds=BOUNDS, weights=WEIGHTS)
    assert len(rs) and all(r.success for r in rs)
    for r in rs:
        far = np.linalg.norm(ur5.fk(r.q).translation - T.translation)
        assert r.reason.endswith(
            f"the tip is {far:.3g} m, {r.orientation_error:.3g} rad from the target"
        )


def test_weights_alone_still_say_the_target():
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(2)))
    r = ur5.solve(T, weights=(1, 1, 1, 1, 1, 0.5))
    assert r.success and r.reason.endswith("from the target"), r.reason


@pytest.mark.parametrize("region", [False, True])
def test_every_answer_with_obstacles_says_its_distances_before_its_closest_pair(region):
    """``solve_all`` with obstacles checks collisions before the distances are measured:
    its words say them in ``solve``'s order, what the verdict measured, the distances,
    then the closest pair."""
    ur5 = arm("ur5")
    far = armik.Sphere(0.05, (2.0, 0.0, 0.0))
    kw = dict(weights=WEIGHTS, obstacles=[far], **({"bounds": BOUNDS} if region else {}))
    T = _target(ur5) if region else ur5.fk(ur5.random_q(np.random.default_rng(2)))
    rs = ur5.solve_all(T, **kw)
    one = ur5.solve(T, **kw)
    assert len(rs) and one.success
    for r in [*rs, one]:
        said, clear, pair = r.reason.partition("; collision-free: closest ")
        assert clear and pair.endswith("(margin 0 m)"), r.reason
        assert said.endswith(
            f"{r.position_error:.3g} m, {r.orientation_error:.3g} rad from the target"
        ), r.reason


def _successes(a, target, **options):
    """The reasons of a success by solve, solve_all, a batch row and a loaded batch."""
    import tempfile
    from pathlib import Path

    rows = a.solve_batch([target, target], q0=a.middle, **options)
    got = [a.solve(target, q0=a.middle, **options), a.solve_all(target, q0=a.middle, **options)[0]]
    assert all(r.success for r in got) and rows.success.all(), [r.reason for r in got]
    with tempfile.TemporaryDirectory() as folder:
        back = armik.BatchResult.load(rows.save(Path(folder) / "rows.npz"))
    assert back.reason(1) == rows.reason(1)
    return got, [r.reason for r in got] + [rows.reason(0), back.reason(1)]


def test_weights_that_free_the_position_say_no_position_error_of_0():
    """weights=(0, 0, 0, 1, 1, 1): it said 'position error 0 m (tol 1e-06), orientation
    error ... (on the weighted axes); the tip is 1.14 m ... from the target'."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(3)))
    got, said = _successes(ur5, T, weights=(0, 0, 0, 1, 1, 1))
    r = got[0]
    far = np.linalg.norm(ur5.fk(r.q).translation - T.translation)  # by Pinocchio
    assert far > 0.1 and r.position_error == pytest.approx(far, abs=1e-12)
    for reason in said:
        head, _, tail = reason.partition("; the tip is ")
        assert "position error" not in head and "orientation error" in head, reason
        assert "(on the weighted axes)" in head and tail.endswith("from the target"), reason
    assert f"the tip is {far:.3g} m," in said[0]


@pytest.mark.parametrize(
    "target",
    [
        lambda a, T: ([armik.LookAt((0.3, 0.2, 0.1))], {}),
        lambda a, T: ([armik.Axis((0, 0, 1), (1, 0, 0))], {}),
        lambda a, T: (T, {"bounds": (np.inf, np.inf, np.inf, 0.1, 0.1, 0.1)}),
    ],
)
def test_a_region_that_frees_the_position_says_no_position_error_of_0(target):
    """A look-at, an axis, or bounds inf on x, y and z: it said 'inside the region:
    position error 0 m ...; the tip is 0 m, ... rad from the region's centre'. The verdict
    measured no position: its words say none; the tip's distance to the pose's position is
    said after them, and an aim alone, which holds no position, says its axis in its own
    terms, no region (tests/verify/test_aim_words.py)."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(3)))
    given, options = target(ur5, T)
    got, said = _successes(ur5, given, **options)
    aimed = not options
    for reason in said:
        assert "position error" not in reason, reason
        assert ("inside the region: " in reason) != aimed, reason
        assert "the tip is " in reason or aimed, reason
    for r in got:  # an aim alone holds no position; a pose's is its own
        far = np.linalg.norm(ur5.fk(r.q).translation - T.translation)
        assert r.position_error == (None if aimed else pytest.approx(far, abs=1e-12))
        assert aimed or f"the tip is {far:.3g} m, " in r.reason


def test_bounds_that_free_the_rotation_say_no_orientation_error_of_0():
    """The verdict measured no rotation: its words say none; the tip's angle to the pose's
    rotation is said after them."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(3)))
    T = pin.SE3(T.rotation, T.translation + np.array([0.03, 0.0, 0.0]))
    got, said = _successes(ur5, T, bounds=(0.05, 0.01, 0.01, np.inf, np.inf, np.inf))
    for reason in said:
        head, _, tail = reason.partition("; the tip is ")
        assert "inside the region: position error" in head, reason
        assert "orientation error" not in head and " rad" not in head, reason
        assert tail.endswith(" rad from the target"), reason
    for r in got:
        truth = np.linalg.norm(pin.log3(ur5.fk(r.q).rotation.T @ T.rotation))
        assert r.orientation_error == pytest.approx(truth, abs=1e-12)


def test_the_task_solvers_region_that_frees_the_position_says_its_distance():
    """A joint held on a 6-joint arm (the task solver): bounds inf on x, y and z said 'the
    tip is 0 m, 0.139 rad from the region's centre'; the tip's distance to the position is
    said, as with weights of 0 on the position."""
    ur5 = arm("ur5")
    q = ur5.random_q(np.random.default_rng(3))
    T = ur5.fk(q)
    held = {"hold": {"wrist_3_joint": float(q[5]) - 0.3}, "q0": ur5.middle}
    for options in (
        {"bounds": (np.inf, np.inf, np.inf, 0.5, 0.5, 0.5)},
        {"weights": (0, 0, 0, 1, 1, 1)},
    ):
        r = ur5.solve(T, **options, **held)
        X = ur5.fk(r.q)  # by Pinocchio
        far = np.linalg.norm(X.translation - T.translation)
        angle = np.linalg.norm(pin.log3(X.rotation.T @ T.rotation))
        assert r.success and far > 0.01, r.reason
        assert (r.position_error, r.orientation_error) == pytest.approx((far, angle), abs=1e-12)
        assert f"the tip is {far:.3g} m, {angle:.3g} rad from the target" in r.reason, r.reason


def test_a_pose_tasks_weights_that_free_the_position_keep_its_distance_said():
    """``armik.Pose(T, weights=(0, 0, 0, 1, 1, 1))`` is a region of bounds 0: its distance
    to the position is a true one, said, as bounds inf say it."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(3)))
    got, said = _successes(ur5, [armik.Pose(T, weights=(0, 0, 0, 1, 1, 1))])
    far = np.linalg.norm(ur5.fk(got[0].q).translation - T.translation)  # by Pinocchio
    assert far > 0.1 and f"the tip is {far:.3g} m, " in said[0], said[0]
    for reason in said:
        assert "position error" not in reason and "the tip is " in reason, reason


def test_a_batch_summary_leaves_out_what_the_verdicts_measured_of_a_free_part():
    # its rows' reasons left out the free position; the summary still said "at most 0 m"
    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(1))
    b = ur5.solve_batch([T, T], q0=ur5.middle, weights=(0, 0, 0, 1, 1, 1))
    assert b.success.all()
    measured = b.summary().partition("(the verdicts measured at most ")[2]
    assert measured.endswith(" rad)") and " m" not in measured, b.summary()


def test_a_frame_other_than_the_tip_says_its_distance_to_its_target():
    # the task solver said "frame 'wrist_2_link' is 0 m, 0.156 rad from the region's
    # centre" of a position its bounds left wholly free, 0.36 m off
    ur5 = arm("ur5")
    q = ur5.random_q(np.random.default_rng(3))
    free = (np.inf,) * 3 + (0.1,) * 3
    shift = np.array([0.3, 0.2, 0.0])
    tasks = []
    for frame in ("wrist_2_link", "forearm_link"):
        T = ur5.fk(q, frame)
        tasks.append(
            armik.Pose(pin.SE3(T.rotation, T.translation + shift), frame=frame, bounds=free)
        )
    for given in (tasks[:1], tasks):
        r = ur5.solve(given, q0=ur5.middle)
        assert r.success, r.reason
        far = max(np.linalg.norm(ur5.fk(r.q, t.frame).translation - t.T.translation) for t in given)
        assert r.position_error == pytest.approx(far, abs=1e-12) and far > 0.1
        said = r.reason.rpartition("; ")[2]
        to = "the target" if len(given) == 1 else "its target"  # several: each frame's
        assert said.endswith(f"{far:.3g} m, {r.orientation_error:.3g} rad from {to}"), r.reason


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_jump_on_a_path_says_what_its_answer_s_verdict_measured(plan):
    # a waypoint turned into a jump said "verified: position error 0 m" of a position its
    # bounds freed, and "position error 1.3 m (tol 1e-06)" of one its weights freed
    ur5 = arm("ur5")
    rng = np.random.default_rng(5)
    poses = [ur5.fk(ur5.random_q(rng)) for _ in range(3)]
    free = {
        "bounds": ((np.inf,) * 3 + (0.1,) * 3, "; the tip is"),
        "weights": ((0, 0, 0, 1, 1, 1), "(on the weighted axes); the tip is"),
    }
    for option, (value, said) in free.items():
        p = ur5.solve_path(poses, q0=ur5.middle, max_joint_step=0.05, plan=plan, **{option: value})
        jumps = [i for i in range(len(p)) if p.status[i] == "discontinuous"]
        assert jumps
        for i in jumps:
            verified = p.reason(i).partition(", verified: ")[2]
            assert said in verified and "position error" not in verified, p.reason(i)
            assert verified.endswith("from the target"), p.reason(i)
