"""The one-dimensional search families (axes 2 and 3 parallel; axes 5 and 6 meeting):
classified, solved completely on random arms with random fixed transforms before joint 1
and after joint 6, near misses refused with their number, out-of-reach targets refused."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.model.random_arms import random_urdf
from armik.solvers.closed_form import two_intersecting, two_parallel
from armik.status import Status

from .random_arms import check_round_trips, load_arm, random_arm

FAMILIES = {"two_parallel": two_parallel, "two_intersecting": two_intersecting}


@pytest.mark.parametrize("kind", list(FAMILIES))
def test_random_arms_are_solved_completely(kind):
    rng = np.random.default_rng({"two_parallel": 31, "two_intersecting": 32}[kind])
    misses: list = []
    checked = 0
    for _ in range(4):
        a = load_arm(kind, rng)
        geo = FAMILIES[kind].classify(a.kinematics)
        assert not isinstance(geo, str), geo
        T = a.fk(a.random_q(rng))
        # auto takes the elimination for every solution, the search when asked for
        assert a.solve_all(T)[0].solver == "elimination_6r"
        assert a.solve_all(T, solver=kind)[0].solver == kind
        assert a.solve(T).solver == "dls"  # and the numeric solver for one answer
        checked += check_round_trips(a, kind, rng, 10, misses)
    # a search, not a closed form: a zero within 2^-17 of a grid step of a fold may be
    # missed (benchmarks/families_6r.py counts them); these seeds miss none
    assert checked >= 36 and not misses, misses


def test_the_search_over_q4_solves_the_ur_family_too():
    """The UR family's axes 5 and 6 meet: the search over q4 solves it; auto keeps its
    closed form."""
    rng = np.random.default_rng(33)
    a = load_arm("three_parallel", rng)
    assert a.solve(a.fk(a.random_q(rng))).solver == "three_parallel"
    assert check_round_trips(a, "two_intersecting", rng, 5) >= 4


def test_degenerate_layouts_are_left_to_their_closed_forms():
    """With a spherical wrist, or axis 4 parallel to axes 2 and 3, the search over q1 would
    meet a degenerate SP6: refused, naming the closed form that solves the arm."""
    rng = np.random.default_rng(39)
    why = two_parallel.classify(load_arm("parallel_23", rng).kinematics)
    assert isinstance(why, str) and "spherical_general solves" in why
    why = two_parallel.classify(load_arm("three_parallel_free", rng).kinematics)
    assert isinstance(why, str) and "three_parallel_general solves" in why


def test_up_to_sixteen_solutions_are_distinct_and_exact():
    rng = np.random.default_rng(34)
    a = load_arm("two_parallel", rng)
    for _ in range(5):
        T = a.fk(a.random_q(rng))
        rs = [r for r in a.solve_all(T, solver="two_parallel") if r.success]
        assert 1 <= len(rs) <= 16
        Q = np.array([r.q for r in rs])
        for i in range(len(Q)):
            for j in range(i):
                assert np.abs(np.angle(np.exp(1j * (Q[i] - Q[j])))).max() > 1e-6


def test_near_misses_are_refused_with_their_number():
    rng = np.random.default_rng(35)
    c, h = random_arm("two_parallel", rng)
    axis = np.cross(h[2], [0.0, 0.0, 1.0])
    h[2] = pin.exp3(3e-6 * axis / np.linalg.norm(axis)) @ h[2]
    a = load_arm("two_parallel", rng, c, h)
    why = two_parallel.classify(a.kinematics)
    assert isinstance(why, str) and "3e-06 rad apart (tolerance 1e-09 rad)" in why, why
    with pytest.raises(armik.SolverError, match="3e-06 rad apart"):
        a.solve(a.fk(np.zeros(6)), solver="two_parallel")

    c, h = random_arm("two_intersecting", rng)
    across = np.cross(h[4], h[5])
    c[5] = c[5] + 4e-7 * across / np.linalg.norm(across)  # axis 6 moved off axis 5
    a = load_arm("two_intersecting", rng, c, h)
    why = two_intersecting.classify(a.kinematics)
    # the measure: how far the point nearest both lines is from each, half their gap
    assert isinstance(why, str) and "miss by 2e-07 m (tolerance 1e-09 m)" in why, why


def test_other_families_are_refused():
    rng = np.random.default_rng(36)
    general = load_arm("general", rng)
    assert "axes 2 and 3 are not parallel" in two_parallel.classify(general.kinematics)
    assert "axes 5 and 6 do not meet" in two_intersecting.classify(general.kinematics)
    r = general.solve_all(general.fk(np.zeros(6)))[0]
    assert r.success and r.solver == "elimination_6r"  # what no family fits
    assert "7 joints" in two_parallel.classify(armik.load("panda").kinematics)


@pytest.mark.parametrize("kind", list(FAMILIES))
def test_out_of_reach_is_unreachable(kind):
    rng = np.random.default_rng(37)
    a = load_arm(kind, rng)
    far = pin.SE3(a.fk(a.random_q(rng)).rotation, np.array([50.0, 0.0, 0.0]))
    r = a.solve(far, solver=kind)
    # a search's miss is a proof only beyond the reach bound
    assert not r.success and r.status is Status.UNREACHABLE
    assert "beyond the arm's reach" in r.reason
    results = a.solve_all(far, solver=kind)
    assert len(results) == 1 and not results[0].success


@pytest.mark.parametrize("kind", list(FAMILIES))
def test_batch_equals_solve(kind):
    rng = np.random.default_rng(38)
    a = load_arm(kind, rng)
    poses = np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(4)])
    b = a.solve_batch(poses, solver=kind, workers=1, progress=False)
    for i, H in enumerate(poses):
        r = a.solve(H, solver=kind)
        assert b.success[i] == r.success
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)


def test_a_spherical_shoulder_is_refused_by_the_search_over_q4():
    """The Panda with joint 7 locked: axes 1, 2, 3 meet and axes 5, 6 meet, but SP5 has no
    shoulder offsets to work on; refused with the reason, auto takes the closed form
    (spherical_shoulder)."""
    a = armik.load("panda", locked={"panda_joint7": 0.3})
    why = two_intersecting.classify(a.kinematics)
    assert isinstance(why, str) and "spherical shoulder" in why, why
    r = a.solve_all(a.fk(a.middle))[0]
    assert r.success and r.solver == "spherical_shoulder"


def _replayed(kind: str, arm_index: int, config: int):
    """The arm and configuration ``benchmarks/families_6r.py`` (seed 0, 50 configurations an
    arm) draws at that position."""
    rng = np.random.default_rng(0)
    for a in range(arm_index + 1):
        arm = armik.load_string(random_urdf(kind, rng), base="world", tip="tool")
        arm.random_q(rng)  # the benchmark's warm-up target
        for c in range(50):
            q = arm.random_q(rng)
            if a == arm_index and c == config:
                return arm, q
    raise AssertionError("not reached")


@pytest.mark.parametrize(
    "kind, arm_index, config",
    [
        # two branches die and two are born between two samples (the counts stay equal),
        # and the zero lies next to those folds: found once rough intervals are halved
        ("two_parallel", 1, 0),
        # the zero lies 1e-8 rad from a fold, closer than the fold's bisection: found as
        # the fold's own point, polished
        ("two_intersecting", 9, 11),
    ],
)
def test_zeros_next_to_folds_are_found(kind, arm_index, config):
    arm, q = _replayed(kind, arm_index, config)
    results = arm.solve_all(arm.fk(q), solver=kind)
    found = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in results if r.success]
    assert min(found) < 1e-6, found


@pytest.mark.parametrize("kind", list(FAMILIES))
def test_solve_all_numbers_the_branch_labels_two_solutions_share(kind):
    arm, q = _replayed(kind, 0, 0)
    T = arm.fk(q)
    labels = [r.branch for r in arm.solve_all(T, solver=kind)]
    assert len(set(labels)) == len(labels) and any("#2" in b for b in labels), labels
    # the general path (a list seed is not plain) labels them alike
    general = arm.solve_all(T, q0=arm.middle.tolist(), solver=kind)
    assert [r.branch for r in general] == labels


NEAR_FOLDS = json.loads((Path(__file__).parent / "two_parallel_near_folds.json").read_text())


@pytest.mark.parametrize(
    "config",
    [
        # two branches born together, each followed to the same state at the next sample:
        # one's change of sign was missed until such an interval counted as rough
        "449",
        # a branch just born dips through zero and back between finer samples
        "433",
        # a dip narrower than the grid's parabola shows, between two samples: the midpoints
        "265",
        # a dip two samples wide, the branch dying at a fold after it: the probe between them
        "164",
    ],
)
def test_zeros_in_dips_next_to_folds_are_found(config):
    # a random two_parallel arm (armik compare's) on which the search missed these
    arm = armik.load_string(NEAR_FOLDS["urdf"], base="world", tip="tool")
    q = np.array(NEAR_FOLDS["configurations"][config])
    results = arm.solve_all(arm.fk(q), solver="two_parallel")
    found = [np.abs(np.angle(np.exp(1j * (r.q - q)))).max() for r in results if r.success]
    assert found and min(found) < 1e-6, found
