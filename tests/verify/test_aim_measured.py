"""A target's aim is measured whatever else is: a position target with ``cone=`` and
``look_at=`` or ``toward=`` keeps no rotation, and its verdict measured the position alone,
so an answer whose tip axis pointed anywhere was a success. The verdict measures the angle
of the tip's axis outside its cone (``verify.region``) on every route; an answer outside
it is refused, its reason naming the angle and the cone; ``orientation_error`` reports the
axis' angle to its direction."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import armik
from armik.solve.read import read, read_batch
from armik.status import Status
from armik.verify.measure import measure, measure_batch, measure_many
from tests.conftest import arm as bundled

WITHIN = 0.1  # rad


def _opposite(a: armik.Arm, seed: int):
    """(q, its tip position, the direction opposite its tip's z axis): q reaches the
    position with the axis pi from that direction."""
    q = a.random_q(np.random.default_rng(seed))
    T = a.fk(q)
    return q, T.translation.copy(), -T.rotation[:, 2]


def _aims(p: np.ndarray, away: np.ndarray) -> list[dict]:
    """The keyword aims that q (axis along -away at p) violates by pi - WITHIN."""
    return [
        {"cone": (0, 0, 1, WITHIN), "toward": tuple(away)},
        {"cone": (0, 0, 1, WITHIN), "look_at": tuple(p + 0.4 * away)},
    ]


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_an_aim_on_a_position_target_is_measured(name):
    """``measure``, ``measure_many`` and ``measure_batch``: the axis' angle outside its
    cone, not None, and the pose refused; the words name the angle and the cone."""
    a = bundled(name)
    q, p, away = _opposite(a, 1)
    for aim in _aims(p, away):
        req = read(a.kinematics, p, None, "auto", aim)
        assert req.target.rotation is None and req.target.aim is not None
        m = measure(a.kinematics, q, req.target, req.opts)
        assert m.position_error <= 1e-9
        assert m.orientation_error == pytest.approx(math.pi - WITHIN, abs=1e-9)
        assert not m.pose_ok and not m.ok
        said = m.describe()
        sight = "the line to the point" if "look_at" in aim else "its direction"
        assert "outside the region" in said and f"3.14 rad from {sight}" in said
        assert "outside its cone of 0.1 rad" in said
        many = measure_many(a.kinematics, [q, q], req.target, req.opts)
        np.testing.assert_allclose(many.orientation_error, math.pi - WITHIN, atol=1e-9)
        assert not many.ok.any()
        batch = read_batch(a.kinematics, [p, p], None, "auto", aim).target
        b = measure_batch(a.kinematics, np.array([q, q]), batch, req.opts)
        np.testing.assert_allclose(b.orientation_error, math.pi - WITHIN, atol=1e-9)
        assert not b.pose_ok.any()


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_an_answer_outside_the_aim_is_refused_on_every_route(name, aimless):
    """The seed reaches the position with its axis pi from the aim: ``solve``,
    ``solve_all``, ``solve_batch`` and ``solve_path`` refuse it, naming the angle and the
    cone, and report the axis' angle to its direction as ``orientation_error``."""
    a = bundled(name)
    q, p, away = _opposite(a, 2)
    for aim in _aims(p, away):
        r = a.solve(p, q0=q, solver="aimless", **aim)
        assert not r.success and r.status is Status.NOT_CONVERGED, r.reason
        sight = "the line to the point" if "look_at" in aim else "its direction"
        assert f"3.14 rad from {sight}, outside its cone of 0.1 rad" in r.reason
        assert r.orientation_error == pytest.approx(math.pi, abs=1e-9)
        assert r.measured[1] == pytest.approx(math.pi - WITHIN, abs=1e-9)
        (every,) = a.solve_all(p, q0=q, solver="aimless", **aim)
        assert not every.success and every.orientation_error == pytest.approx(math.pi, abs=1e-9)
        b = a.solve_batch([p, p], q0=q, solver="aimless", workers=1, progress=False, **aim)
        assert not b.success.any() and "outside its cone of 0.1 rad" in b.reason(1)
        np.testing.assert_allclose(b.orientation_error, math.pi, atol=1e-9)
        path = a.solve_path([p, p], q, solver="aimless", **aim)
        assert not path.success.any() and "outside its cone" in path.reason(0)
        np.testing.assert_allclose(path.orientation_error, math.pi, atol=1e-9)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_a_success_says_it_is_inside_the_region_and_the_cone(name):
    """A verified answer's words say what held (inside the region, the axis within its
    cone), and ``orientation_error`` is the axis' angle to its direction, within it."""
    a = bundled(name)
    q, p, away = _opposite(a, 3)
    for aim in _aims(p, -away):  # the axis q has: inside the cone at once
        for r in (a.solve(p, q0=q, **aim), a.solve_all(p, q0=q, **aim)[0]):
            assert r.success, r.reason
            assert "inside the region" in r.reason and "outside the region" not in r.reason
            assert "the tip's axis within its cone of 0.1 rad" in r.reason
            axis = a.fk(r.q).rotation[:, 2]
            sight = -away if "toward" in aim else aim["look_at"] - a.fk(r.q).translation
            sight = sight / np.linalg.norm(sight)
            angle = math.atan2(np.linalg.norm(np.cross(axis, sight)), axis @ sight)
            assert r.orientation_error == pytest.approx(angle, abs=1e-9)
            assert r.orientation_error <= WITHIN + 1e-6
        b = a.solve_batch([p, p], q0=q, workers=1, progress=False, **aim)
        assert b.success.all() and "inside the region" in b.reason(0)


@pytest.mark.parametrize("bounds", [None, (0.01,) * 3 + (0.0,) * 3])
def test_a_batch_row_with_an_aim_says_what_solve_says(tmp_path, bounds):
    """A batch success with an aim names its cone as ``solve`` does for the same answer
    ("the tip's axis within its cone of 0.1 rad", ``reasons.region``), where it said
    "orientation error 0 rad"; so does a path's, and the batch saved and loaded. A file
    saved before the cone was kept loads, its successes naming no cone as they did."""
    panda = bundled("panda")
    rng = np.random.default_rng(2)
    poses = [panda.fk(panda.random_q(rng)) for _ in range(4)]
    options = {"cone": (0.0, 0.0, 1.0, WITHIN), "solver": "dls"}
    if bounds is not None:
        options["bounds"] = bounds
    batch = panda.solve_batch(poses, q0=panda.middle, progress=False, **options)
    back = armik.BatchResult.load(batch.save(tmp_path / "b.npz"))
    for i, T in enumerate(poses):
        r = panda.solve(T, q0=panda.middle, **options)
        assert r.success and f"within its cone of {WITHIN:g} rad" in r.reason
        assert batch.reason(i) == back.reason(i) == batch[i].reason == r.reason
    path = panda.solve_path(poses[:1], q0=batch.q[0], **options)
    assert path.success[0] and f"within its cone of {WITHIN:g} rad" in path.reason(0)
    with np.load(tmp_path / "b.npz") as z:  # as a file written before the cone was kept
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays.pop("meta")))
    del meta["cone"]
    np.savez(tmp_path / "old.npz", **arrays, meta=np.array(json.dumps(meta)))
    old = armik.BatchResult.load(tmp_path / "old.npz")
    assert old.cone is None and "orientation error" in old.reason(0)
    np.testing.assert_array_equal(old.q, batch.q)
