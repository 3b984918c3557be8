"""A target within what a structurally limited arm (a gantry, a SCARA, a planar arm) allows
passes cheap measures and is never measured exactly (``solvers/numeric/structure.py``); the
cheap measures never pass a target the exact ones refuse, and a batch refuses the rows a
loop of single solves refuses."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.options import Options
from armik.solvers.numeric import heights, orientations, slides, structure

from .test_long_rail import GANTRY as WRIST
from .test_orientations import GANTRY, SCARA
from .test_slides import SKEWED, XYZ


def _arms():
    return {
        "gantry": armik.load_string(GANTRY),
        "skewed gantry": armik.load_string(SKEWED),
        "rail": armik.load_string(XYZ).with_limits({"px": (-np.inf, np.inf)}),
        "scara": armik.load("scara"),
        "tilted scara": armik.load_string(SCARA.replace("TILT", "1e-5")),
        "planar": armik.load("planar_3link"),
        "gantry with a wrist": armik.load_string(WRIST.replace("RAIL", "10")),
    }


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_reachable_target_is_not_measured_exactly(monkeypatch, solver):
    """Poses and positions the arms reach, by ``solve`` (its prepared plan and the general
    path) and ``solve_batch``: solved, each checked by Pinocchio's FK, without a call of the
    exact measures."""

    def exact(*_):
        raise AssertionError("measured exactly")

    monkeypatch.setattr(orientations, "refused", exact)
    monkeypatch.setattr(slides, "refused", exact)
    monkeypatch.setattr(heights, "refused", exact)
    for name, arm in _arms().items():
        rng = np.random.default_rng(3)
        poses = [arm.fk(arm.random_q(rng)) for _ in range(4)]
        for T in poses:
            for target in (T, (T.translation.copy(), T.rotation.copy()), T.translation.copy()):
                r = arm.solve(target, solver=solver, seed=0)
                assert r.success, (name, r.reason)
                got = arm.fk(r.q)
                assert np.linalg.norm(got.translation - T.translation) < 1e-6, name
                if not isinstance(target, np.ndarray):
                    assert np.linalg.norm(pin.log3(got.rotation.T @ T.rotation)) < 1e-6, name
        b = arm.solve_batch(poses, solver=solver, seed=0, workers=1, progress=False)
        assert b.success.all(), name


def test_the_cheap_measures_never_pass_what_the_exact_ones_refuse():
    """Rotations tilted and positions moved by every scale around the tolerances, and
    heights from the ends of the reached ones to three tolerances beyond: where a cheap
    measure passes one, the exact one does not refuse it; the cheap ones pass every reached
    pose and fail a target well beyond."""
    opts = Options()
    rng = np.random.default_rng(0)
    for name, arm in _arms().items():
        kin = arm.kinematics
        family = orientations.FAMILY(kin)
        near = slides.NEAR(kin)
        above = heights.HEIGHTS(kin)
        poses = [arm.fk(arm.random_q(rng)) for _ in range(20)]
        R = np.array([T.rotation for T in poses])
        P = np.array([T.translation for T in poses])
        assert family is None or orientations.near(family, R, opts.tol_orientation).all()
        assert slides.near(kin, P, opts.tol_position).all(), name
        for T in poses:
            assert family is None or orientations.near_one(family, T.rotation, 1e-6), name
            assert near is None or slides.near_one(near, T.translation, opts.tol_position)
            for size in np.geomspace(1e-9, 1.0, 40):
                Rt = T.rotation @ pin.exp3(size * rng.normal(size=3))
                pt = T.translation + size * rng.normal(size=3)
                if family is not None:
                    passed = orientations.near(family, Rt[None], opts.tol_orientation)[0]
                    assert passed == orientations.near_one(family, Rt, opts.tol_orientation)
                    if passed:
                        assert orientations.refused(kin, Rt, opts) is None, (name, size)
                if near is not None:
                    placed = slides.near(kin, pt[None], opts.tol_position)[0]
                    assert placed == slides.near_one(near, pt, opts.tol_position)
                    if placed:
                        assert slides.refused(kin, pt, opts) is None, (name, size)
                if above is not None:
                    _heights_agree(kin, above, pt, opts, (name, size))
        if above is not None and np.isfinite([above.low, above.high]).all():
            tol, axis = opts.tol_position, np.array(above.axis)
            for f in 0.05 * np.arange(61) + 0.025:  # tolerances beyond, none at a bound
                for end, sign in ((above.high, 1.0), (above.low, -1.0)):
                    pt = P[0] + (end - float(P[0] @ axis) + sign * f * tol) * axis
                    passed = _heights_agree(kin, above, pt, opts, (name, f))
                    assert passed == (f < 0.5), (name, f)
                    assert (heights.refused(kin, pt, opts) is None) == (f < 1.0), (name, f)
        far = poses[0].rotation @ pin.exp3(np.array([0.5, 0.0, 0.0]))
        assert family is None or not orientations.near(family, far[None], 1e-6)[0], name
        if near is not None:
            assert not slides.near(kin, P[:1] + 10.0, opts.tol_position)[0], name


def _heights_agree(kin, above, pt, opts, what) -> bool:
    """Whether ``pt``'s height passes the cheap measure (``heights.near``, and ``beyond``'s
    plain floats agreeing), having checked that the exact one then does not refuse it."""
    passed = heights.near(kin, pt[None], opts.tol_position)[0]
    assert passed == (heights.height(above, pt) <= 0.5 * opts.tol_position), what
    if passed:
        assert heights.refused(kin, pt, opts) is None, what
    return bool(passed)


def test_a_batch_refuses_the_rows_single_solves_refuse():
    """Rows reached, tilted beyond the family and moved beyond a gantry's travel: the batch
    answers each row as ``solve`` does (status, and the reason of a refused one)."""
    for name, arm in _arms().items():
        rng = np.random.default_rng(5)
        family = orientations.FAMILY(arm.kinematics)
        axis = None if family is None else family.axis
        across = np.cross(np.array([1.0, 0.0, 0.0]) if axis is None else axis, [0.6, 0.0, 0.8])
        tilt = pin.exp3(0.3 * across / np.linalg.norm(across))  # off every family's axis
        gantry = slides.SLIDES(arm.kinematics) is not None
        refused = ([1, 4, 7] if family is not None else []) + ([2, 5, 8] if gantry else [])
        targets = []
        for k in range(9):
            T = arm.fk(arm.random_q(rng))
            if k % 3 == 1:
                T = pin.SE3(tilt @ T.rotation, T.translation)
            if k % 3 == 2 and gantry:
                T = pin.SE3(T.rotation, T.translation + np.array([0.0, 0.0, 3.0]))
            targets.append(T)
        b = arm.solve_batch(targets, solver="dls", seed=0, workers=1, progress=False)
        for k, T in enumerate(targets):
            r = arm.solve(T, solver="dls", seed=0)
            assert b.status[k] == r.status == ("unreachable" if k in refused else "converged")
            assert k not in refused or b.reason(k) == r.reason, (name, k)
        sf = np.zeros(32)  # no slack on the reach bound
        R = np.array([T.rotation for T in targets])
        P = np.array([T.translation for T in targets])
        got = structure.refusals(arm.kinematics, R, P, Options(), sf)
        one = [structure.beyond(arm.kinematics, R[k], P[k], Options(), sf) for k in range(9)]
        assert got == {k: why for k, why in enumerate(one) if why is not None}, name
        assert got and set(got) <= set(refused), name
