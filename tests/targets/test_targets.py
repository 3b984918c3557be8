"""Target parsing: every accepted form, and every malformed one refused by name."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from armik import TargetError, parse_target

from ..conftest import model


def _quat_xyzw(R):
    q = pin.Quaternion(R)
    return np.array([q.x, q.y, q.z, q.w])


def test_all_pose_forms_round_trip():
    T = pin.SE3.Random()
    forms = [
        T,
        T.homogeneous,
        (T.translation, _quat_xyzw(T.rotation)),
        list(T.translation) + list(_quat_xyzw(T.rotation)),
    ]
    for form in forms:
        t = parse_target(form)
        np.testing.assert_allclose(t.position, T.translation, atol=1e-15)
        np.testing.assert_allclose(t.rotation, T.rotation, atol=1e-12)
        assert not t.position_only


def test_position_only():
    t = parse_target([0.1, 0.2, 0.3])
    assert t.position_only and t.rotation is None
    np.testing.assert_allclose(t.se3().translation, [0.1, 0.2, 0.3])


def test_non_unit_quaternion_is_normalised():
    t = parse_target(([0, 0, 0], [0, 0, 2.0, 2.0]))  # 90 deg about z, scaled
    np.testing.assert_allclose(t.rotation, pin.rpy.rpyToMatrix(0, 0, np.pi / 2), atol=1e-12)


def test_planar_two_vector():
    a = model("planar_2link")
    t = parse_target([1.2, 0.5], a)
    np.testing.assert_allclose(t.position, [1.2, 0.5, 0.0])
    assert t.planar
    d = model("double_pendulum")  # axes along x: plane coordinates are base (y, z)
    t = parse_target([0.1, 0.2], d)
    np.testing.assert_allclose(d.plane.to_2d(t.position), [0.1, 0.2], atol=1e-15)
    assert abs(d.plane.height(t.position)) < 1e-15


@pytest.mark.parametrize(
    "value, match",
    [
        ([np.nan, 0, 0], "NaN or inf"),
        ([0, np.inf, 0], "NaN or inf"),
        ([1, 2, 3, 4], "shape"),
        (np.zeros((3, 3)), "shape"),
        ("abc", "not numeric"),
        (([0, 0, 0], [0, 0, 0, 0]), "zero norm"),
        (([0, 0], [0, 0, 0, 1]), "3 numbers"),
        (([0, 0, 0], [0, 0, 1]), "4 numbers"),
    ],
)
def test_malformed_targets(value, match):
    with pytest.raises(TargetError, match=match):
        parse_target(value)


def test_bad_matrices():
    M = np.eye(4)
    M[3] = [0, 0, 1, 1]
    with pytest.raises(TargetError, match="last row"):
        parse_target(M)
    M = np.eye(4)
    M[0, 0] = 2.0
    with pytest.raises(TargetError, match="not orthonormal"):
        parse_target(M)
    M = np.eye(4)
    M[2, 2] = -1.0
    with pytest.raises(TargetError, match="determinant -1"):
        parse_target(M)
    M = np.eye(4)
    M[1, 3] = np.nan
    with pytest.raises(TargetError, match="NaN"):
        parse_target(M)


def test_two_vector_needs_planar_arm():
    with pytest.raises(TargetError, match="planar arm.*'panda' is not planar .*not parallel"):
        parse_target([0.3, 0.2], model("panda"))
    assert isinstance(TargetError("x"), ValueError)


LIMIT = '<limit lower="-2" upper="2" effort="1" velocity="1"/>'


def _flat_arm(third: str) -> str:
    """Joints about z and a third joint ``third`` (its type and XML), every motion in the
    base's x-y plane."""
    joints = [("revolute", f'<axis xyz="0 0 1"/>{LIMIT}')] * 2 + [third]
    parts = ['<robot name="flat"><link name="l0"/>']
    for i, (kind, rest) in enumerate(joints, 1):
        parts.append(
            f'<link name="l{i}"/><joint name="j{i}" type="{kind}"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="{0 if i == 1 else 0.5} 0 0"/>{rest}</joint>'
        )
    return "".join(parts) + "</robot>"


@pytest.mark.parametrize(
    "third, words",
    [
        (
            ("revolute", f'<axis xyz="0 0 1"/>{LIMIT}<mimic joint="j2" multiplier="0.5"/>'),
            "has the mimic joint(s) 'j3'",
        ),
        (("prismatic", f'<axis xyz="1 0 0"/>{LIMIT}'), "has the prismatic joint 'j3'"),
    ],
)
def test_two_vector_on_an_arm_with_a_mimic_or_prismatic_joint_says_why(third, words):
    """Their motion stays in a plane, but the planar reading takes revolute joints only:
    the refusal says so instead of calling the arm not planar."""
    import armik

    arm = armik.load_string(_flat_arm(third), tip="l3")
    with pytest.raises(TargetError) as info:
        arm.solve([0.3, 0.2])
    text = str(info.value)
    assert words in text and "does not take" in text and "not planar" not in text
    assert "give a position (x, y, z)" in text


@pytest.mark.parametrize("form", ["(N, 4, 4)", "(N, 7)", "(N, 3)"])
def test_a_batch_position_beyond_reach_of_any_arm_is_refused_as_one_target_is(form):
    """``parse_target`` refuses a position beyond ``MAX_POSITION`` (the error arithmetic
    overflows); a batch's array forms hold each row to the same, naming the row."""
    from armik.targets.batch import parse_targets
    from armik.tolerances import MAX_POSITION

    T = np.array([pin.SE3.Random().homogeneous for _ in range(3)])
    T[1, 0, 3] = 10 * MAX_POSITION
    with pytest.raises(TargetError, match="beyond"):
        parse_target(T[1])
    value = {
        "(N, 4, 4)": T,
        "(N, 7)": np.hstack([T[:, :3, 3], np.tile([0.0, 0.0, 0.0, 1.0], (3, 1))]),
        "(N, 3)": T[:, :3, 3],
    }[form]
    with pytest.raises(TargetError, match=r"target 1: position .* is beyond 1e\+06 m"):
        parse_targets(value)
    if value.ndim == 3:  # at the bound: taken, as one target is
        value[1, 0, 3] = MAX_POSITION
    else:
        value[1, 0] = MAX_POSITION
    parse_targets(value)


def test_a_spatialmath_quaternion_is_read_by_its_scalar_and_vector_parts():
    """spatialmath's quaternions are (w, x, y, z) as arrays: ``(p, UnitQuaternion(R))`` is
    the pose (p, R), a ``Quaternion`` of any norm too, and one holding several rotations is
    refused as several poses are, not read as its first."""
    sm = pytest.importorskip("spatialmath")
    T = pin.SE3.Random()
    unit = sm.UnitQuaternion(T.rotation)
    for rotation in (unit, sm.Quaternion(3.0 * unit.A), sm.SO3(T.rotation)):
        t = parse_target((T.translation, rotation))
        np.testing.assert_allclose(t.rotation, T.rotation, atol=1e-12)
    two = sm.UnitQuaternion([unit, sm.UnitQuaternion.Rx(0.3)])
    with pytest.raises(TargetError, match="UnitQuaternion of 2 rotations"):
        parse_target((T.translation, two))
    with pytest.raises(TargetError, match="SO3 of 2 rotations"):
        parse_target((T.translation, sm.SO3([sm.SO3.Rx(0.1), sm.SO3.Ry(0.2)])))


def test_a_target_built_by_hand_is_checked_as_its_parts():
    """``armik.Target`` is public: one built with a position of 2 numbers was solved as if
    it had 3 (a success, its third read past the array's end), a 2x2 rotation or a row of a
    batch raised numpy's error. Its parts are checked as the parser checks them; plain
    parts given as lists are read as arrays."""
    import armik

    from ..conftest import arm

    ur5 = arm("ur5")
    T = ur5.fk(ur5.random_q(np.random.default_rng(1)))
    short = armik.Target(np.array([0.3, 0.2]))
    flat = armik.Target(T.translation, np.eye(2))
    nan = armik.Target(np.array([np.nan, 0.0, 0.0]), T.rotation)  # was "joint_limits"
    for bad, words in ((short, "3 numbers"), (flat, r"shape \(2, 2\)"), (nan, "NaN")):
        with pytest.raises(TargetError, match=words):
            ur5.solve(bad)
        with pytest.raises(TargetError, match="target 1: .*" + words):
            ur5.solve_batch([T, bad])
        with pytest.raises(TargetError, match=words):
            parse_target(bad)
    with pytest.raises(TargetError, match="target 0: .*determinant -1"):
        ur5.solve_batch([armik.Target(T.translation, -T.rotation)])
    listed = armik.Target(list(T.translation), T.rotation.tolist())
    r = ur5.solve(listed)
    assert r.success, r.reason
    np.testing.assert_allclose(ur5.fk(r.q).translation, T.translation, atol=1e-9)
    assert ur5.solve_batch([listed, T]).success.all()


def test_a_rotation_alone_or_tasks_among_poses_are_named_as_such():
    """A rotation without a position, or a row of tasks in a batch of poses, was refused
    as "not numeric"; the refusal says what it is and what to give."""
    from scipy.spatial.transform import Rotation

    import armik

    from ..conftest import arm

    for rotation in (pin.Quaternion(1, 0, 0, 0), Rotation.from_rotvec([0, 0, 0.1])):
        with pytest.raises(TargetError, match="a rotation without a position"):
            parse_target(rotation)
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle)
    with pytest.raises(TargetError, match="target 1: .* is a list of tasks where a pose"):
        ur5.solve_batch([T, [armik.Position(T.translation)]])


def test_a_lowered_task_list_or_a_target_by_hand_beyond_reach_of_any_arm_is_refused():
    """A position beyond ``MAX_POSITION`` is refused as the parser refuses one, where it
    comes as an ``armik.Target`` built by hand or from a task list lowered to one (a
    ``Position`` with an ``Axis``): it was solved, ``unreachable`` at an infinite distance."""
    import armik

    from ..conftest import arm

    ur5 = arm("ur5")
    far = [2e6, 0.0, 0.0]
    for target in (
        armik.Target(np.array(far)),
        [armik.Position(far), armik.Axis((0, 0, 1), (0, 0, 1), 0.1)],
    ):
        with pytest.raises(TargetError, match=r"beyond 1e\+06 m"):
            ur5.solve(target)


@pytest.mark.parametrize(
    "rotation",
    [lambda R: 2.0 * R, lambda R: R + 1e-3, lambda R: -R],
    ids=["scaled", "off by 1e-3", "reflected"],
)
def test_a_target_built_by_hand_whose_rotation_is_no_rotation_is_refused_by_solve(rotation):
    # solve's quick check of a hand-built Target read its shape alone: 2 R came out a
    # failed FK check, where solve_batch refused it by name
    import armik

    arm = armik.load("ur5")
    T = arm.fk(arm.random_q(3))
    target = armik.Target(T.translation.copy(), rotation(T.rotation))
    for call in (arm.solve, arm.solve_all, lambda t: arm.solve_batch([t])):
        with pytest.raises(TargetError, match="orthonormal|determinant"):
            call(target)


def test_two_positions_in_one_target_are_named_as_several_targets():
    # read as (position, rotation), they were refused for the rotation's shape (3,) alone
    p = np.array([0.4, 0.1, 0.3])
    for two in ([p, p + 0.01], (p, p + 0.01), [list(p), list(p)]):
        with pytest.raises(TargetError, match="4 numbers .*two positions are several targets"):
            parse_target(two)
    assert parse_target((p, [0.0, 0.0, 0.0, 1.0])).rotation is not None  # a pose still
