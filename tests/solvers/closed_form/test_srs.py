"""SRS 7R arms (solvers/closed_form/srs.py): every branch at one elbow swivel angle, each
verified by Pinocchio FK, the configuration that made the target among them."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers import registry
from armik.solvers.closed_form import families, srs, srs_kernel

from ...conftest import arm, model


def _same_angles(a, b, tol=1e-6) -> bool:
    d = np.asarray(a) - np.asarray(b)
    return bool(np.all(np.abs(np.arctan2(np.sin(d), np.cos(d))) < tol))


def _pose_error(a: armik.Arm, q, T) -> float:
    """|log6(fk(q)^-1 T)|, Pinocchio's FK computed here."""
    return float(np.linalg.norm(pin.log6(a.fk(q).inverse() * T).vector))


def random_srs_urdf(rng: np.random.Generator) -> str:
    """A 7R arm with random axes, none orthogonal to the next, axes 1-3 meeting in one
    point, 5-7 in another, and an elbow off the line between them: SRS, not an iiwa."""

    def unit():
        v = rng.normal(size=3)
        return v / np.linalg.norm(v)

    offsets = [
        (0, 0, 0.3),
        (0, 0, 0),
        (0, 0, 0),
        tuple(rng.uniform(-0.08, 0.08, 2)) + (0.4,),
        tuple(rng.uniform(-0.08, 0.08, 2)) + (0.35,),
        (0, 0, 0),
        (0, 0, 0),
    ]
    joints = []
    for i, xyz in enumerate(offsets):
        ax = " ".join(f"{x:.17g}" for x in unit())
        pos = " ".join(f"{x:.17g}" for x in xyz)
        joints.append(
            f'<joint name="j{i + 1}" type="revolute"><parent link="l{i}"/>'
            f'<child link="l{i + 1}"/><origin xyz="{pos}"/><axis xyz="{ax}"/>'
            f'<limit lower="-3.1" upper="3.1" effort="1" velocity="1"/></joint>'
        )
    links = "".join(f'<link name="l{i}"/>' for i in range(8))
    tool = (
        '<link name="tool"/><joint name="t" type="fixed"><parent link="l7"/>'
        '<child link="tool"/><origin xyz="0.02 0.03 0.1" rpy="0.3 -0.2 0.5"/></joint>'
    )
    return f'<robot name="srs">{links}{tool}{"".join(joints)}</robot>'


def test_which_arms_are_srs():
    geo = srs.classify(model("kuka_iiwa14"))
    assert isinstance(geo, srs.Srs)
    assert np.allclose(geo.shoulder, [0, 0, 0.36]) and np.allclose(geo.wrist, [0, 0, 1.18])
    assert "0.42 m from the shoulder and 0.4 m from the wrist" in geo.description
    assert "axes 5, 6, 7 do not meet" in srs.applies(model("panda"))  # its flange offset
    assert "needs 7" in srs.applies(model("ur5"))
    assert "do not meet" in srs.applies(model("xarm7"))
    assert isinstance(families.classify(model("kuka_iiwa14"))["srs"], srs.Srs)  # armik info
    T = arm("kuka_iiwa14").fk(np.full(7, 0.3))
    assert registry.choose("auto", model("kuka_iiwa14"), None).name == "srs"
    assert arm("kuka_iiwa14").solve(T).solver == "srs"
    assert "closed form needs a full pose" in srs.applies(model("kuka_iiwa14"), _position(T))


def _position(T):
    from armik.targets.pose import parsed

    return parsed(T.translation, model("kuka_iiwa14"))


def test_a_wrist_offset_of_a_millimetre_is_refused_with_its_size(tmp_path):
    text = (armik.model.catalogue.entry("kuka_iiwa14").urdf_path()).read_text()
    moved = text.replace('<origin xyz="0 0.081 0"', '<origin xyz="0.001 0.081 0"')
    assert moved != text
    path = tmp_path / "iiwa_offset.urdf"
    path.write_text(moved)
    why = srs.applies(armik.load(str(path)).kinematics)
    assert "axes 5, 6, 7 do not meet" in why and "miss by 0.000667 m" in why  # 2/3 of 1 mm


def test_every_branch_at_the_swivel_angle_and_the_generating_configuration_among_them():
    """200 seeded random iiwa configurations: at each one's swivel angle, every branch is
    verified (an FK computed here agrees), keeps that angle, and the configuration that
    made the target is one of them, on every target."""
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(53)
    found = eight = 0
    for _ in range(200):
        q = a.random_q(rng)
        T = a.fk(q)
        psi = srs.swivel_of(a.kinematics, q)
        results = a.solve_all(T, swivel=psi)
        assert 1 <= len(results) <= 8
        eight += len(results) == 8
        for r in results:
            assert r.solver == "srs"
            assert _pose_error(a, r.q, T) < 1e-9  # every branch reaches the target
            assert _same_angles(srs.swivel_of(a.kinematics, r.q), psi, 1e-9)
            assert r.success == a.within_limits(r.q)  # a failure only by the limits
        found += any(_same_angles(r.q, q) for r in results)
    assert found == 200
    assert eight == 200  # no random target sits on a singular configuration


def test_a_random_srs_arm_not_an_iiwa():
    rng = np.random.default_rng(7)
    for _ in range(3):
        a = armik.load_string(random_srs_urdf(rng), base="l0", tip="tool")
        assert isinstance(srs.classify(a.kinematics), srs.Srs)
        for _ in range(20):
            q = a.random_q(rng)
            T = a.fk(q)
            results = a.solve_all(T, swivel=srs.swivel_of(a.kinematics, q))
            assert any(_same_angles(r.q, q) for r in results)
            assert all(_pose_error(a, r.q, T) < 1e-9 for r in results if r.success)


def test_the_compiled_elbow_and_wrist_agree_with_pinocchio():
    """``srs_kernel.elbow_wrist`` (the points the swivel angle is read from) against
    Pinocchio's joint placements: each point carried by the joint it rides on."""
    for a in (arm("kuka_iiwa14"), armik.load_string(random_srs_urdf(np.random.default_rng(3)))):
        m = a.kinematics
        geo = srs.geometry(m)
        rng = np.random.default_rng(11)
        data = m.model.createData()
        pin.forwardKinematics(m.model, data, pin.neutral(m.model))
        zero = [data.oMi[i].copy() for i in range(m.model.njoints)]
        for _ in range(50):
            q = a.random_q(rng)
            pin.forwardKinematics(m.model, data, q)
            E, W = srs_kernel.elbow_wrist(geo.geo, q)
            E_pin = data.oMi[4] * (zero[4].inverse() * geo.elbow)
            W_pin = data.oMi[7] * (zero[7].inverse() * geo.wrist)
            assert np.abs(np.array(E) - E_pin).max() < 1e-12
            assert np.abs(np.array(W) - W_pin).max() < 1e-12


def test_solve_from_the_generating_configuration_returns_it():
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(5)
    for _ in range(30):
        q = a.random_q(rng)
        r = a.solve(a.fk(q), q0=q)
        assert r.success and r.solver == "srs"
        assert _same_angles(r.q, q, 1e-9)


def test_a_stretched_elbow_keeps_the_shoulder_roll_nearest_q0():
    # the elbow on the line S-W (joint 4 at 0): the swivel angle moves nothing and the
    # shoulder's roll about the line is free; it is q0's, so the configuration comes back
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(8)
    for _ in range(6):
        q = a.random_q(rng)
        q[0] = q[3] = 0.0
        T = a.fk(q)
        psi = srs.swivel_of(a.kinematics, q)
        every = a.solve_all(T, swivel=psi, q0=q)
        assert any(r.success and np.abs(r.q - q).max() < 1e-9 for r in every)
        assert all(r.singular for r in every)
        r = a.solve(T, q0=q)
        assert r.success and r.solver == "srs" and np.abs(r.q - q).max() < 1e-9
        # from the middle: within the limits, where the roll the swivel angle gave was not
        good = [r for r in a.solve_all(T, swivel=psi) if r.success]
        assert good and all(_pose_error(a, r.q, T) < 1e-9 for r in good)


def test_solve_from_the_middle_finds_an_answer_within_the_limits():
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(6)
    for _ in range(40):
        T = a.fk(a.random_q(rng))
        r = a.solve(T)
        assert r.success and a.within_limits(r.q) and _pose_error(a, r.q, T) < 1e-9


def test_out_of_reach_is_a_proof_naming_the_span():
    a = arm("kuka_iiwa14")
    for swivel in ({}, {"swivel": 0.1}):
        r = a.solve(pin.SE3(np.eye(3), np.array([1.2, 0.0, 0.5])), **swivel)
        assert not r.success and r.status == armik.Status.UNREACHABLE and r.solver == "srs"
        assert "shoulder to wrist span is" in r.reason


def test_an_elbow_beyond_its_limits_at_every_swivel_angle_is_a_proof():
    a = arm("kuka_iiwa14")
    T = pin.SE3(np.eye(3), np.array([0.2, 0.1, 0.2]))  # the wrist 0.36 m from the shoulder
    r = a.solve(T)
    assert not r.success and r.status == armik.Status.UNREACHABLE and r.solver == "srs"
    assert "the elbow (iiwa_joint_4) must turn to" in r.reason
    assert abs(r.q[3]) > a.upper[3] and _pose_error(a, r.q, T) < 1e-9  # exact, beyond


def test_a_held_joint_gives_every_branch_at_its_value():
    a = arm("kuka_iiwa14")
    rng = np.random.default_rng(9)
    q = a.random_q(rng)
    T = a.fk(q)
    for joint, k, solver in (("iiwa_joint_3", 2, "spherical"), ("iiwa_joint_7", 6, "swept")):
        results = a.solve_all(T, hold={joint: float(q[k])})
        assert results[0].solver == solver  # a closed form either way
        assert any(_same_angles(r.q, q) for r in results)
        assert all(r.q[k] == q[k] and _pose_error(a, r.q, T) < 1e-9 for r in results if r.success)


@pytest.mark.parametrize(
    "q",
    [
        [0.5177, 1.9569, -1.87, 1.9376, -2.2664, 2.0944, 3.0543],
        [-1.2448, 2.0944, 1.8291, -2.0944, -1.4691, -1.1036, -1.6708],
        [-0.0556, 1.1511, -2.9671, 2.0944, -0.3301, -1.3254, -0.5914],
    ],
)
def test_the_held_elbow_frees_joint_3_within_the_limits(q):
    # joint 4 held: the span from the shoulder to the wrist is fixed and joint 3 turns the
    # wrist round it, free; at q0's value it broke a limit, at another it does not
    a = arm("kuka_iiwa14")
    q = np.clip(np.array(q), a.lower, a.upper)
    T = a.fk(q)
    good = [r for r in a.solve_all(T, hold={"iiwa_joint_4": float(q[3])}) if r.success]
    assert good and all(r.singular and r.q[3] == q[3] for r in good)
    assert all(a.within_limits(r.q) and _pose_error(a, r.q, T) < 1e-9 for r in good)
    r = a.solve(T, hold={"iiwa_joint_4": float(q[3])})
    assert r.success and r.q[2] != a.middle[2]


@pytest.mark.parametrize(
    "options, words",
    [
        ({"swivel": "up"}, "swivel must be a number"),
        ({"swivel": float("nan")}, "swivel must be finite"),
        ({"swivel": 0.1, "hold": {"iiwa_joint_3": 0.2}}, "each fix the self-motion"),
        ({"swivel": 0.1, "solver": "dls"}, "leave solver='auto'"),
        ({"swivel": 0.1, "bounds": (0, 0, 0, 0, 0, 1)}, "rotation component are for the numeric"),
    ],
)
def test_bad_swivel_options_are_clear_errors(options, words):
    a = arm("kuka_iiwa14")
    with pytest.raises(armik.OptionError, match=words):
        a.solve_all(a.fk(np.full(7, 0.2)), **options)


def test_swivel_on_other_arms_is_refused_and_a_batch_takes_it():
    p = arm("panda")
    with pytest.raises(
        armik.OptionError,
        match=r"elbow swivel angle .*applies to arm .panda. \(srs: axes 5, 6, 7 do not meet",
    ):
        p.solve(p.fk(p.middle), swivel=0.2)
    a = arm("kuka_iiwa14")
    # a batch takes it: each row at that swivel angle (tests/solve/test_batch_swivel.py)
    batch = a.solve_batch(np.array([a.fk(np.full(7, 0.2)).homogeneous]), swivel=0.2, workers=1)
    assert batch.success.all()
    assert _same_angles(srs.swivel_of(a.kinematics, batch.q[0]), 0.2, 1e-9)
    with pytest.raises(armik.OptionError, match="full pose"):
        a.solve(a.fk(np.full(7, 0.2)).translation, swivel=0.2)


def _through_zero(a: armik.Arm, seed: int, joint: int, n: int = 41) -> np.ndarray:
    """A straight joint path from ``a.random_q(seed)`` with ``joint`` going 0.2 -> -0.2 rad,
    passing exactly through 0 at its middle row."""
    Q = np.repeat(a.random_q(seed)[None], n, 0)
    Q[:, joint] = np.linspace(0.2, -0.2, n)
    return Q


@pytest.mark.parametrize("seed", range(6))
def test_from_a_stretched_elbow_the_answer_is_next_to_q0(seed):
    """q0 with the elbow exactly stretched (joint 4 at 0) has no swivel angle of its own
    (the elbow on the line S-W); a target just past it is answered next to q0, on the side
    the elbow bends to, not at a swivel angle of 0 a turn of joints away (2.7 rad before)."""
    a = arm("kuka_iiwa14")
    Q = _through_zero(a, seed, 3)
    assert Q[20, 3] == 0.0
    geo = srs.geometry(a.kinematics).geo
    one, other = srs_kernel.sides_of(geo, Q[20])
    assert abs(abs(np.angle(np.exp(1j * (one - other)))) - np.pi) < 0.1  # opposite sides
    r = a.solve(a.fk(Q[21]), q0=Q[20])
    assert r.success and r.solver == "srs"
    assert np.abs(r.q - Q[20]).max() < 0.08
    assert _pose_error(a, r.q, a.fk(Q[21])) < 1e-9
