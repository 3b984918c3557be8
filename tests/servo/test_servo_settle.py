"""A target the joint limits keep out of reach: the servo comes to rest at a local minimum
of the error within the limits and says ``stalled``; a target it reaches gets no stalled
tick on the way (armik.servo.minimum, armik.servo.step's damping, armik.servo.box_qp)."""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from numba import njit

import armik
from armik.kernel.step import active_set
from armik.servo.box_qp import nearest_in_box
from armik.servo.streams import START

STILL = 1e-9  # rad/s: the viewer's rest (``view.follow.STILL``)


def _talos_urdf() -> Path:
    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
    return share / "share/example-robot-data/robots/talos_data/robots/talos_reduced.urdf"


def _largest_drop(arm, q, error, tip=None) -> float:
    """The most that a feasible move of q (each joint and 500 random directions, 1e-4 to
    1e-2 rad, clipped into the limits) lowers ``error`` (Pinocchio's FK)."""
    e0 = error(arm.fk(q, tip) if tip else arm.fk(q))
    rng = np.random.default_rng(0)
    n = q.shape[0]
    best = 0.0
    for d in [*np.eye(n), *-np.eye(n), *rng.normal(size=(500, n))]:
        for size in (1e-4, 1e-3, 1e-2):
            moved = np.clip(q + size * d / np.linalg.norm(d), arm.lower, arm.upper)
            T = arm.fk(moved, tip) if tip else arm.fk(moved)
            best = max(best, e0 - error(T))
    return best


def _rests(record, by: int) -> bool:
    """Whether every tick from ``by`` on commands no motion."""
    return bool(np.abs(record.dq[by:]).max() < STILL)


def test_a_talos_arm_sent_where_its_limits_block_it_settles_stalled_at_a_minimum():
    """The TALOS right arm (torso and 7 joints) told to reach 0.3 m down, which its limits
    keep out of reach: it wandered at up to 1.1 rad/s, 9-14 mm off, ``joint_limit`` for
    good. Now it rests within 600 ticks (1.2 s), stalled, where no feasible small move of
    any joint lowers the error (Pinocchio's FK)."""
    right = armik.load(_talos_urdf(), tip="gripper_right_base_link")
    q0 = right.middle.copy()
    q0[5], q0[3] = -1.2, -0.3
    p = right.fk(q0).translation + np.array([0.0, 0.0, -0.3])
    record = right.servo(q0).track([p] * 900)
    assert _rests(record, 600)
    assert set(record.status[600:].tolist()) == {"stalled"}
    q = record.q[-1]
    assert np.all(q >= right.lower) and np.all(q <= right.upper)
    error = float(np.linalg.norm(p - right.fk(q).translation))
    assert error == pytest.approx(record.position_error[-1], abs=1e-12)
    assert 0.008 < error < 0.0095  # off target: the limits keep it 9 mm away
    # a local minimum of the error within the limits, to the stall test's first order
    assert _largest_drop(right, q, lambda T: np.linalg.norm(p - T.translation)) < 1e-6


def test_two_talos_hands_pulled_apart_settle_stalled():
    """Both TALOS hands pulled 0.65 m apart over the shared torso (the union's step): at
    rest within 700 ticks, stalled, where no feasible small move lowers the larger error."""
    talos = armik.load(_talos_urdf(), tips=["gripper_left_base_link", "gripper_right_base_link"])
    q0 = talos.middle.copy()
    q0[[5, 12]], q0[3], q0[10] = -1.2, 0.3, -0.3
    left, right = talos.tips
    goal = {
        left: talos.fk(q0, left).translation + np.array([0.0, 0.65, 0.0]),
        right: talos.fk(q0, right).translation + np.array([0.0, -0.65, 0.0]),
    }
    record = talos.servo(q0).track([goal] * 1000)
    assert _rests(record, 700)
    assert set(record.status[700:].tolist()) == {"stalled"}
    q = record.q[-1]

    def worst(qq):
        return max(np.linalg.norm(goal[t] - talos.fk(qq, t).translation) for t in talos.tips)

    e0 = worst(q)
    assert e0 == pytest.approx(record.position_error[-1], abs=1e-12) and e0 > 0.05
    rng = np.random.default_rng(1)
    for d in [*np.eye(talos.dof), *rng.normal(size=(200, talos.dof))]:
        for size in (1e-3, -1e-3, 1e-2):
            moved = np.clip(q + size * d / np.linalg.norm(d), talos.lower, talos.upper)
            assert worst(moved) > e0 - 1e-6


def test_a_target_behind_a_saddle_is_reached_with_no_stalled_tick():
    """The Panda from START sent 0.6 m back: its shoulder and wrist reach their limits with
    the arm in its plane of symmetry, where the error's gradient vanishes but turning out
    of the plane lowers it (a saddle). It is not called stalled there, and leaves it."""
    arm = armik.load("panda")
    q0 = START["panda"]
    T0 = arm.fk(q0)
    record = arm.servo(q0).track([T0.translation + np.array([-0.6, 0.0, 0.0])] * 1200)
    assert "stalled" not in set(record.status.tolist())
    assert record.status[-1] == "on_target" and record.position_error[-1] < 1e-6


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_reached_targets_are_tracked_with_no_stalled_tick(name):
    """Targets the servo reaches (the FK of a configuration halfway to a random one):
    no stalled tick on the way, on target within the ticks given."""
    arm = armik.load(name)
    rng = np.random.default_rng(3)
    reached = 0
    for _ in range(8):
        q0, q1 = arm.random_q(int(rng.integers(1e9))), arm.random_q(int(rng.integers(1e9)))
        target = arm.fk(q0 + 0.5 * (q1 - q0))
        record = arm.servo(q0=q0, dt=0.004).track([target] * 1200)
        if record.status[-1] == "on_target":
            reached += 1
            assert "stalled" not in set(record.status.tolist())
    assert reached >= 4  # (the others rest at a joint limit, stalled)


@njit(cache=True)
def _nearest(H, t, lb, ub):
    n = t.shape[0]
    x, r, p = np.zeros(n), np.zeros(n), np.zeros(n)
    side, free = np.zeros(n, np.int64), np.zeros(n, np.int64)
    ok = nearest_in_box(H, t, lb, ub, x, side, free, np.zeros((n, n)), r, p)
    return ok, x


def test_the_box_qp_is_exact_where_the_fast_iteration_cycles():
    """``box_qp.nearest_in_box`` against the optimality conditions on random boxes and
    metrics (strongly coupled ones among them): within the box, the gradient projected
    on the box zero to rounding, where the primal-dual iteration can cycle."""
    rng = np.random.default_rng(0)
    cycled = 0
    for _ in range(400):
        n = int(rng.integers(1, 17))
        A = rng.normal(size=(int(rng.integers(1, 13)), n)) * rng.choice([1.0, 1e-3, 1e3], n)
        H = A.T @ A
        H += np.trace(H) * rng.choice([1e-9, 1e-3]) * np.eye(n)
        t = 3.0 * rng.normal(size=n)
        lb, ub = -rng.random(n), rng.random(n)
        ok, x = _nearest(H, t, lb, ub)
        assert ok and np.all(x >= lb) and np.all(x <= ub)
        z = np.zeros(n, np.int64)
        cycled += not active_set(
            np.linalg.inv(H), t, lb, ub, t, z, z.copy(), z.copy(), np.zeros((n, n)),
            np.zeros(n), np.zeros(n), np.zeros((n, n)), np.zeros(n),
        )  # fmt: skip
        g = H @ (x - t)  # the objective's gradient; none may point into the box
        free = np.where((x <= lb) & (g > 0.0), 0.0, np.where((x >= ub) & (g < 0.0), 0.0, g))
        assert np.abs(free).max() <= 1e-12 * np.abs(H).max() * max(np.abs(x - t).max(), 1.0)
    assert cycled >= 5  # (9 of these 400: the servo's step clipped there)


def test_a_planar_arm_held_off_by_its_elbow_says_joint_limit_then_rests_stalled():
    """The two-link planar arm with its elbow narrowed to (0.2, 0.5) rad sent where the
    elbow would need 1.6: ``joint_limit`` while the elbow holds, then at rest, stalled,
    with the elbow at its limit and no feasible small move lowering the error."""
    plain = armik.load("planar_2link")
    arm = plain.with_limits({"joint2": (0.2, 0.5)})
    target = plain.fk(np.array([0.3, 1.6])).translation
    record = arm.servo(np.array([0.0, 0.3]), dt=0.002).track([target] * 1000)
    statuses = record.status.tolist()
    assert "joint_limit" in statuses and statuses[-1] == "stalled"
    assert _rests(record, 500)
    q = record.q[-1]
    assert q[1] == pytest.approx(0.5, abs=1e-9)  # at the elbow's limit
    assert record.position_error[-1] > 0.4
    assert _largest_drop(arm, q, lambda T: np.linalg.norm(target - T.translation)) < 1e-6


@pytest.mark.parametrize("away", [200, 300, 700])
def test_the_irb120_sent_far_away_and_back_recovers(away):
    """The IRB 120 from START sent 3 m away, then back to where it started: after 300
    ticks away it folded through its elbow singularity onto the other branch and stayed
    at joint 3's lower limit, 0.14 m off, joint_limit for good. It now stretches less
    deep into the singularity (the damping grows with the error no joint removes) and is
    back on target within 500 ticks of the return, whatever the excursion."""
    arm = armik.load("abb_irb120")
    q0 = START["abb_irb120"]
    T0 = arm.fk(q0)
    far = pin.SE3(T0.rotation, T0.translation + np.array([3.0, 0.0, 0.0]))
    record = arm.servo(q0, dt=0.002).track([far] * away + [T0] * 500)
    assert record.status[-1] == "on_target" and record.position_error[-1] < 1e-9
    assert "stalled" not in set(record.status.tolist())


def test_near_a_singularity_the_pull_never_holds_the_arm_short_of_its_target():
    """The Kinova sent 25 cm along y comes near its wrist singularity (sigma 0.02), where
    the damping's pull toward q0 once balanced the gradient: it came to rest 0.8 mm off a
    target a Gauss-Newton step from there reaches, saying 'singularity' for good. The
    pull now acts only along what no row sees: on target, by Pinocchio's FK."""
    arm = armik.load("kinova")
    q0 = np.array([0.41, 3.82, 3.6, 0.38, 2.65, -0.12])
    T0 = arm.fk(q0)
    target = pin.SE3(T0.rotation, T0.translation + np.array([0.0, 0.25, 0.0]))
    record = arm.servo(q0).track([target] * 2000)
    assert record.sigma[-1] < 0.05  # (near the singularity)
    assert set(record.status[-500:].tolist()) == {"on_target"}
    T = arm.fk(record.q[-1])
    assert np.linalg.norm(T.translation - target.translation) < 1e-6
    assert np.linalg.norm(pin.log3(target.rotation.T @ T.rotation)) < 1e-6
