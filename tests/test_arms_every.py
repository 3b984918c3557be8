"""``Arms.solve_all`` with a tip placed relative to another (``armik.Relative``) on chains
that share no joint: the reference chain's answers in turn, the relative tip's own answers
at each, every combination listed and checked here by Pinocchio's FK of the whole URDF;
where the reference tip's answers are a continuum (a position) every combination at one
sampled orientation, and where the chains are solved at once (shared joints, a cycle) the
one answer, each said in the reason."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import whole_placements
from tests.test_arms import dual_irb120

LEFT, RIGHT = "l_tool0", "r_tool0"


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=[LEFT, RIGHT])


@pytest.fixture(scope="module")
def whole():
    """The whole URDF's Pinocchio model, its data and the tips' frame ids: the check."""
    model = pin.buildModelFromXML(dual_irb120())
    return model, model.createData(), model.getFrameId(LEFT), model.getFrameId(RIGHT)


def _placed(whole, cell, q) -> tuple[pin.SE3, pin.SE3]:
    """Both tips' placements at the robot's ``q`` by Pinocchio on the whole URDF."""
    model, data, left, right = whole
    whole_placements(model, data, cell.joint_names, q)
    return pin.SE3(data.oMf[left]), pin.SE3(data.oMf[right])


def _relative_error(L: pin.SE3, R: pin.SE3, T: pin.SE3) -> np.ndarray:
    """The right tip's pose in the left's against ``T``: (x, y, z, rx, ry, rz) in ``T``'s
    frame, as ``Relative`` holds it."""
    return pin.log6(T.actInv(L.actInv(R))).vector


def _count(arm, target) -> int:
    return sum(r.success for r in arm.solve_all(target))


@pytest.mark.parametrize("seed", [8, 21, 40])
def test_a_relative_target_lists_every_combination_as_the_two_poses_do(cell, whole, seed):
    """The same request as two poses, given as a pose and a relative pose (a mapping, or a
    flat list of tasks): the same answers (it listed one), each holding the left pose and
    the relative pose on Pinocchio's FK, their number the product of the chains'."""
    q = cell.random_q(np.random.default_rng(seed))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    poses = cell.solve_all({LEFT: T_l, RIGHT: T_r}, q0=q)
    count = _count(cell.chain(LEFT), T_l) * _count(cell.chain(RIGHT), T_r)
    assert len(poses) == count > 1
    for spelling in ({LEFT: T_l, RIGHT: rel}, [armik.Pose(T_l, frame=LEFT), rel]):
        every = cell.solve_all(spelling, q0=q)
        assert len(every) == count and all(r.success for r in every)
        np.testing.assert_allclose(every[0].q, q, atol=1e-9)  # nearest q0 first
        for r in every:
            L, R = _placed(whole, cell, r.q)
            assert np.linalg.norm(pin.log6(T_l.actInv(L)).vector) < 1e-9
            assert np.linalg.norm(_relative_error(L, R, rel.pose.T)) < 1e-9
            assert min(np.abs(p.q - r.q).max() for p in poses) < 1e-7  # one of the poses'


def test_a_relative_region_is_measured_as_the_task_measures_it(cell, whole):
    """A relative pose free to spin about its z within 0.1 rad: every combination is
    within it on Pinocchio's FK, the left chain's every answer among them."""
    q = cell.random_q(np.random.default_rng(12))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    box = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r), bounds=(0, 0, 0, 0, 0, 0.1))
    every = cell.solve_all({LEFT: T_l, RIGHT: box}, q0=q)
    assert all(r.success for r in every)
    lefts = {tuple(np.round(cell.split(r.q)[LEFT], 6)) for r in every}
    assert len(lefts) == _count(cell.chain(LEFT), T_l) > 1
    for r in every:
        L, R = _placed(whole, cell, r.q)
        e = _relative_error(L, R, box.pose.T)
        assert np.abs(e[:5]).max() < 1e-6 and abs(e[5]) <= 0.1 + 1e-6


@pytest.mark.parametrize("flat", [False, True])
def test_a_position_of_the_reference_lists_the_combinations_at_one_sampled_orientation(
    cell, whole, flat
):
    """A position of the left tip (a point, or a flat list's ``Position``): its answers are
    a continuum; every combination of the chains' answers at one orientation (the chains
    solved first) is listed, the reason saying so, each at the position and holding the
    relative pose on Pinocchio's FK."""
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    p = T_l.translation
    every = cell.solve_all([armik.Position(p, frame=LEFT), rel] if flat else {LEFT: p, RIGHT: rel})
    assert len(every) > 1 and all(r.success for r in every)
    assert all("held at one orientation" in r.reason for r in every)
    L0, R0 = _placed(whole, cell, every[0].q)
    for r in every:
        L, R = _placed(whole, cell, r.q)
        assert np.linalg.norm(L.translation - p) < 1e-6
        assert np.allclose(L.rotation, L0.rotation, atol=1e-9)  # one orientation, sampled
        assert np.linalg.norm(_relative_error(L, R, rel.pose.T)) < 1e-6
    at = pin.SE3(L0.rotation, p)
    assert len(every) == _count(cell.chain(LEFT), at) * _count(cell.chain(RIGHT), at * rel.pose.T)


def test_a_reference_tip_left_out_keeps_q0s_values(cell, whole):
    """Only the relative tip given: the left chain keeps q0's values, the right chain's
    every answer at its placement listed; where none reaches from there, the one answer
    of the chains at once, its reason saying it is one."""
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    every = cell.solve_all({RIGHT: rel}, q0=q)
    assert len(every) == _count(cell.chain(RIGHT), T_r) > 1
    for r in every:
        assert r.success and np.array_equal(cell.split(r.q)[LEFT], cell.split(q)[LEFT])
        L, R = _placed(whole, cell, r.q)
        assert np.linalg.norm(_relative_error(L, R, rel.pose.T)) < 1e-9
    (one,) = cell.solve_all({RIGHT: rel})  # from mid-limits the right tip is out of reach
    assert one.success and "solve_all lists this one answer" in one.reason


def test_the_chains_solved_at_once_list_one_answer_and_say_so(cell):
    """Tips relative to each other in a cycle, chains that share joints: the task solver's
    one answer, its reason saying that solve_all lists one, not every solution."""
    q = cell.random_q(np.random.default_rng(5))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    cycle = {
        LEFT: [armik.Relative(LEFT, RIGHT, T_r.actInv(T_l))],
        RIGHT: [armik.Position(T_r.translation), armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))],
    }
    (one,) = cell.solve_all(cycle, q0=q)
    assert one.success and "in a cycle are solved together" in one.reason
    panda = armik.load("panda", tips=["panda_link4", "panda_hand"])
    qp = panda.random_q(np.random.default_rng(4))
    (shared,) = panda.solve_all({tip: panda.fk(qp, tip) for tip in panda.tips})
    assert shared.success and "chains that share joints are solved together" in shared.reason


def test_a_relative_target_ranks_its_combinations_by_prefer(cell):
    """A named score: the same combinations, best first by the robot's score; a cost of
    the whole configuration refused by name, as ``solve`` refuses it."""
    q = cell.random_q(np.random.default_rng(21))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    targets = {LEFT: T_l, RIGHT: armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))}
    plain = cell.solve_all(targets)
    ranked = cell.solve_all(targets, prefer="limits")
    assert len(ranked) == len(plain) > 1
    scores = [r.score for r in ranked]
    assert all(s is not None for s in scores) and scores == sorted(scores)
    with pytest.raises(armik.OptionError, match="not available on tips placed relative"):
        cell.solve_all(targets, prefer=lambda x: float(x[0] ** 2))


def test_a_reference_out_of_reach_is_one_failure_naming_it(cell):
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    far = pin.SE3(T_l.rotation, np.array([5.0, 0.0, 0.0]))
    (failed,) = cell.solve_all({LEFT: far, RIGHT: armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))})
    assert not failed.success and f"{LEFT}: unreachable" in failed.reason


def test_a_bad_target_is_named_by_its_tip_as_solve_names_it(cell):
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    for other in (T_r, armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))):
        for call in (cell.solve, cell.solve_all):
            with pytest.raises(armik.TargetError, match=f"the target of tip '{LEFT}'"):
                call({LEFT: [1.0, 2.0], RIGHT: other})  # a 2-vector on arms not planar


def test_a_position_reference_with_a_preference_lists_the_combinations_ranked(cell, whole):
    # the sample's solve ranked the left chain by the preference and landed on an
    # orientation the right chain cannot reach from: one "unreachable" where 8 answers exist
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    targets = {LEFT: T_l.translation, RIGHT: rel}
    plain = [r for r in cell.solve_all(targets) if r.success]
    ranked = cell.solve_all(targets, prefer="limits")
    assert len(ranked) == len(plain) > 1 and all(r.success for r in ranked)
    for r in ranked:
        L, R = _placed(whole, cell, r.q)
        assert np.linalg.norm(L.translation - T_l.translation) < 1e-6
        assert np.linalg.norm(_relative_error(L, R, rel.pose.T)) < 1e-6


def _free_references(T_l: pin.SE3):
    """(the left tip's target, options) that leave its placement free within a continuum:
    a region, a spin, an axis beside a position, in a cone, a look-at, an axis alone,
    bounds and weights given as options."""
    z = T_l.rotation[:, 2]
    return [
        (armik.Pose(T_l, bounds=(0.01, 0.01, 0.01, 0, 0, 0)), {}),
        (armik.Pose(T_l, bounds=(0, 0, 0, 0, 0, np.inf)), {}),
        (armik.Position(T_l.translation, bounds=(0.01,) * 3), {}),
        ([armik.Position(T_l.translation), armik.Axis((0, 0, 1), z)], {}),
        ([armik.Position(T_l.translation), armik.Axis((0, 0, 1), z, 0.1)], {}),
        ([armik.Position(T_l.translation), armik.LookAt(T_l.translation + 0.3 * z)], {}),
        (armik.Axis((0, 0, 1), z), {}),
        (T_l, {"bounds": (0, 0, 0, 0, 0, 0.2)}),
    ]


def test_a_reference_whose_target_leaves_its_placement_free_says_it_is_a_sample(cell, whole):
    """A region, a cone, an axis, a look-at of the left tip: every combination is listed at
    the placements the left chain's own answers found, one sample of the continuum the
    target allows, and each reason says so, as a position's says its orientation is one
    sample. They said nothing of it. Each holds the relative pose on Pinocchio's FK."""
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    for given, options in _free_references(T_l):
        every = cell.solve_all({LEFT: given, RIGHT: rel}, q0=q, **options)
        assert every and all(r.success for r in every), every[0].reason
        for r in every:
            assert "the target of ['l_tool0'] leaves its placement free" in r.reason, r.reason
            assert "a sample of that continuum" in r.reason
            L, R = _placed(whole, cell, r.q)
            e = _relative_error(L, R, rel.pose.T)  # (the options' spin bound every tip's)
            assert np.abs(e[:5]).max() < 1e-6 and abs(e[5]) <= (0.2 if options else 0) + 1e-6


def test_a_reference_held_exactly_says_no_sample(cell):
    """A full pose, as a target, a ``Pose`` task or with weights all non-zero: every
    combination there is, none a sample."""
    q = cell.random_q(np.random.default_rng(8))
    T_l, T_r = cell.fk(q, LEFT), cell.fk(q, RIGHT)
    rel = armik.Relative(RIGHT, LEFT, T_l.actInv(T_r))
    for given, options in [
        (T_l, {}),
        (armik.Pose(T_l), {}),
        (T_l, {"weights": (1, 1, 1, 2, 2, 2)}),
    ]:
        every = cell.solve_all({LEFT: given, RIGHT: rel}, q0=q, **options)
        assert every and all(r.success for r in every)
        assert not any("sample" in r.reason or "free" in r.reason for r in every), every[0].reason
