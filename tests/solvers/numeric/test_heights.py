"""A chain whose turning axes are all parallel (a planar arm, a SCARA) keeps the tip's
height along them but for its slides: a target beyond those heights is refused by the
numeric solvers at once as ``unreachable`` (``solvers/numeric/heights.py``); every height
reached stays solvable."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.options import Options
from armik.solvers.numeric import heights, orientations

from .test_orientations import SCARA

L = 'effort="1" velocity="1"'
# a SCARA on a lift without limits along its axes, and one whose quill a mimic follower
# doubles (turned upside down)
LIFT = f"""<robot name="lift"><link name="b"/><link name="l0"/><link name="l1"/><link name="l2"/>
<link name="l3"/><link name="l4"/>
<joint name="up" type="prismatic"><parent link="b"/><child link="l0"/><axis xyz="0 0 1"/>
  <limit lower="0" upper="1" {L}/></joint>
<joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/>
  <origin xyz="0 0 0.4"/><limit lower="-2.5" upper="2.5" {L}/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/>
  <origin xyz="0.35 0 0"/><limit lower="-2.5" upper="2.5" {L}/></joint>
<joint name="q1" type="prismatic"><parent link="l2"/><child link="l3"/><axis xyz="0 0 -1"/>
  <origin xyz="0.3 0 0" rpy="3.141592653589793 0 0"/><limit lower="0" upper="0.2" {L}/>
  </joint>
<joint name="q2" type="prismatic"><parent link="l3"/><child link="l4"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" {L}/><mimic joint="q1" multiplier="2" offset="0.05"/></joint>
</robot>"""


def _arms():
    lifted = armik.load_string(LIFT)
    return {
        "scara": armik.load("scara"),
        "planar_2link": armik.load("planar_2link"),
        "planar_3link": armik.load("planar_3link"),
        "quill doubled": lifted.with_locked({"up": 0.0}),
        "on a lift": lifted.with_limits({"up": (-np.inf, np.inf)}),
    }


def test_every_height_reached_is_within_and_the_ends_are_reached():
    """Random configurations' heights (Pinocchio's FK) lie within the heights, and the
    configurations with the slides at their limits reach both ends; a lift without limits
    along the axis reaches every height; axes not quite parallel have none."""
    rng = np.random.default_rng(0)
    for name, arm in _arms().items():
        h = heights.HEIGHTS(arm.kinematics)
        assert h is not None, name
        along = np.array(h.axis)
        got = [float(arm.fk(arm.random_q(rng)).translation @ along) for _ in range(300)]
        assert h.low - 1e-12 <= min(got) and max(got) <= h.high + 1e-12, name
        if name == "on a lift":
            assert (h.low, h.high) == (-np.inf, np.inf)
            continue
        slides = np.asarray(arm.kinematics.prismatic)
        ends = [
            float(arm.fk(np.where(slides, q, 0.0)).translation @ along)
            for q in (arm.kinematics.lower, arm.kinematics.upper)
        ]
        assert min(ends) == pytest.approx(h.low, abs=1e-12), name
        assert max(ends) == pytest.approx(h.high, abs=1e-12), name
    assert heights.HEIGHTS(armik.load_string(SCARA.replace("TILT", "1e-5")).kinematics) is None
    assert heights.HEIGHTS(armik.load("ur5").kinematics) is None


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_a_target_beyond_the_heights_is_unreachable_at_once(solver):
    """A pose and a position 0.3 m above or below every height: ``unreachable`` by
    ``solve`` (its prepared plan and the general path) and ``solve_batch``, the distance in
    the reason, no iteration, the seed returned; the same point within the heights solved
    (checked by Pinocchio's FK)."""
    rng = np.random.default_rng(1)
    for name, arm in _arms().items():
        h = heights.HEIGHTS(arm.kinematics)
        if name == "on a lift":
            continue
        q = arm.random_q(rng)
        T = arm.fk(q)
        step = np.array(h.axis) * (h.high - float(T.translation @ h.axis) + 0.3)
        if name == "scara":  # below: the quill's lowest end
            step = np.array(h.axis) * (h.low - float(T.translation @ h.axis) - 0.3)
        off = pin.SE3(T.rotation, T.translation + step)
        q0 = np.asarray(arm.middle, dtype=float)
        for target in (off, (off.translation.copy(), off.rotation.copy()), off.translation):
            r = arm.solve(target, solver=solver, q0=q0, seed=0)
            assert r.status == "unreachable" and r.iterations == 0, (name, r.reason)
            assert "0.3 m, along the axis its turning joints share" in r.reason, name
            np.testing.assert_array_equal(r.q, q0)
        ok = arm.solve(T, solver=solver, seed=0)
        assert ok.success, (name, ok.reason)
        assert np.linalg.norm(pin.log6(arm.fk(ok.q).actInv(T)).vector) < 1e-5
        b = arm.solve_batch([T, off, T], solver=solver, seed=0, workers=1, progress=False)
        assert b.success.tolist() == [True, False, True], name
        assert b.status[1] == "unreachable" and "along the axis" in b.reason(1)


def test_a_height_within_the_tolerance_is_not_refused():
    """At the heights' end plus most of ``tol_position``: not refused; beyond it, refused."""
    arm = armik.load("scara")
    h = heights.HEIGHTS(arm.kinematics)
    opts = Options()
    p = np.array([0.4, 0.1, h.high + 0.9 * opts.tol_position])
    assert heights.refused(arm.kinematics, p, opts) is None
    p[2] = h.high + 2 * opts.tol_position
    assert heights.refused(arm.kinematics, p, opts) is not None
    assert heights.refused(arm.kinematics, np.array([np.nan, 0.0, 1.0]), opts) is None


def test_axes_parallel_to_rounding_have_heights():
    """A SCARA whose second joint is turned by pi about x (``rpy="3.14159..."``) with its
    axis reversed, its axes parallel to 5e-16 rad: its heights hold every height reached,
    and a target 0.1 m above them is ``unreachable`` with no iteration."""
    flip = SCARA.replace('rpy="TILT 0 0"', 'rpy="3.141592653589793 0 0"')
    flip = flip.replace(
        '<child link="l2"/><axis xyz="0 0 1"/>', '<child link="l2"/><axis xyz="0 0 -1"/>'
    )
    arm = armik.load_string(flip)
    assert 0.0 < orientations.FAMILY(arm.kinematics).slack <= heights.SLACK
    h = heights.HEIGHTS(arm.kinematics)
    assert h is not None
    rng = np.random.default_rng(2)
    got = [float(arm.fk(arm.random_q(rng)).translation @ h.axis) for _ in range(300)]
    assert h.low <= min(got) and max(got) <= h.high
    T = arm.fk(arm.middle)
    target = T.translation + np.array(h.axis) * (h.high - float(T.translation @ h.axis) + 0.1)
    r = arm.solve(target, solver="dls", seed=0)
    assert r.status == "unreachable" and r.iterations == 0, r.reason
    assert "0.1 m, along the axis its turning joints share" in r.reason
