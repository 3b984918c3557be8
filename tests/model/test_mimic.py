"""Mimic joints on the chain: the mimicking joint follows its driver (q = multiplier x
q_driver + offset) in the arm's FK (Pinocchio's own mimic model, yourdfpy), the compiled FK
and Jacobian, the limits and the solves; mimic joints whose driver does not move are fixed;
a bad mimic is a clear error."""

from __future__ import annotations

import io
import math
import pickle

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import armik
from armik.errors import JointError, SolverError, URDFError
from armik.kernel import fk
from armik.options import Options
from armik.solvers import registry
from armik.solvers.closed_form import families
from armik.solvers.numeric import pieces
from armik.targets.pose import parse_target
from armik.tolerances import LIMIT_TOL

from ..conftest import TOL

LIM = '<limit lower="{lo}" upper="{hi}" effort="1" velocity="1"/>'


def joint(name, kind, parent, child, xyz, axis, lo=-2.0, hi=2.0, mimic="", rpy="0 0 0"):
    limit = "" if kind == "continuous" else LIM.format(lo=lo, hi=hi)
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}{mimic}</joint>'
    )


def mimic_tag(driver_name, multiplier, offset):
    return f'<mimic joint="{driver_name}" multiplier="{multiplier}" offset="{offset}"/>'


def five_joint_urdf(multiplier=-0.5, offset=0.2, extra="") -> str:
    """j1, j2 drive; j3 (revolute) mimics j2, j4 (prismatic) mimics j1; j5 drives."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "l3", "l4", "tip"))
    return (
        f'<robot name="mimicky">{links}'
        + joint("j1", "revolute", "base", "l1", "0 0 0.1", "0 0 1")
        + joint("j2", "revolute", "l1", "l2", "0 0 0.3", "0 1 0", rpy="0.1 0.2 0.3")
        + joint(
            "j3",
            "revolute",
            "l2",
            "l3",
            "0.3 0 0",
            "0 1 0",
            -1.0,
            1.0,
            mimic_tag("j2", multiplier, offset),
        )  # fmt: skip
        + joint(
            "j4", "prismatic", "l3", "l4", "0.2 0 0", "1 0 0", 0.0, 0.2, mimic_tag("j1", 0.05, 0.1)
        )  # fmt: skip
        + joint("j5", "revolute", "l4", "tip", "0.1 0 0.05", "1 0 0")
        + extra
        + "</robot>"
    )


FACTORS = [(-0.5, 0.2), (1.5, -0.1)]  # a negative multiplier and one above 1, offsets != 0


def mimic_values(a, q) -> dict[str, float]:
    """Every moving joint's value (rad or m) for the arm's joint values q."""
    cfg = dict(zip(a.joint_names, np.asarray(q, float).tolist()))
    for m in a.kinematics.mimics:
        cfg[m.name] = m.multiplier * cfg[m.driver] + m.offset
    return cfg


def pin_mimic_fk(xml: str, a, q) -> pin.SE3:
    """T_base_tip from Pinocchio's own mimic model of the whole URDF."""
    model = pin.buildModelFromXML(xml, mimic=True)
    data = model.createData()
    qp = pin.neutral(model)
    for name, v in zip(a.joint_names, q):
        qp[model.joints[model.getJointId(name)].idx_q] = v
    pin.framesForwardKinematics(model, data, qp)
    return data.oMf[model.getFrameId("tip", pin.BODY)]


def yourdfpy_fk(xml: str, cfg: dict[str, float]) -> pin.SE3:
    model = yourdfpy.URDF.load(
        io.StringIO(xml), load_meshes=False, build_collision_scene_graph=False
    )
    full = {j: 0.0 for j in model.actuated_joint_names}
    full.update({k: v for k, v in cfg.items() if k in full})
    model.update_cfg(full)
    return pin.SE3(model.get_transform(frame_to="tip", frame_from="base"))


def dist(A: pin.SE3, B: pin.SE3) -> float:
    return float(np.linalg.norm(pin.log6(A.inverse() * B).vector))


@pytest.fixture(scope="module", params=FACTORS, ids=["negative", "above-one"])
def case(request):
    xml = five_joint_urdf(*request.param)
    return xml, armik.load_string(xml)


def test_only_the_driving_joints_are_joints_of_the_arm(case):
    _, a = case
    assert a.joint_names == ["j1", "j2", "j5"] and a.dof == 3
    assert [m.name for m in a.kinematics.mimics] == ["j3", "j4"]
    assert a.random_q(0).shape == (3,)


def test_fk_agrees_with_pinocchio_mimic_model_and_yourdfpy(case, rng):
    xml, a = case
    Q = a.random_q(rng, 8)
    batch = a.fk_batch(Q)
    for i, q in enumerate(Q):
        T = a.fk(q)
        assert dist(T, pin_mimic_fk(xml, a, q)) < TOL["fk_exact"]
        if i < 3:  # yourdfpy rebuilds its scene graph per load: a few poses suffice
            assert dist(T, yourdfpy_fk(xml, mimic_values(a, q))) < TOL["fk_exact"]
        # the compiled FK of the kernel chain (physical joints, mimic map)
        np.testing.assert_allclose(batch[i], T.homogeneous, atol=1e-12)


def test_the_physical_chain_with_mimic_values_filled_in_is_the_same_arm(case, rng):
    """The model the kernel is read from (each mimic joint its own) at the mimic values."""
    _, a = case
    m = a.kinematics
    model = m.physical_model
    data = model.createData()
    for q in a.random_q(rng, 5):
        cfg = mimic_values(a, q)
        qp = np.array([cfg[model.names[j]] for j in range(1, model.njoints)])
        pin.framesForwardKinematics(model, data, qp)
        assert dist(a.fk(q), m.T_base_world * data.oMf[m.tip_frame_id]) < 1e-12


def kernel_jacobian(a, q) -> np.ndarray:
    pb = pieces.Problem.build(a.kinematics, parse_target(a.fk(q).homogeneous), q, Options())
    pieces.evaluate(pb, a.kinematics.to_pin(q))
    return pb.ws.J.copy()


def fd_jacobian(a, q, h=1e-6) -> np.ndarray:
    T0 = a.fk(q)
    cols = []
    for k in range(a.dof):
        dq = np.zeros(a.dof)
        dq[k] = h
        plus = pin.log6(T0.inverse() * a.fk(q + dq)).vector
        minus = pin.log6(T0.inverse() * a.fk(q - dq)).vector
        cols.append((plus - minus) / (2 * h))
    return np.array(cols).T


def test_compiled_jacobian_folds_the_mimic_columns(case, rng):
    _, a = case
    for q in a.random_q(rng, 5):
        J = kernel_jacobian(a, q)
        np.testing.assert_allclose(J, a.jacobian(q), atol=1e-12)  # Pinocchio's mimic Jacobian
        np.testing.assert_allclose(J, fd_jacobian(a, q), atol=1e-7)


def test_joint_frames_follow_the_mimic_model(case, rng):
    _, a = case
    m = a.kinematics
    H = np.empty((a.model.njoints, 4, 4))
    for q in a.random_q(rng, 5):
        fk.joint_frames(m.kernel_chain.flat, q, H)
        pin.forwardKinematics(a.model, m.data, m.to_pin(q))  # Pinocchio's mimic model
        for j in range(a.model.njoints):
            want = (m.T_base_world * m.data.oMi[j]).homogeneous
            np.testing.assert_allclose(H[j], want, rtol=0, atol=1e-12)


def mimic_limits_hold(a, q, xml_limits) -> bool:
    cfg = mimic_values(a, q)
    return all(
        lo - LIMIT_TOL * 2 <= cfg[name] <= hi + LIMIT_TOL * 2
        for name, (lo, hi) in xml_limits.items()
    )


def test_limits_are_enforced_through_the_driver(case):
    _, a = case
    (m3,) = [m for m in a.kinematics.mimics if m.name == "j3"]
    ends = sorted(((-1.0 - m3.offset) / m3.multiplier, (1.0 - m3.offset) / m3.multiplier))
    assert a.lower[1] == pytest.approx(max(-2.0, ends[0]))
    assert a.upper[1] == pytest.approx(min(2.0, ends[1]))
    # j4 (prismatic, [0, 0.2]) = 0.05 j1 + 0.1 keeps j1 within [-2, 2]: its own limits
    assert (a.lower[0], a.upper[0]) == pytest.approx((-2.0, 2.0))
    # with_limits narrows the driver, and the mimic joint's range still applies
    b = a.with_limits({"j2": (-3.0, 3.0)})
    assert (b.lower[1], b.upper[1]) == pytest.approx((max(-3.0, ends[0]), min(3.0, ends[1])))
    with pytest.raises(JointError, match="'j2'.*mimic joints 'j3'"):
        a.with_limits({"j2": (ends[1] + 0.1, ends[1] + 0.2)})


@pytest.mark.parametrize("solver", ["dls", "qp"])
def test_solves_round_trip_and_honour_the_mimic_limits(case, solver, rng):
    _, a = case
    limits = {"j3": (-1.0, 1.0), "j4": (0.0, 0.2)}
    solved = 0
    for _ in range(6):
        q = a.random_q(rng)
        assert mimic_limits_hold(a, q, limits)
        r = a.solve(a.fk(q), solver=solver, q0=a.random_q(rng))
        if r.success:
            solved += 1
            assert dist(a.fk(r.q), a.fk(q)) < 1e-5
            assert a.within_limits(r.q) and mimic_limits_hold(a, r.q, limits)
    assert solved >= 5


def test_solves_refuse_a_pose_the_mimic_limits_exclude(case):
    """A pose reached by a j2 outside the range j3's limits leave: never a success."""
    _, a = case
    q = np.array([0.3, a.upper[1] + 0.3, 0.2])  # beyond the narrowed range, within [-2, 2]
    if q[1] > 2.0:
        q[1] = a.lower[1] - 0.3
    assert q[1] >= -2.0 and not a.within_limits(q)
    T = a.fk(q)  # FK does not check limits
    for solver in ("dls", "qp"):
        r = a.solve(T, solver=solver, q0=a.middle)
        assert not r.success or a.within_limits(r.q)


def test_closed_forms_refuse_with_the_reason(case):
    _, a = case
    reasons = families.classify(a.kinematics)
    assert reasons and all("joint 'j3' mimics 'j2'" in str(v) for v in reasons.values())
    for name in ("planar2r", "spherical", "three_parallel", "swept"):
        why = registry.why_not(name, a.kinematics)
        assert why is not None and "mimics" in why
    with pytest.raises(SolverError, match="mimics"):
        a.solve(a.fk(a.middle), solver="spherical")
    assert a.solve(a.fk(a.middle)).solver in ("dls", "qp")


def test_a_planar_pair_with_a_mimic_is_not_planar2r():
    """j2 mimics j1 on a planar arm: 1 driving joint, planar2r refuses with the reason."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "tip"))
    xml = (
        f'<robot name="p">{links}'
        + joint("j1", "revolute", "base", "l1", "0 0 0", "0 0 1", -3, 3)
        + joint("j2", "revolute", "l1", "l2", "1 0 0", "0 0 1", -3, 3, mimic_tag("j1", 2, 0.1))
        + joint("tool", "fixed", "l2", "tip", "0.8 0 0", "1 0 0")
        + "</robot>"
    )
    a = armik.load_string(xml, tip="tip")
    assert a.dof == 1 and a.kinematics.plane is None
    assert "joint 'j2' mimics 'j1'" in registry.why_not("planar2r", a.kinematics)
    x = 0.4
    np.testing.assert_allclose(
        a.fk([x]).translation,
        [math.cos(x) + 0.8 * math.cos(3 * x + 0.1), math.sin(x) + 0.8 * math.sin(3 * x + 0.1), 0],
        atol=1e-12,
    )


def test_the_arm_pickles(case, rng):
    _, a = case
    b = pickle.loads(pickle.dumps(a))
    assert b.joint_names == a.joint_names and b.kinematics.mimics == a.kinematics.mimics
    np.testing.assert_array_equal(b.lower, a.lower)
    q = a.random_q(rng)
    np.testing.assert_array_equal(b.fk(q).homogeneous, a.fk(q).homogeneous)
    assert b.solve(a.fk(q), solver="dls").success


def branch_urdf(multiplier: float, offset: float) -> str:
    """j2 on the chain mimics jx, on a side branch off the chain."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "lx", "tip"))
    return (
        f'<robot name="b">{links}'
        + joint("j1", "revolute", "base", "l1", "0 0 0.1", "0 0 1")
        + joint("jx", "revolute", "l1", "lx", "0 0.1 0", "0 1 0")
        + joint(
            "j2",
            "revolute",
            "l1",
            "l2",
            "0 0 0.3",
            "0 1 0",
            -2,
            2,
            mimic_tag("jx", multiplier, offset),
        )  # fmt: skip
        + joint("j3", "revolute", "l2", "tip", "0.3 0 0", "1 0 0")
        + "</robot>"
    )


@pytest.mark.parametrize("locked", [{}, {"jx": 0.2}])
def test_a_mimic_whose_driver_is_off_the_chain_is_fixed(locked, rng):
    xml = branch_urdf(2.0, 0.3)
    a = armik.load_string(xml, tip="tip", locked=locked)
    assert a.joint_names == ["j1", "j3"] and not a.kinematics.mimics
    fixed = 2.0 * locked.get("jx", 0.0) + 0.3
    for q in a.random_q(rng, 2):
        cfg = {"j1": q[0], "j3": q[1], "j2": fixed, **locked}
        assert dist(a.fk(q), yourdfpy_fk(xml, cfg)) < TOL["fk_exact"]


def test_a_locked_driver_or_a_zero_multiplier_fixes_the_mimic(rng):
    xml = five_joint_urdf(-0.5, 0.2)
    a = armik.load_string(xml, locked={"j2": 0.4})
    assert a.joint_names == ["j1", "j5"] and [m.name for m in a.kinematics.mimics] == ["j4"]
    for q in a.random_q(rng, 2):
        cfg = {"j1": q[0], "j2": 0.4, "j3": -0.5 * 0.4 + 0.2, "j4": 0.05 * q[0] + 0.1, "j5": q[1]}
        assert dist(a.fk(q), yourdfpy_fk(xml, cfg)) < TOL["fk_exact"]
    zero = five_joint_urdf(0, 0.25)
    b = armik.load_string(zero)
    assert b.joint_names == ["j1", "j2", "j5"] and [m.name for m in b.kinematics.mimics] == ["j4"]
    q = b.random_q(rng)
    cfg = {"j1": q[0], "j2": q[1], "j3": 0.25, "j4": 0.05 * q[0] + 0.1, "j5": q[2]}
    assert dist(b.fk(q), yourdfpy_fk(zero, cfg)) < TOL["fk_exact"]


def test_a_locked_driver_that_holds_its_mimic_outside_its_limits_is_refused():
    # j3 = -0.5 j2 + 0.2 within [-1, 1]: j2 within [-1.6, 2.4]; -2 is within j2's own
    with pytest.raises(JointError, match=r"locking 'j2' at -2 holds its mimic joint 'j3' at 1.2"):
        armik.load_string(five_joint_urdf(-0.5, 0.2), locked={"j2": -2.0})
    assert armik.load_string(five_joint_urdf(-0.5, 0.2), locked={"j2": -1.5}).dof == 2
    # j2 = 2 jx + 0.3 within [-2, 2]: jx within [-1.15, 0.85], its own limits [-2, 2];
    # jx off the chain, j2 on it (tip) or off it too (l1)
    for tip in ("tip", "l1"):
        with pytest.raises(JointError, match=r"within \[-1.15, 0.85\], or lock 'j2' too"):
            armik.load_string(branch_urdf(2.0, 0.3), tip=tip, locked={"jx": 1.5})
        a = armik.load_string(branch_urdf(2.0, 0.3), tip=tip, locked={"jx": 1.5, "j2": 1.0})
        assert a.locked == {"jx": 1.5, "j2": 1.0}
        assert armik.load_string(branch_urdf(2.0, 0.3), tip=tip, locked={"jx": 0.8}).dof >= 1


def test_a_mimic_or_locked_joint_of_the_chain_is_named_as_such_where_a_joint_is_asked():
    # j3 = -0.5 j2 + 0.2 follows j2; each is on the chain, none is a joint of the arm
    a = armik.load_string(five_joint_urdf(-0.5, 0.2))
    with pytest.raises(JointError, match=r"'j3' mimics 'j2' on this arm's chain .*name 'j2'"):
        a.with_limits({"j3": (-1.0, 1.0)})
    b = armik.load_string(five_joint_urdf(-0.5, 0.2), locked={"j2": 0.4})
    with pytest.raises(JointError, match=r"'j2' is locked at 0.4 on this arm's chain"):
        b.with_limits({"j2": (-1.0, 1.0)})
    with pytest.raises(JointError, match=r"'j3' mimics 'j2', which does not move on this arm"):
        b.with_limits({"j3": (-1.0, 1.0)})
    with pytest.raises(JointError, match=r"'nope' is not on this arm's chain"):
        b.with_limits({"nope": (-1.0, 1.0)})


def test_the_mimic_joint_itself_can_be_locked():
    a = armik.load_string(five_joint_urdf(), locked={"j3": 0.1})
    assert a.joint_names == ["j1", "j2", "j5"] and [m.name for m in a.kinematics.mimics] == ["j4"]
    assert (a.lower[1], a.upper[1]) == (-2.0, 2.0)  # j3 no longer narrows j2


def test_bad_mimics_are_clear_errors():
    with pytest.raises(URDFError, match="'j3' on the chain mimics 'nope'.*not a moving joint"):
        armik.load_string(five_joint_urdf().replace('mimic joint="j2"', 'mimic joint="nope"'))
    mimic_of_mimic = five_joint_urdf().replace('mimic joint="j1"', 'mimic joint="j3"')
    with pytest.raises(URDFError, match="'j4' on the chain mimics 'j3', which itself mimics 'j2'"):
        armik.load_string(mimic_of_mimic)
    cycle = five_joint_urdf().replace('mimic joint="j2"', 'mimic joint="j4"')
    cycle = cycle.replace('mimic joint="j1"', 'mimic joint="j3"')
    with pytest.raises(URDFError, match="'j3' -> 'j4' -> 'j3' form a cycle"):
        armik.load_string(cycle)
    later = five_joint_urdf().replace('mimic joint="j2"', 'mimic joint="j5"')
    with pytest.raises(JointError, match="'j3' mimics 'j5', which comes after it"):
        armik.load_string(later)
    continuous = (
        five_joint_urdf()
        .replace(
            joint("j5", "revolute", "l4", "tip", "0.1 0 0.05", "1 0 0"),
            joint("j5", "continuous", "l4", "tip", "0.1 0 0.05", "1 0 0")
            + joint("jy", "revolute", "tip", "tip2", "0 0 0", "1 0 0", mimic=mimic_tag("j5", 1, 0)),
        )
        .replace('<link name="tip"/>', '<link name="tip"/><link name="tip2"/>')
    )
    with pytest.raises(JointError, match="the driver 'j5' is continuous"):
        armik.load_string(continuous, tip="tip2")
    narrow = five_joint_urdf(1.0, 5.0)  # j3 = j2 + 5 within [-1, 1]: j2 in [-6, -4]
    with pytest.raises(JointError, match="'j2'.*leave it no value"):
        armik.load_string(narrow)


def test_armik_info_lists_the_mimic_joints(capsys, tmp_path):
    from armik.tools.cli import main

    path = tmp_path / "mimicky.urdf"
    path.write_text(five_joint_urdf())
    assert main(["info", str(path), "--lock", "j1=0.5"]) == 0
    out = capsys.readouterr().out
    assert "mimic: j3 = -0.5 x j2 + 0.2" in out
    assert "mimic: j4 fixed at 0.125" in out  # 0.05 x 0.5 + 0.1
    assert "joint 'j3' mimics 'j2'" in out


def test_a_tip_offset_applies_to_a_mimic_chain(case, rng):
    xml, a = case
    b = armik.load_string(xml, tip_offset=(0.0, 0.05, 0.1))
    offset = pin.SE3(np.eye(3), np.array([0.0, 0.05, 0.1]))
    Q = b.random_q(rng, 3)
    batch = b.fk_batch(Q)
    for i, q in enumerate(Q):
        assert dist(b.fk(q), pin_mimic_fk(xml, b, q) * offset) < TOL["fk_exact"]
        np.testing.assert_allclose(batch[i], b.fk(q).homogeneous, atol=1e-12)
    assert b.solve(b.fk(Q[0]), solver="dls").success


def test_a_prismatic_mimic_of_a_prismatic_driver(rng):
    """Two fingers: jm = -1 x jp + 0.3, both prismatic in [0, 0.3] (jp kept in [0, 0.3])."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "l3", "tip"))
    xml = (
        f'<robot name="slides">{links}'
        + joint("j1", "revolute", "base", "l1", "0 0 0.1", "0 0 1")
        + joint("jp", "prismatic", "l1", "l2", "0.1 0 0", "1 0 0", 0.0, 0.3)
        + joint(
            "jm", "prismatic", "l2", "l3", "0 0 0.1", "0 0 1", 0.0, 0.25, mimic_tag("jp", -1.0, 0.3)
        )  # fmt: skip
        + joint("j3", "revolute", "l3", "tip", "0 0.1 0", "0 1 0")
        + "</robot>"
    )
    a = armik.load_string(xml)
    assert a.joint_names == ["j1", "jp", "j3"]
    assert (a.lower[1], a.upper[1]) == pytest.approx((0.05, 0.3))  # jm <= 0.25: jp >= 0.05
    Q = a.random_q(rng, 4)
    batch = a.fk_batch(Q)
    for i, q in enumerate(Q):
        assert dist(a.fk(q), pin_mimic_fk(xml, a, q)) < TOL["fk_exact"]
        np.testing.assert_allclose(batch[i], a.fk(q).homogeneous, atol=1e-12)
        np.testing.assert_allclose(kernel_jacobian(a, q), a.jacobian(q), atol=1e-12)
    assert dist(a.fk(Q[0]), yourdfpy_fk(xml, mimic_values(a, Q[0]))) < TOL["fk_exact"]
    r = a.solve(a.fk(Q[1]), solver="qp", q0=a.middle)
    assert r.success and mimic_limits_hold(a, r.q, {"jm": (0.0, 0.25)})


def test_the_stick_figure_draws_every_joint_of_a_mimic_chain(case, rng, tmp_path):
    """The view's skeleton has a point and an axis per physical joint, the mimic joints
    placed at their values (the physical chain's FK)."""
    from armik.view.stick import skeleton

    _, a = case
    q = a.random_q(rng)
    sk = skeleton(a.kinematics, q)
    model = a.kinematics.physical_model
    data = model.createData()
    cfg = mimic_values(a, q)
    pin.forwardKinematics(model, data, np.array([cfg[model.names[j]] for j in range(1, 6)]))
    origins = [(a.kinematics.T_base_world * data.oMi[j]).translation for j in range(1, 6)]
    np.testing.assert_allclose(sk.points[1:-1], origins, atol=1e-12)
    assert sk.axes.shape == (5, 3) and sk.prismatic.tolist() == [0, 0, 0, 1, 0]
    pytest.importorskip("matplotlib")
    assert armik.plot(a, q, tmp_path / "m.png").exists()


def test_a_mimic_driver_is_never_shifted_by_two_pi(rng):
    """2 pi is no period of a driver whose mimic turns by multiplier x 2 pi: neither
    ``nearest_equivalent`` nor the kernel's answers shift it (the pose would change)."""
    xml = (
        five_joint_urdf(-0.5, 0.2)
        .replace('lower="-1.0" upper="1.0"', 'lower="-4" upper="4"')
        .replace(
            '<axis xyz="0 1 0"/><limit lower="-2.0" upper="2.0"',
            '<axis xyz="0 1 0"/><limit lower="-6.2" upper="6.2"',
        )
    )
    a = armik.load_string(xml)
    assert (a.lower[1], a.upper[1]) == (-6.2, 6.2)
    q = np.array([0.3, -2.5, 0.2])
    ref = np.array([0.3, 2.5, 0.2])
    assert a.kinematics.nearest_equivalent(q, ref)[1] == -2.5
    plain = armik.load_string(xml.replace("<mimic", "<nomimic"))  # no mimic: j2 is shifted
    assert plain.kinematics.nearest_equivalent(q, ref)[1] == pytest.approx(-2.5 + 2 * math.pi)
    ok = 0
    for _ in range(6):
        q = a.random_q(rng)
        q0 = np.clip(q + np.array([0.0, 4.0 if q[1] < 0 else -4.0, 0.0]), a.lower, a.upper)
        for solver in ("dls", "qp"):
            r = a.solve(a.fk(q), solver=solver, q0=q0)
            ok += r.success
            if r.success:
                assert dist(a.fk(r.q), a.fk(q)) < 1e-5
    assert ok >= 8


def fingers_urdf() -> str:
    """A 2R arm with a gripper off the chain: f1 drives, f2 mimics it (2 f1 + 0.1)."""
    names = ("base", "l1", "tip", "g1", "g2")
    links = "".join(f'<link name="{n}"/>' for n in names)
    return (
        f'<robot name="g">{links}'
        + joint("j1", "revolute", "base", "l1", "0 0 0.1", "0 0 1")
        + joint("j2", "revolute", "l1", "tip", "0.3 0 0", "0 1 0")
        + joint("f1", "prismatic", "tip", "g1", "0 0.05 0", "0 1 0", 0.0, 0.04)
        + joint(
            "f2",
            "prismatic",
            "tip",
            "g2",
            "0 -0.05 0",
            "0 -1 0",
            0.0,
            0.2,
            mimic_tag("f1", 2.0, 0.1),
        )  # fmt: skip
        + "</robot>"
    )


@pytest.mark.parametrize("locked", [{"f1": 0.03}, {}])
def test_mimic_joints_off_the_chain_follow_their_locked_driver(locked, rng):
    # the gripper's links carry collision geometry: they must be where the URDF puts them
    xml = fingers_urdf()
    a = armik.load_string(xml, tip="tip", locked=locked)
    f1 = locked.get("f1", 0.0)
    cfg = {"f1": f1, "f2": 2.0 * f1 + 0.1}
    for q in a.random_q(rng, 3):
        pin.framesForwardKinematics(a.model, a.kinematics.data, a.kinematics.to_pin(q))
        reader = yourdfpy.URDF.load(
            io.StringIO(xml), load_meshes=False, build_collision_scene_graph=False
        )
        reader.update_cfg({"j1": q[0], "j2": q[1], "f1": f1})  # yourdfpy follows the mimics
        for link in ("g1", "g2"):
            mine = a.kinematics.data.oMf[a.model.getFrameId(link)]
            theirs = pin.SE3(reader.get_transform(frame_to=link, frame_from="base"))
            assert dist(mine, theirs) < TOL["fk_exact"], link
    chain = a.kinematics.chain
    values = {n: chain.q_ref[chain.full.idx_qs[chain.full.getJointId(n)]] for n in cfg}
    assert values == pytest.approx(cfg)


def test_a_mimic_joint_locked_by_name_keeps_its_own_value():
    a = armik.load_string(fingers_urdf(), tip="tip", locked={"f1": 0.03, "f2": 0.05})
    full = a.kinematics.chain.full
    assert a.kinematics.chain.q_ref[full.idx_qs[full.getJointId("f2")]] == 0.05


def test_the_pandas_second_finger_follows_the_first():
    a = armik.load("panda", locked={"panda_finger_joint1": 0.03})
    full = a.kinematics.chain.full
    assert a.kinematics.chain.q_ref[full.idx_qs[full.getJointId("panda_finger_joint2")]] == 0.03


def wheel_urdf() -> str:
    """A continuous 'wheel' (no limits) drives a prismatic slide on the chain to 'tip' and
    another, 'side', off it: q_slide = 0.5 q_wheel + 0.1."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "w", "l1", "tip", "s"))
    slide = mimic_tag("wheel", 0.5, 0.1)
    return (
        f'<robot name="wheely">{links}'
        + joint("wheel", "continuous", "base", "w", "0 0 0.1", "0 0 1")
        + joint("j1", "revolute", "base", "l1", "0 0 0.2", "0 0 1")
        + joint("slide", "prismatic", "l1", "tip", "0.1 0 0", "1 0 0", -10, 10, slide)
        + joint("side", "prismatic", "base", "s", "0 0.1 0", "0 1 0", -10, 10, slide)
        + "</robot>"
    )


@pytest.mark.parametrize("angle", [4.0, -4.0, 7.5])
def test_a_continuous_driver_locked_past_pi_moves_its_mimics_by_the_value_as_given(angle, rng):
    # Pinocchio holds the wheel as (cos, sin): read back, 4 rad is 4 - 2 pi, and the slides
    # were put 0.5 x 2 pi = 3.14 m from where robot_state_publisher and yourdfpy put them
    xml = wheel_urdf()
    a = armik.load_string(xml, tip="tip", locked={"wheel": angle})
    assert a.joint_names == ["j1"] and a.kinematics.chain.fixed_mimics == {
        "slide": pytest.approx(0.5 * angle + 0.1)
    }
    reader = yourdfpy.URDF.load(
        io.StringIO(xml), load_meshes=False, build_collision_scene_graph=False
    )
    for q in a.random_q(rng, 3):
        reader.update_cfg({"wheel": angle, "j1": q[0]})
        for link in ("tip", "s"):
            theirs = pin.SE3(reader.get_transform(frame_to=link, frame_from="base"))
            assert dist(a.fk(q, frame=link), theirs) < TOL["fk_exact"], link


def test_a_driver_named_universe_drives_its_mimic_joint(rng):
    # Pinocchio's joint 0 is "universe": looked up by name, the driver was taken for it,
    # and the mimic joint was fixed at 0.5 x 0 (the arm's FK 0.16 rad off the robot)
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "tip"))
    half = mimic_tag("universe", 0.5, 0)
    xml = (
        f'<robot name="named">{links}'
        + joint("universe", "revolute", "base", "l1", "0 0 0.1", "0 0 1")
        + joint("j2", "revolute", "l1", "l2", "0.3 0 0", "0 0 1", mimic=half)
        + joint("j3", "revolute", "l2", "tip", "0.3 0 0", "0 0 1")
        + "</robot>"
    )  # fmt: skip
    a = armik.load_string(xml)
    assert a.joint_names == ["universe", "j3"]
    assert [(m.name, m.driver) for m in a.kinematics.mimics] == [("j2", "universe")]
    for q in a.random_q(rng, 3):
        assert dist(a.fk(q), yourdfpy_fk(xml, mimic_values(a, q))) < TOL["fk_exact"]
