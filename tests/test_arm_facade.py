"""The facade has an arm model (``Arm.kinematics``) instead of being one: its public names,
what it reads through, the variants it builds and how it and its model pickle."""

import pickle

import numpy as np
import pytest

import armik
from armik.model.arm_model import ArmModel, model_of

PUBLIC = {
    # what the arm is
    "name", "source", "dof", "joint_names", "joint_types", "lower", "upper", "neutral",
    "middle", "base", "tip", "tip_offset", "tip_reason", "locked", "info", "model",
    "kinematics",
    # its kinematics
    "fk", "fk_batch", "jacobian", "random_q", "within_limits", "frames",
    # variants
    "with_limits", "with_locked",
    # solving and collisions
    "solve", "solve_all", "solve_batch", "solve_path", "min_distance", "in_collision",
    # a 7R arm's self-motion: each branch's intervals of its parameter
    "intervals",
    # streaming
    "servo",
}  # fmt: skip


def test_the_facade_publishes_its_names_only():
    arm = armik.load("ur5")
    assert {n for n in dir(arm) if not n.startswith("_")} == PUBLIC
    assert isinstance(arm.kinematics, ArmModel) and not isinstance(arm, ArmModel)
    for internal in ("to_pin", "data", "tip_frame_id", "kernel_chain", "mimics", "seed"):
        assert not hasattr(arm, internal) and hasattr(arm.kinematics, internal)


def test_the_facade_reads_its_model():
    arm = armik.load("panda", locked={"panda_joint7": 0.2})
    kin = arm.kinematics
    for name in ("name", "source", "dof", "joint_names", "base", "tip", "tip_reason", "info"):
        assert getattr(arm, name) == getattr(kin, name)
    for name in ("lower", "upper", "middle", "neutral"):
        assert getattr(arm, name) is getattr(kin, name)
    assert arm.model is kin.model and dict(arm.locked) == {"panda_joint7": 0.2}
    q = arm.random_q(7)
    np.testing.assert_array_equal(arm.fk(q).homogeneous, kin.fk(q).homogeneous)
    np.testing.assert_array_equal(arm.jacobian(q, "base"), kin.jacobian(q, "base"))
    np.testing.assert_array_equal(arm.fk_batch(q[None]), kin.fk_batch(q[None]))
    assert arm.within_limits(q) and not arm.within_limits(arm.upper + 0.1)
    with pytest.raises(AttributeError):
        arm.dof = 3  # read-only: the model says how many joints there are
    assert repr(arm).startswith("Arm('panda', dof=6")
    assert repr(kin).startswith("ArmModel('panda', dof=6")


def test_a_tool_offset_is_said_by_the_arm_the_robot_and_armik_info(capsys):
    """The double pendulum's catalogue tip carries a 0.2 m tool point: fk included it, but
    ``Arm`` had no ``tip_offset`` and ``armik info`` said only 'to 'link2''."""
    from armik.tools.cli import main

    arm = armik.load("double_pendulum")
    assert arm.tip == "link2" and arm.tip_offset == (0.0, 0.0, 0.2)
    q = arm.random_q(3)
    bare = armik.load("double_pendulum", tip_offset=(0, 0, 0))  # link2's own frame
    tool = bare.fk(q).act(np.array(arm.tip_offset))
    np.testing.assert_allclose(arm.fk(q).translation, tool, atol=1e-12)
    with pytest.raises(AttributeError):
        arm.tip_offset = None  # read-only: the model's
    assert "tip_offset=(0.0, 0.0, 0.2)" in repr(arm)
    assert armik.load("ur5").tip_offset is None
    assert armik.load("ur5", tip_offset=(0, 0, 0.1)).tip_offset == (0.0, 0.0, 0.1)
    assert main(["info", "double_pendulum"]) == 0
    assert "tip offset: (0, 0, 0.2) m in the frame of 'link2'" in capsys.readouterr().out
    assert main(["info", "ur5"]) == 0
    assert "tip offset" not in capsys.readouterr().out
    robot = armik.load("double_pendulum", tips=["link1", "link2"])
    assert robot.tip_offsets == {"link2": (0.0, 0.0, 0.2)}
    assert "tip_offsets={'link2': (0.0, 0.0, 0.2)}" in repr(robot)
    assert main(["info", "double_pendulum", "--tip", "link1", "--tip", "link2"]) == 0
    out = capsys.readouterr().out
    assert out.count("tip offset:") == 1 and "in the frame of 'link2'" in out


def test_variants_are_facades_of_new_models():
    arm = armik.load("panda")
    narrow = arm.with_limits({"panda_joint1": (-0.5, 0.5)})
    assert isinstance(narrow, armik.Arm) and narrow.kinematics is not arm.kinematics
    assert narrow.upper[0] == 0.5 and arm.upper[0] != 0.5
    held = arm.with_locked({"panda_joint7": 0.3})
    assert isinstance(held, armik.Arm) and held.dof == 6
    model = arm.kinematics.with_locked({"panda_joint7": 0.3})  # what hold= builds
    assert isinstance(model, ArmModel) and model.joint_names == held.joint_names
    np.testing.assert_array_equal(
        model.fk(held.middle).homogeneous, held.fk(held.middle).homogeneous
    )


def test_an_arm_and_its_model_pickle_as_their_recipe():
    arm = armik.load("panda").with_limits({"panda_joint1": (-0.5, 0.5)})
    again = pickle.loads(pickle.dumps(arm))
    assert isinstance(again, armik.Arm) and again.upper[0] == 0.5
    model = pickle.loads(pickle.dumps(arm.kinematics))
    assert isinstance(model, ArmModel) and model.upper[0] == 0.5
    q = arm.random_q(3)
    np.testing.assert_array_equal(model.fk(q).homogeneous, arm.fk(q).homogeneous)


def test_a_model_without_a_recipe_says_how_to_get_one():
    kin = armik.load("ur5").kinematics
    bare = object.__new__(ArmModel)
    bare.__dict__.update(kin.__dict__)
    bare._recipe = None
    with pytest.raises(TypeError, match=r"not built by armik.load.*armik.load\(\.\.\.\)"):
        pickle.dumps(bare)
    with pytest.raises(TypeError, match="no recipe to rebuild from"):
        bare.with_locked({"wrist_3_joint": 0.0})
    with pytest.raises(armik.JointError, match=r"e\.g\. \{'wrist_3_joint': 0\.0\}; got None"):
        kin.with_locked(None)  # type: ignore[arg-type]


def test_public_functions_below_the_facade_take_either():
    arm = armik.load("ur5")
    assert model_of(arm) is arm.kinematics and model_of(arm.kinematics) is arm.kinematics
    with pytest.raises(armik.InputError, match="expected an arm from armik.load"):
        model_of("ur5")
    pairs = armik.collision.never_colliding_pairs(arm, n=20)
    assert pairs == armik.collision.never_colliding_pairs(arm.kinematics, n=20)


@pytest.mark.parametrize("name", ["constraints", "secondary", "budget"])
def test_none_is_an_option_not_given(name):
    """``constraints=None``, ``secondary=None`` and ``budget=None`` mean none given, as
    None does for every other option (``obstacles``, ``hold``, ``prefer``), where they were
    refused as not a constraint, a Posture or a Budget."""
    ur5 = armik.load("ur5")
    T = ur5.fk(ur5.middle + 0.1)
    plain = ur5.solve(T, seed=3)
    r = ur5.solve(T, seed=3, **{name: None})
    assert r.success and np.array_equal(r.q, plain.q)
    assert ur5.solve_batch([T, T], workers=1, **{name: None}).success.all()
