"""Joints locked on the chain: fixed transforms at their values, checked against the full
arm's FK (Pinocchio on the whole URDF, and yourdfpy as an independent reader)."""

from __future__ import annotations

import math
import pickle
import warnings

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import armik
from armik.errors import JointError
from armik.model.catalogue import CATALOGUE

from ..conftest import TOL, arm, two_link_urdf, write_urdf

#: (robot, locked): the Panda's last joint; the UR5's first and fourth (mid-chain) joints;
#: a continuous joint of the Kinova beyond pi; the SCARA's prismatic quill; two at once.
CASES = [
    ("panda", {"panda_joint7": 0.3}),
    ("ur5", {"shoulder_pan_joint": 0.4}),
    ("ur5", {"wrist_1_joint": -1.2}),
    ("kinova", {"j2s6s200_joint_4": 4.0}),
    ("scara", {"quill": 0.12}),
    ("ur5", {"shoulder_pan_joint": -0.7, "wrist_2_joint": 0.9}),
]
IDS = [f"{name}-{'-'.join(locked)}" for name, locked in CASES]


def _load(name, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load(name, **kw)


def full_q(full: armik.Arm, locked_arm: armik.Arm, q: np.ndarray) -> np.ndarray:
    """The full arm's joint values: ``q`` for the free joints, the locked values inserted."""
    values = dict(zip(locked_arm.joint_names, q))
    values.update(locked_arm.locked)
    return np.array([values[n] for n in full.joint_names])


def pinocchio_fk(name: str, cfg: dict[str, float], base: str) -> pin.SE3:
    """T_base_tip of the catalogue arm, straight from Pinocchio's model of the whole URDF."""
    spec = CATALOGUE[name]
    model = pin.buildModelFromUrdf(str(spec.urdf_path()))
    q = pin.neutral(model)
    for jname, value in cfg.items():
        joint = model.joints[model.getJointId(jname)]
        if joint.nq == 2:  # continuous: (cos, sin)
            q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
        else:
            q[joint.idx_q] = value
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)

    def placement(frame: str) -> pin.SE3:
        assert model.existFrame(frame, pin.BODY)
        return data.oMf[model.getFrameId(frame, pin.BODY)]

    offset = pin.SE3(np.eye(3), np.array(spec.tip_offset or (0.0, 0.0, 0.0)))
    return placement(base).inverse() * placement(spec.tip) * offset


def yourdfpy_fk(name: str, cfg: dict[str, float], base: str) -> pin.SE3:
    spec = CATALOGUE[name]
    model = yourdfpy.URDF.load(
        str(spec.urdf_path()),
        build_scene_graph=True,
        load_meshes=False,
        build_collision_scene_graph=False,
        load_collision_meshes=False,
    )
    full = {j: 0.0 for j in model.actuated_joint_names}
    full.update(cfg)
    model.update_cfg(full)
    offset = pin.SE3(np.eye(3), np.array(spec.tip_offset or (0.0, 0.0, 0.0)))
    return pin.SE3(model.get_transform(frame_to=spec.tip, frame_from=base)) * offset


def close(A: pin.SE3, B: pin.SE3, tol: float) -> bool:
    return np.linalg.norm(pin.log6(A.inverse() * B).vector) < tol


@pytest.mark.parametrize("name, locked", CASES, ids=IDS)
def test_locked_chain_fk_matches_the_full_arm(name, locked, rng):
    a = _load(name, locked=locked)
    full = arm(name)
    assert a.dof == full.dof - len(locked)
    assert set(a.joint_names) == set(full.joint_names) - set(locked)
    assert dict(a.locked) == locked and set(a.kinematics.locked_on_chain) == set(locked)
    for i in range(10):
        q = a.random_q(rng)
        qf = full_q(full, a, q)
        T = a.fk(q)
        assert close(T, full.fk(qf), TOL["fk_exact"])
        cfg = dict(zip(full.joint_names, qf))
        assert close(T, pinocchio_fk(name, cfg, a.base), TOL["fk_exact"])
        if i < 3:  # yourdfpy rebuilds its scene graph per load: a few poses suffice
            assert close(T, yourdfpy_fk(name, cfg, a.base), TOL["fk_exact"])


@pytest.mark.parametrize("name, locked", CASES, ids=IDS)
def test_solves_on_the_locked_arm_reach_the_target_on_the_full_arm(name, locked):
    a = _load(name, locked=locked)
    full = arm(name)
    rng = np.random.default_rng(5)
    for _ in range(4):
        q = a.random_q(rng)
        T = full.fk(full_q(full, a, q))  # the target from the full arm
        r = a.solve(T, q0=a.middle, seed=1, iteration_budget=20000)
        assert r.success, r.reason
        assert len(r.q) == a.dof and a.within_limits(r.q)
        assert close(full.fk(full_q(full, a, r.q)), T, TOL["solve"] * 3)


def test_a_continuous_joint_locks_at_any_angle(rng):
    full = arm("kinova")
    for value in (100.0, -7.5, math.pi):
        a = _load("kinova", locked={"j2s6s200_joint_1": value})
        q = a.random_q(rng)
        assert close(a.fk(q), full.fk(full_q(full, a, q)), TOL["fk_exact"])
        assert a.locked["j2s6s200_joint_1"] == value


def test_locked_is_read_only():
    a = _load("panda", locked={"panda_joint7": 0.3})
    with pytest.raises(TypeError):
        a.locked["panda_joint7"] = 0.1  # type: ignore[index]


def test_locked_lists_off_chain_joints_given_by_value():
    a = _load("panda", locked={"panda_finger_joint1": 0.02, "panda_joint7": 0.3})
    assert dict(a.locked) == {"panda_finger_joint1": 0.02, "panda_joint7": 0.3}
    assert a.kinematics.locked_on_chain == ("panda_joint7",)
    assert dict(arm("panda").locked) == {} and arm("panda").kinematics.locked_on_chain == ()


def test_the_reduced_panda_is_a_6r_arm():
    a = _load("panda", locked={"panda_joint7": 0.3})
    assert a.dof == 6 and a.joint_types == ["revolute"] * 6
    assert a.joint_names == [f"panda_joint{i}" for i in range(1, 7)]


def test_with_locked_adds_locks_and_keeps_the_other_limits():
    base = arm("panda").with_limits({"panda_joint1": (-1.0, 1.0), "panda_joint7": (0.0, 1.0)})
    a = base.with_locked({"panda_joint7": 0.3})
    ref = _load("panda", locked={"panda_joint7": 0.3})
    assert a.joint_names == ref.joint_names and dict(a.locked) == {"panda_joint7": 0.3}
    assert a.lower[0] == -1.0 and a.upper[0] == 1.0  # the replaced limit of a free joint
    np.testing.assert_array_equal(a.lower[1:], ref.lower[1:])
    q = a.random_q(2)
    assert a.fk(q).isApprox(ref.fk(q), 1e-14)

    b = a.with_locked({"panda_joint2": -0.5})  # added to the lock already there
    assert dict(b.locked) == {"panda_joint7": 0.3, "panda_joint2": -0.5}
    assert b.dof == 5 and b.lower[0] == -1.0
    c = b.with_locked({"panda_joint7": 0.8})  # locked again: the new value, within (0, 1)
    assert c.locked["panda_joint7"] == 0.8 and c.dof == 5
    assert not c.fk(c.middle).isApprox(b.fk(b.middle), 1e-6)


@pytest.mark.parametrize(
    "make",
    [
        lambda: _load("panda", locked={"panda_joint7": 0.3}),
        lambda: _load("ur5", locked={"wrist_1_joint": -1.2}).with_limits(
            {"shoulder_pan_joint": (-1.0, 1.0)}
        ),
        lambda: arm("kinova").with_locked({"j2s6s200_joint_4": 4.0}),
        lambda: _load("scara", locked={"quill": 0.12}),
    ],
)
def test_pickling_keeps_the_locked_joints(make):
    a = make()
    copy = pickle.loads(pickle.dumps(a))
    assert copy.joint_names == a.joint_names and dict(copy.locked) == dict(a.locked)
    assert copy.kinematics.locked_on_chain == a.kinematics.locked_on_chain
    np.testing.assert_array_equal(copy.lower, a.lower)
    np.testing.assert_array_equal(copy.upper, a.upper)
    q = a.random_q(3)
    assert copy.fk(q).isApprox(a.fk(q), 1e-14)


@pytest.mark.parametrize(
    "name, locked, words",
    [
        ("panda", {"panda_joint7": 3.5}, "outside its URDF limits [-2.8973, 2.8973] rad"),
        # a value just past a limit reads past it, not as the limit itself
        ("panda", {"panda_joint7": 2.897301}, "locked value 2.897301 rad for 'panda_joint7'"),
        ("panda", {"panda_joint4": 0.0}, "'panda_joint4' is outside its URDF limits"),
        ("panda", {"panda_finger_joint1": 0.5}, "outside its URDF limits [0, 0.04] m"),
        ("scara", {"quill": -0.1}, "locked value -0.1 m for 'quill' is outside"),
        ("panda", {"panda_joint7": float("nan")}, "must be a finite number (rad or m), got nan"),
        ("panda", {"panda_joint7": float("inf")}, "must be a finite number"),
        ("panda", {"panda_joint7": "0.3"}, "must be a finite number"),
        ("panda", {"panda_joint7": 1 + 2j}, "must be a finite number"),
        ("panda", {"panda_joint9": 0.0}, "locked joint 'panda_joint9' does not exist; closest"),
        # the Panda's flange joint is fixed in its URDF: it exists, with no value to lock
        ("panda", {"panda_joint8": 0.0}, "locked joint 'panda_joint8' is a fixed joint: it has"),
        ("panda", {7: 0.0}, "joint names (str)"),
        ("panda", ["panda_joint7"], "locked must map joint names"),
        (
            "scara",
            {"shoulder": 0.0, "elbow": 0.0, "quill": 0.1, "tool_roll": 0.0},
            "leaves no moving joint on the chain",
        ),
    ],
)
def test_bad_locks_are_refused_with_the_joint_and_the_fix(name, locked, words):
    with pytest.raises(JointError) as err:
        _load(name, locked=locked)
    assert words in str(err.value)
    assert isinstance(err.value, ValueError)


def test_bad_locks_through_with_locked():
    a = arm("ur5")
    with pytest.raises(JointError, match="outside its URDF limits"):
        a.with_locked({"elbow_joint": 10.0})
    with pytest.raises(JointError, match="leaves no moving joint"):
        a.with_locked({n: 0.0 for n in a.joint_names})
    with pytest.raises(JointError, match="locked must map"):
        a.with_locked(None)  # type: ignore[arg-type]
    with pytest.raises(JointError, match="does not exist"):
        a.with_locked({"wrist_9_joint": 0.0})


def test_the_error_names_the_joint():
    with pytest.raises(JointError) as err:
        _load("panda", locked={"panda_joint7": 3.5})
    assert err.value.joint == "panda_joint7"


def test_a_mimic_joint_on_the_chain_can_be_locked(tmp_path):
    limit = '<limit lower="-3.14159" upper="3.14159" effort="1" velocity="1"/>'
    text = two_link_urdf().replace(
        f'{limit}</joint>\n  <joint name="tool"',
        f'{limit}<mimic joint="j1" multiplier="1"/></joint>\n  <joint name="tool"',
    )
    path = write_urdf(tmp_path, text)
    a = armik.load(path, tip="tip", locked={"j2": 0.5})
    assert a.joint_names == ["j1"]
    np.testing.assert_allclose(
        a.fk([0.25]).translation,
        [math.cos(0.25) + 0.8 * math.cos(0.75), math.sin(0.25) + 0.8 * math.sin(0.75), 0.0],
        atol=1e-12,
    )


def test_a_lock_after_with_limits_is_checked_against_those_limits():
    full = arm("panda")
    # widened past the URDF's 2.8973 rad: a value within them locks, at that value
    wide = full.with_limits({"panda_joint7": (-3.2, 3.2)}).with_locked({"panda_joint7": 3.1})
    assert dict(wide.locked) == {"panda_joint7": 3.1} and wide.dof == 6
    q = wide.random_q(4)
    cfg = dict(zip(wide.joint_names, q), panda_joint7=3.1)
    assert close(wide.fk(q), pinocchio_fk("panda", cfg, wide.base), TOL["fk_exact"])
    copy = pickle.loads(pickle.dumps(wide))  # rebuilt from its recipe, the lock kept
    assert dict(copy.locked) == {"panda_joint7": 3.1} and copy.fk(q).isApprox(wide.fk(q), 1e-14)
    # narrowed: a value within the URDF's limits but outside the arm's own is refused
    narrow = full.with_limits({"panda_joint7": (-1.0, 1.0), "panda_joint1": (-0.5, 0.5)})
    with pytest.raises(JointError, match=r"2 rad for 'panda_joint7' is outside its limits"):
        narrow.with_locked({"panda_joint7": 2.0})
    locked = narrow.with_locked({"panda_joint7": 0.5})  # the other joint keeps its limits
    assert locked.lower[0] == -0.5 and locked.upper[0] == 0.5
    again = locked.with_locked({"panda_joint7": -0.9})  # locked again: the same limits hold
    assert again.locked["panda_joint7"] == -0.9
    with pytest.raises(JointError, match=r"outside its limits \(given by with_limits\) \[-1, 1\]"):
        locked.with_locked({"panda_joint7": 1.5})


def test_a_continuous_joint_given_limits_locks_at_any_turn_within_them():
    a = arm("kinova").with_limits({"j2s6s200_joint_1": (-1.0, 1.0)})
    turns = -0.5 + 4 * math.pi  # an encoder's reading two turns on from -0.5 rad
    b = a.with_locked({"j2s6s200_joint_1": turns})
    assert b.locked["j2s6s200_joint_1"] == turns
    q = b.random_q(3)
    cfg = dict(zip(b.joint_names, q), j2s6s200_joint_1=-0.5)
    assert close(b.fk(q), pinocchio_fk("kinova", cfg, b.base), TOL["fk_exact"])
    with pytest.raises(JointError, match="outside its limits"):
        a.with_locked({"j2s6s200_joint_1": 2.5})  # no turn of 2.5 rad lies within them
