"""The swept 7R closed form (``hold=`` on joint 7, ``solver="swept"``) where two axes one
joint apart lie in one line: the Panda's joints 3 and 5 at joint 4 = 0 (its limits widened
to hold 0), where the closed form's split was its rounding's, not called singular. Only the
pair's sum turns the tip; the split is kept at q0's value, or the value nearest it within
both limits, and the row called singular, so that the configuration the target came from
(or one with the same pose, only the split moved) is among the successes, each checked
here by Pinocchio's FK. (The iiwa's joints 3 and 5 in line at joint 4 = 0 are its elbow
stretched, which the closed form calls singular itself.)"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik

WIDE = {"panda_joint4": (-3.0718, 1.0)}  # joint 4's limits holding 0


def panda_wide() -> armik.Arm:
    return armik.load("panda").with_limits(WIDE)


def panda_shifted() -> armik.Arm:
    """The Panda with each joint's limits shifted to hold a configuration at joint 4 = 0."""
    return armik.load("panda").with_limits(SHIFTED)


SHIFTED = {
    "panda_joint1": (-1.7224, 3.2776), "panda_joint2": (-2.5777, 2.4223),
    "panda_joint3": (-2.7809, 4.2191), "panda_joint4": (-3.4291, 3.5709),
    "panda_joint5": (-1.6641, 0.8359), "panda_joint6": (-4.1997, 2.8003),
    "panda_joint7": (-1.4858, -0.4858),
}  # fmt: skip


def _placed(a: armik.Arm, q: np.ndarray) -> pin.SE3:
    """The tip's placement at ``q`` by Pinocchio's FK on the arm's own model."""
    km = a.kinematics
    data = km.model.createData()
    pin.framesForwardKinematics(km.model, data, km.to_pin(np.asarray(q, dtype=float)))
    return data.oMf[km.tip_frame_id].copy()


def _true(a: armik.Arm, r, q: np.ndarray) -> None:
    """``r`` reaches the tip's placement at ``q`` (Pinocchio's FK), joint 7 exactly at
    q's, every joint within the limits."""
    assert np.linalg.norm(pin.log6(_placed(a, r.q).inverse() * _placed(a, q)).vector) < 1e-7
    assert r.q[6] == q[6]
    assert a.within_limits(r.q)


def _wrapped(a, b) -> float:
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def _found(a: armik.Arm, q: np.ndarray, split: list[int]) -> list:
    """``solve_all(hold=)``'s successes, each checked, and those that are ``q`` but for the
    ``split`` pair."""
    T = a.fk(q)
    v = float(q[6])
    ok = [r for r in a.solve_all(T, hold={a.joint_names[6]: v}) if r.success]
    for r in ok:
        _true(a, r, q)
    return [r for r in ok if _wrapped(np.delete(r.q, split), np.delete(q, split)) < 1e-5]


CASES = {  # a configuration within the limits whose split the closed form left outside them
    "panda joint 4 = 0": (
        panda_shifted,
        [0.0, 1.835782, 1.134787, 0.0, -1.18262, -0.358901, -1.196562],
        [2, 4],
    ),
    "panda joint 4 = -1e-9": (
        panda_wide,
        [-2.352710926188906, 0.6278539897591542, 2.406927160981603, -1e-09,
         2.425891471182768, -0.0007559055784758517, 2.6329910384593034],
        [2, 4],
    ),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_split_in_line_is_found_within_the_limits(case):
    load, q, split = CASES[case]
    a, q = load(), np.array(q)
    assert a.within_limits(q)
    same = _found(a, q, split)
    assert same, case
    assert all(r.singular for r in same if _wrapped(r.q, q) > 1e-5)


def test_the_split_keeps_q0s_value_and_says_singular():
    a = panda_shifted()
    q = np.array(CASES["panda joint 4 = 0"][1])
    T = a.fk(q)
    ok = [r for r in a.solve_all(T, hold={"panda_joint7": q[6]}) if r.success]
    at_zero = [r for r in ok if abs(r.q[3]) < 1e-9]
    assert len(at_zero) == 2 and all(r.singular and "singular" in r.reason for r in at_zero)
    assert all(r.q[4] == pytest.approx(a.middle[4], abs=1e-12) for r in at_zero)  # q0's
    locked = armik.load("panda", locked={"panda_joint7": float(q[6])})
    locked = locked.with_limits({k: v for k, v in SHIFTED.items() if k != "panda_joint7"})
    assert len(ok) >= sum(r.success for r in locked.solve_all(T))  # none fewer
    one = a.solve(T, hold={"panda_joint7": q[6]}, q0=q)  # from q: q's pose, q0's split
    assert one.success
    _true(a, one, q)
    swept = a.solve(T, solver="swept", q0=q)  # the sweep at q0's joint 7 first
    assert swept.success and swept.q[6] == q[6]


@pytest.mark.parametrize("seed", [7, 8])
def test_targets_at_and_near_the_line_keep_their_configuration(seed):
    a = panda_wide()
    rng = np.random.default_rng(seed)
    for _ in range(30):
        q = a.random_q(rng)
        q[3] = rng.choice([0.0, 1e-12, -1e-10, 1e-9, -1e-8, 1e-6])
        if a.within_limits(q):
            assert _found(a, q, [2, 4]), q.tolist()


def test_the_iiwas_stretched_elbow_keeps_every_shoulder():
    """The iiwa's joints 3 and 5 in line at joint 4 = 0 are its elbow stretched, which the
    closed form calls singular: the split is still made, so that the configuration of the
    target (but for the split) is among the successes, as at the Panda's. The first is one
    whose split the closed form left outside joint 3's limits."""
    a = armik.load("kuka_iiwa14")
    rng = np.random.default_rng(4)
    first = [-0.746773, 0.149062, -2.147778, 0.0, -1.166115, -1.126557, 2.588474]
    for k in range(30):
        q = np.array(first) if k == 0 else a.random_q(rng)
        q[3] = (0.0, 1e-12, -1e-12)[k % 3]
        if abs(q[1]) > 1e-3:  # joint 2 at 0 too puts joint 1 in the line
            assert _found(a, q, [2, 4]), q.tolist()
