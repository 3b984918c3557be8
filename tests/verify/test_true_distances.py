"""One rule for what a result reports, on every route (docs/tolerances.md): its
``position_error`` is the tip's distance to the target's position and its
``orientation_error`` the geodesic angle to the target's rotation, whatever the weights
and the bounds (an infinite one included), a cone on the pose or a spin left free; what the
verdict measured is ``measured``, beside them. Each spelling on ``solve`` (the prepared plan
and the general path), ``solve_all``, ``solve_batch`` (its arrays, its rows, a saved file),
``solve_path``, a task list, the task solver, ``Arms`` and the servo, against Pinocchio's
FK to 1e-12; the verdict's measure against the region's, the cone's or the weights' own
rule written out here."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

import armik

from ..conftest import arm
from ..test_arms import dual_irb120

INF = math.inf
TOL = 1e-12


def _log3(R: np.ndarray) -> np.ndarray:
    return np.asarray(pin.log3(R))


def _truth(X: pin.SE3, T: pin.SE3) -> tuple[float, float]:
    """Pinocchio's distances of the placement X to T: |p - p_t|, |log3(R_t^T R)|."""
    return (
        float(np.linalg.norm(X.translation - T.translation)),
        float(np.linalg.norm(_log3(T.rotation.T @ X.rotation))),
    )


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(u, v))), float(u @ v))


def _verdict(X: pin.SE3, T: pin.SE3, options: dict) -> tuple[float, float]:
    """What the verdict measures, by its own rule: a region's distances outside it (the
    error twist in the target frame, each component past its bound), a cone's axis angle
    outside it, the weights' weighted error (tip frame, rotation weights all 1 here)."""
    if "weights" in options:
        w = np.asarray(options["weights"], dtype=float)
        e = X.rotation.T @ (T.translation - X.translation)
        return float(np.linalg.norm(w[:3] * e)), float(
            np.linalg.norm(_log3(X.rotation.T @ T.rotation))
        )
    e = np.concatenate(
        [T.rotation.T @ (X.translation - T.translation), _log3(T.rotation.T @ X.rotation)]
    )
    bounds = np.asarray(options.get("bounds", (0.0,) * 6), dtype=float)
    out = np.where(
        np.isinf(bounds), 0.0, np.maximum(np.abs(e) - np.where(np.isinf(bounds), 0.0, bounds), 0.0)
    )
    if "cone" in options:
        a, within = np.asarray(options["cone"][:3], dtype=float), options["cone"][3]
        tilt = _angle(X.rotation @ a, T.rotation @ a)
        return float(np.linalg.norm(out[:3])), max(tilt - within, 0.0)
    return float(np.linalg.norm(out[:3])), float(np.linalg.norm(out[3:]))


def _close(got, want) -> bool:
    return got is not None and abs(got - want) <= TOL


def _check(name, q, errors, measured, T, options, a, verdict=True) -> None:
    """``errors`` (position, orientation) of the answer ``q`` are its true distances to T,
    ``measured`` what the verdict measured (``verdict``: checked against the rule)."""
    X = a.fk(q)
    pos, ori = _truth(X, T)
    assert _close(errors[0], pos) and _close(errors[1], ori), (name, errors, (pos, ori))
    if verdict:
        want = _verdict(X, T, options)
        assert _close(measured[0], want[0]) and _close(measured[1], want[1]), (name, measured, want)


UR5_Q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.4])
T0 = arm("ur5").fk(UR5_Q)
OFF = pin.SE3(T0.rotation, T0.translation + np.array([0.25, 0.12, 0.08]))  # the position off
SPUN = T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.45])), np.zeros(3))  # turned about z
TILTED = T0 * pin.SE3(
    pin.exp3(np.array([0.3, 0.0, 0.0])) @ pin.exp3(np.array([0.0, 0.0, 0.4])), np.zeros(3)
)
BOXED = T0 * pin.SE3(pin.exp3(np.array([0.05, -0.04, 0.1])), np.array([0.01, -0.02, 0.015]))

# (name, target, options): each a request whose verdict measures other than the distances
CASES = [
    ("position free", OFF, {"bounds": (INF, INF, INF, 0.0, 0.0, 0.0)}),
    ("spin free", SPUN, {"bounds": (0.0, 0.0, 0.0, 0.0, 0.0, INF)}),
    ("box", BOXED, {"bounds": (0.03,) * 3 + (0.2,) * 3}),
    ("weights", OFF, {"weights": (0, 0, 0, 1, 1, 1)}),
    ("cone on a pose", TILTED, {"cone": (0.0, 0.0, 1.0, 0.6)}),
]
IDS = [c[0] for c in CASES]


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_solve_and_solve_all_report_the_true_distances(case):
    """The prepared plan (a float array seed), the general path (a seed of numpy floats)
    and every answer of ``solve_all``; a success's words say the distances to the target."""
    name, T, options = case
    a = arm("ur5")
    fast = a.solve(T, q0=UR5_Q, **options)
    general = a.solve(T, q0=tuple(np.float64(v) for v in UR5_Q), **options)
    every = a.solve_all(T, q0=UR5_Q, **options)
    assert fast.success and general.success and every, (fast.reason, general.reason)
    for r in [fast, general, *every]:
        _check(name, r.q, (r.position_error, r.orientation_error), r.measured, T, options, a)
    pos, ori = fast.position_error, fast.orientation_error  # Pinocchio's, to 1e-12
    assert f"the tip is {pos:.3g} m, {ori:.3g} rad from the target" in fast.reason, fast.reason
    assert "region's centre" not in fast.reason and fast.reason == general.reason


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_a_batch_its_rows_and_its_file_report_the_true_distances(case, tmp_path):
    name, T, options = case
    a = arm("ur5")
    b = a.solve_batch([T, T], q0=UR5_Q, workers=1, **options)
    back = armik.BatchResult.load(b.save(tmp_path / "b.npz"))
    assert b.success.all(), b.summary()
    for batch in (b, back):
        for i in range(2):
            errors = (batch.position_error[i], batch.orientation_error[i])
            _check(name, batch.q[i], errors, batch.measured[i], T, options, a)
            row = batch[i]
            _check(
                name,
                row.q,
                (row.position_error, row.orientation_error),
                row.measured,
                T,
                options,
                a,
            )
            assert row.reason == b[i].reason
    assert "region's centre" not in b.summary() and "distance" in b.summary()


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_a_path_reports_the_true_distances_to_its_poses_as_given(case):
    """A path whose bounds free a spin solves each pose turned to the spin nearest the one
    before: its distances are to the poses as given all the same."""
    name, T, options = case
    a = arm("ur5")
    p = a.solve_path([T, T], UR5_Q, **options)
    assert p.success.all(), p.summary()
    for i in range(2):
        errors = (p.position_error[i], p.orientation_error[i])
        # (the verdict measured each pose turned: its spin the path's choice)
        _check(name, p.q[i], errors, p.measured[i], T, options, a, name != "spin free")


POSE_CASES = [c for c in CASES if "cone" not in c[2]]


@pytest.mark.parametrize("case", POSE_CASES, ids=[c[0] for c in POSE_CASES])
def test_a_pose_task_reports_the_true_distances_on_every_route(case):
    """``armik.Pose(T, bounds=..., weights=...)``: lowered to the compiled path (solve, a
    batch, a path), solved by the task solver (a joint held), and followed by the servo."""
    name, T, options = case
    a = arm("ur5")
    task = armik.Pose(T, **options)
    r = a.solve([task], q0=UR5_Q)
    batch = a.solve_batch([[task], [task]], q0=UR5_Q, workers=1)
    path = a.solve_path([[task], [task]], UR5_Q)
    held = a.solve([task], q0=UR5_Q, hold={"wrist_3_joint": float(UR5_Q[5]) + 0.05})
    assert r.success and batch.success.all() and path.success.all() and held.success
    assert held.solver == "tasks", held.solver
    for got, verdict in ((r, True), (batch[1], True), (path[1], name != "spin free"), (held, True)):
        errors = (got.position_error, got.orientation_error)
        _check(name, got.q, errors, got.measured, T, options, a, verdict)
    pos, ori = held.position_error, held.orientation_error  # Pinocchio's, to 1e-12
    assert f"the tip is {pos:.3g} m, {ori:.3g} rad from the target" in held.reason
    step = a.servo(UR5_Q).step(task)
    record = a.servo(UR5_Q).track([task] * 2)
    _check(name, step.q, (step.position_error, step.orientation_error), None, T, options, a, False)
    errors = (record.position_error[1], record.orientation_error[1])
    _check(name, record.q[1], errors, None, T, options, a, False)


def test_a_position_in_a_box_reports_its_distance_to_the_point():
    """``armik.Position(p, bounds=...)`` (the task solver, a batch and a path of it, the
    servo) and ``bounds=`` on a position (the compiled path): the tip's distance to the
    point, the box's free z included; no orientation."""
    a = arm("ur5")
    p = T0.translation - np.array([0.005, 0.0, 0.3])
    task = armik.Position(p, bounds=(0.01, 0.01, INF))
    keyword = {"bounds": (0.01, 0.01, INF, 0.0, 0.0, 0.0)}
    got = [
        a.solve([task], q0=UR5_Q),
        a.solve_batch([[task], [task]], q0=UR5_Q, workers=1)[1],
        a.solve_path([[task], [task]], UR5_Q)[1],
        a.solve(p, q0=UR5_Q, **keyword),
        a.solve_batch([p, p], q0=UR5_Q, workers=1, **keyword)[1],
        a.solve_path([p, p], UR5_Q, **keyword)[1],
    ]
    for r in got:
        assert r.success, r.reason
        X = a.fk(r.q)
        far = float(np.linalg.norm(X.translation - p))
        e = X.translation - p
        outside = np.linalg.norm(np.maximum(np.abs(e[:2]) - 0.01, 0.0))
        assert _close(r.position_error, far) and r.orientation_error is None, r
        assert far > 0.25 and _close(r.measured[0], outside), r.measured
    step = a.servo(UR5_Q).step(task)
    far = float(np.linalg.norm(a.fk(step.q).translation - p))
    assert _close(step.position_error, far) and step.orientation_error is None


def test_arms_report_each_tips_true_distance_apart_over_shared_joints_and_relative():
    """Two IRB 120s solved apart (a tip's pose with its position free), the Panda's elbow
    and hand over shared joints (the hand's position free, or its spin), and a ``Relative``
    task, whose target is the relative pose: on ``solve`` and a batch's and a path's rows,
    each tip's errors are its true distances; ``measured`` the worst tip's measure, the
    region's by its rule, an exact pose's its distances."""
    free = (INF, INF, INF, 0.0, 0.0, 0.0)
    spin = (0.0, 0.0, 0.0, 0.0, 0.0, INF)
    cell = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    q = cell.random_q(np.random.default_rng(3))
    T_l, T_r = cell.fk(q, "l_tool0"), cell.fk(q, "r_tool0")
    moved = pin.SE3(T_r.rotation, T_r.translation + np.array([0.1, 0.05, 0.0]))
    relative = T_l.actInv(moved)
    panda = armik.load("panda", tips=["panda_link4", "panda_hand"])
    qp = panda.middle + 0.1
    elbow, hand = panda.fk(qp, "panda_link4"), panda.fk(qp, "panda_hand")
    shifted = pin.SE3(hand.rotation, hand.translation + np.array([0.0, 0.06, 0.03]))
    spun = hand * pin.SE3(pin.exp3(np.array([0.0, 0.0, 0.45])), np.zeros(3))
    relative_task = armik.Relative("r_tool0", "l_tool0", relative, bounds=free)
    # (robot, q0, the exact tip and its pose, the region's tip, its task, its pose, bounds,
    # the frame its target is in: None, the base)
    runs = [
        (cell, q, ("l_tool0", T_l), "r_tool0", armik.Pose(moved, bounds=free), moved, free, None),
        (cell, q, ("l_tool0", T_l), "r_tool0", relative_task, relative, free, "l_tool0"),
        (panda, qp, ("panda_link4", elbow), "panda_hand", armik.Pose(shifted, bounds=free),
         shifted, free, None),
        (panda, qp, ("panda_link4", elbow), "panda_hand", armik.Pose(spun, bounds=spin), spun,
         spin, None),
    ]  # fmt: skip
    for robot, q0, (exact, T_exact), tip, task, T, bounds, reference in runs:
        targets = {exact: T_exact, tip: task}
        batch = robot.solve_batch({exact: [T_exact] * 2, tip: [task] * 2}, q0=q0, workers=1)
        path = robot.solve_path({exact: [T_exact] * 2, tip: [task] * 2}, q0)
        rows = [robot.solve(targets, q0=q0), batch[1], path[1]]
        for r in rows:
            assert r.success, r.reason
            X = robot.fk(r.q, tip)
            if reference is not None:  # the placement of the tip in the reference's frame
                X = robot.fk(r.q, reference).actInv(X)
            pos, ori = _truth(X, T)
            assert pos > 0.01 or ori > 0.4, (pos, ori)
            assert _close(r.errors[tip][0], pos) and _close(r.errors[tip][1], ori), r.errors
            other = _truth(robot.fk(r.q, exact), T_exact)
            assert _close(r.errors[exact][0], other[0]) and _close(r.errors[exact][1], other[1])
            assert r.position_error == max(e[0] for e in r.errors.values())  # the largest
            assert r.orientation_error == max(e[1] for e in r.errors.values())
            region = _verdict(X, T, {"bounds": bounds})
            want = (max(region[0], other[0]), max(region[1], other[1]))
            assert _close(r.measured[0], want[0]) and _close(r.measured[1], want[1]), (
                r.measured,
                want,
            )
        for out in (batch, path):  # the arrays are the rows'
            assert tuple(out.errors[tip][1]) == out[1].errors[tip]
            assert tuple(out.measured[1]) == out[1].measured


@pytest.mark.parametrize("how", ["bounds", "weights"])
def test_a_cone_on_a_pose_whose_position_is_free_reports_the_tips_distance(how):
    """``cone=`` on a pose with its position free holds the pose's position all the same
    (an ``Axis`` alone holds none): its distance is the tip's, as with the weights; it
    was None (NaN in a batch) beside the angle to the pose's own rotation."""
    a = arm("ur5")
    q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.4])
    T0 = a.fk(q)
    T = pin.SE3(T0.rotation @ pin.exp3(np.array([0.3, 0, 0.4])), T0.translation + [0.2, 0.1, 0])
    freed = {"bounds": (math.inf,) * 3 + (0.0,) * 3} if how == "bounds" else {}
    weights = {"weights": (0, 0, 0, 1, 1, 1)} if how == "weights" else {}
    r = a.solve(T, q0=q, cone=(0, 0, 1, 0.6), **freed, **weights)
    tip = a.fk(r.q)
    assert r.position_error == pytest.approx(
        np.linalg.norm(tip.translation - T.translation), abs=1e-12
    )
    angle = np.linalg.norm(pin.log3(tip.rotation.T @ T.rotation))
    assert r.orientation_error == pytest.approx(angle, abs=1e-12)
    b = a.solve_batch([T, T], q0=q, cone=(0, 0, 1, 0.6), workers=1, **freed, **weights)
    np.testing.assert_allclose(b.position_error, r.position_error, atol=1e-12)
    alone = a.solve([armik.Axis((0, 0, 1), T.rotation[:, 2], within=0.6)], q0=q)
    assert alone.position_error is None  # an Axis alone: no position


@pytest.mark.parametrize(
    "bounds, moved",
    [
        ((math.inf, 0, 0, 0, 0, 0), pin.SE3(np.eye(3), np.array([0.05, 0, 0]))),
        ((0, 0, 0, 0, 0, math.inf), pin.SE3(pin.exp3(np.array([0, 0, 0.5])), np.zeros(3))),
    ],
    ids=["line", "spin"],
)
def test_a_followed_jump_says_what_its_verdict_measured(bounds, moved):
    """A waypoint refused for a hidden jump says, after "verified:", what its verdict
    measured (``measured``) against the tolerances, and the true distances as distances:
    it said "position error 0.06 m (tol 1e-06)" of the line's free x, or quoted the
    distance to the pose spun by the free spin (0.102 rad where the pose is 0.5 rad off)."""
    ur5 = arm("ur5")
    qa = np.array([0.3, -1.2, 1.5, -1.0, 0.2, 0.4])
    qb = qa + np.array([0, 0, 0, 0.1, -0.4, 0])  # a wrist flip hides in this step
    poses = [ur5.fk(x) * moved for x in (qa, qb)]
    p = ur5.solve_path(poses, qa, bounds=bounds)
    assert p.status[1] == "discontinuous"
    pos, ori = p.measured[1]
    words = p.reason(1)
    assert f"position error {pos:.3g} m (tol" in words
    assert f"orientation error {ori:.3g} rad (tol" in words
    tip = ur5.fk(p.q[1])
    d_pos = np.linalg.norm(tip.translation - poses[1].translation)
    d_ori = np.linalg.norm(pin.log3(tip.rotation.T @ poses[1].rotation))
    assert p.position_error[1] == pytest.approx(d_pos, abs=1e-12)
    assert p.orientation_error[1] == pytest.approx(d_ori, abs=1e-12)
    assert f"the tip is {d_pos:.3g} m, {d_ori:.3g} rad from the target" in words


def test_a_search_going_on_past_obstacles_keeps_the_verdicts_measure():
    """With obstacles a numeric solve goes on from its first run's row: that row is its
    verdict's measure again, not its distances, which the result then said as
    ``measured`` too ((0.0457, 1.169) beside the words' "orientation error 0 rad")."""
    a = arm("panda")
    rng = np.random.default_rng(2)
    for _ in range(2):
        q = a.random_q(rng)
        T0 = a.fk(q)
        T = pin.SE3(
            T0.rotation @ pin.exp3(rng.normal(size=3) * 0.3),
            T0.translation + rng.normal(size=3) * 0.03,
        )
    options = dict(q0=q, bounds=(0.001, 0.001, 0.001, 0.01, 0.01, math.inf), max_restarts=3)
    plain = a.solve(T, **options)
    far = [armik.Sphere(0.05, T0.translation + np.array([0.25, 0, 0]))]
    clear = a.solve(T, obstacles=far, **options)
    assert not plain.success and not clear.success  # beyond the region both ways
    assert clear.measured == pytest.approx(plain.measured, abs=1e-9)
    assert clear.measured[1] == 0.0  # the spin is free: its part of the region is met
    tip = a.fk(clear.q)
    assert clear.orientation_error == pytest.approx(
        np.linalg.norm(pin.log3(tip.rotation.T @ T.rotation)), abs=1e-12
    )


def test_a_batch_of_an_aim_and_a_pose_names_no_axis():
    """A row-by-row batch whose rows differ in aiming (a position with an axis, a pose
    with its rotation free) says its largest distances as distances: it took the first
    row's aim for all and called the pose's 0.5 rad "its axis 0.5 rad from its direction"."""
    a = arm("ur5")
    q = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.4])
    T = a.fk(q)
    T2 = pin.SE3(T.rotation @ pin.exp3(np.array([0.5, 0, 0])), T.translation)
    aim = [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2])]
    b = a.solve_batch([aim, [armik.Pose(T2, bounds=(0, 0, 0) + (math.inf,) * 3)]], q0=q, workers=1)
    assert b.success.all() and b.orientation_error[1] == pytest.approx(0.5, abs=1e-9)
    assert "axis" not in b.summary()
    alike = a.solve_batch([aim, aim], q0=q, workers=1)
    assert "axis" in alike.summary()  # every row aims: said in its terms
