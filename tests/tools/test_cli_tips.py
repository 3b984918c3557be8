"""Several tips on the command line (``--tip A --tip B``), on example-robot-data's two-armed
robots: the Baxter (no joint shared) and TALOS (a two-joint torso on both chains).
``info`` prints each chain and the shared joints; ``solve`` takes one target per tip,
matched in order, its answer checked on Pinocchio's model of the whole URDF."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import TOL
from tests.tools.cli_run import run, words

ROBOTS = Path(armik.load("panda").kinematics.source).parents[2]  # example-robot-data's folder
BAXTER = str(ROBOTS / "baxter_description" / "urdf" / "baxter.urdf")
TALOS = str(ROBOTS / "talos_data" / "robots" / "talos_reduced.urdf")
HANDS = {
    BAXTER: ("left_gripper", "right_gripper"),
    TALOS: ("gripper_left_base_link", "gripper_right_base_link"),
}


def placements(urdf: str, names, values) -> dict[str, pin.SE3]:
    """Each hand's placement at ``values`` (joint name -> value), by Pinocchio's model of
    the whole URDF, the other joints at neutral."""
    model = pin.buildModelFromUrdf(urdf)
    data = model.createData()
    q = pin.neutral(model)
    for name, value in zip(names, values):
        q[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, q)
    return {tip: data.oMf[model.getFrameId(tip)].copy() for tip in HANDS[urdf]}


def hand_flags(urdf: str, seed: int) -> tuple[list[str], dict[str, pin.SE3]]:
    """``--tip T --xyz .. --quat ..`` for each hand at a random configuration's poses."""
    robot = armik.load(urdf, tips=list(HANDS[urdf]))
    targets = placements(urdf, robot.joint_names, robot.random_q(seed))
    argv: list[str] = []
    for tip, T in targets.items():
        quat = pin.Quaternion(T.rotation).coeffs()  # x, y, z, w
        argv += ["--tip", tip, "--xyz", *words(T.translation), "--quat", *words(quat)]
    return argv, targets


def test_info_each_chain_and_the_shared_joints(capsys):
    left, right = HANDS[TALOS]
    code, out, _ = run(capsys, "info", TALOS, "--tip", left, "--tip", right)
    assert code == 0
    assert "talos: 2 tips from 'base_link', 16 joints, 2 shared" in out
    assert f"tip '{left}': 9 joints" in out and f"tip '{right}': 9 joints" in out
    assert "shared joints: torso_1_joint, torso_2_joint" in out
    assert out.count("torso_1_joint") >= 3 and "arm_right_7_joint" in out
    code, out, _ = run(capsys, "info", BAXTER, "--tip", "left_gripper", "--tip", "right_gripper")
    assert code == 0 and "shared joints: none" in out and "14 joints" in out
    code, out, _ = run(
        capsys, "info", BAXTER, "--tip", "left_gripper", "--tip", "right_gripper", "--frames"
    )
    assert code == 0 and "-> left_gripper  (a tip)" in out and "-> right_gripper  (a tip)" in out
    # --tips A B is --tip A --tip B
    assert (
        run(capsys, "info", TALOS, "--tips", left, right)[1]
        == run(capsys, "info", TALOS, "--tip", left, "--tip", right)[1]
    )
    # one --tip is the one-arm info, as before
    code, out, _ = run(capsys, "info", BAXTER, "--tip", "left_gripper")
    assert code == 0 and "structure:" in out and "auto ->" in out


@pytest.mark.parametrize("urdf", [BAXTER, TALOS], ids=["baxter", "talos"])
def test_solve_a_pose_per_tip(capsys, urdf):
    argv, targets = hand_flags(urdf, 3)
    code, out, err = run(capsys, "solve", urdf, *argv, "--timeout", "1", "--json")
    assert code == 0, err
    data = json.loads(out)
    (r,) = data["results"]
    assert r["success"] and list(data["tips"]) == list(HANDS[urdf])
    assert data["shared"] == ([] if urdf == BAXTER else ["torso_1_joint", "torso_2_joint"])
    reached = placements(urdf, data["joints"], r["q"])
    for tip, T in targets.items():
        err6 = pin.log6(T.inverse() * reached[tip]).vector
        assert np.abs(err6).max() <= 2 * TOL["solve"]
        assert r["tips"][tip]["position_error"] <= TOL["solve"]
    if urdf == BAXTER:  # each chain alone: its own status and solver
        assert all(r["tips"][t]["status"] == "converged" for t in targets)
    else:  # together: a Pose task per tip
        assert all(r["tips"][t]["task_errors"][0]["task"] == "Pose" for t in targets)
    code, out, _ = run(capsys, "solve", urdf, *argv, "--timeout", "1")
    assert code == 0 and "success=True" in out
    for tip in targets:
        assert f"    {tip}: position " in out


def test_regions_and_directions_per_tip(capsys):
    """--bounds on both tips' poses and --axis per tip, on the shared torso."""
    argv, targets = hand_flags(TALOS, 5)
    code, out, err = run(
        capsys, "solve", TALOS, *argv, "--bounds", "0.01", "0.01", "0.01", "0", "0", "inf",
        "--timeout", "1", "--json",
    )  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["results"][0]["success"]
    left, right = HANDS[TALOS]
    flags: list[str] = []
    for tip, T in targets.items():
        flags += ["--tip", tip, "--xyz", *words(T.translation), "--axis", "0", "0", "1"]
        flags += ["--toward", *words(T.rotation[:, 2]), "--within", "0.05"]
    code, out, err = run(capsys, "solve", TALOS, *flags, "--timeout", "1", "--json")
    assert code == 0, err
    r = json.loads(out)["results"][0]
    assert [t["task"] for t in r["tips"][left]["task_errors"]] == ["Position", "Axis"]
    reached = placements(TALOS, json.loads(out)["joints"], r["q"])
    for tip, T in targets.items():
        assert np.linalg.norm(reached[tip].translation - T.translation) <= 2 * TOL["solve"]
        cos = reached[tip].rotation[:, 2] @ T.rotation[:, 2]
        assert np.arccos(min(cos, 1.0)) <= 0.05 + TOL["solve"]
    # --bounds with --axis: each tip's origin within its box, 2 cm off the point given
    box = ["0.03", "0.03", "0.03", "0", "0", "0"]
    moved: list[str] = []
    for tip, T in targets.items():
        point = T.translation + np.array([0.02, 0.0, 0.0])
        moved += ["--tip", tip, "--xyz", *words(point), "--axis", "0", "0", "1"]
        moved += ["--toward", *words(T.rotation[:, 2]), "--within", "0.05"]
    argv = ["solve", TALOS, *moved, "--bounds", *box, "--timeout", "1", "--json"]
    code, out, err = run(capsys, *argv)
    assert code == 0, err
    r = json.loads(out)["results"][0]
    assert r["success"] and r["tips"][left]["task_errors"][0]["within"]
    reached = placements(TALOS, json.loads(out)["joints"], r["q"])
    for tip, T in targets.items():
        point = T.translation + np.array([0.02, 0.0, 0.0])
        assert np.all(np.abs(reached[tip].translation - point) <= 0.03 + TOL["solve"])
        cos = reached[tip].rotation[:, 2] @ T.rotation[:, 2]
        assert np.arccos(min(cos, 1.0)) <= 0.05 + TOL["solve"]


def test_a_tip_out_of_reach_exit_1(capsys):
    argv, _ = hand_flags(BAXTER, 4)
    argv[argv.index("--xyz", argv.index("right_gripper")) + 1] = "5"  # the right hand's x
    code, out, _ = run(capsys, "solve", BAXTER, *argv, "--timeout", "0.05")
    assert code == 1 and "success=False" in out and "reason   : right_gripper:" in out


LEFT, RIGHT = HANDS[BAXTER]
T_LEFT = ["--tip", LEFT, "--xyz", "0.5", "0.5", "0.3"]
T_RIGHT = ["--tip", RIGHT, "--xyz", "0.5", "-0.5", "0.3"]


@pytest.mark.parametrize(
    "urdf, argv, message",
    [
        (BAXTER, [*T_LEFT, "--tip", RIGHT], "--xyz is given 1 time for 2 --tip"),
        (BAXTER, [*T_LEFT, *T_RIGHT, "--rpy", "0", "0", "0"], "--rpy is given 1 time for 2"),
        (BAXTER, [*T_LEFT, "--quat", "0", "0", "0", "1", *T_RIGHT], "--quat is given 1 time"),
        (BAXTER, [*T_LEFT, *T_LEFT], f"--tip {LEFT} is given twice"),
        (BAXTER, [*T_LEFT, *T_RIGHT, "--all"], "--all lists every solution of one chain"),
        (BAXTER, [*T_LEFT, *T_RIGHT, "--q0", "0", "0"], "--q0 must give 14 finite values"),
        (BAXTER, [*T_LEFT, "--tip", "hand", "--xyz", "0", "0", "0"], "'hand'"),
        (
            BAXTER,
            [*T_LEFT, "--axis", "0", "0", "1", *T_RIGHT, "--toward", "0", "0", "-1"],
            "--axis is given 1 time for 2 --tip",
        ),
        (TALOS, ["--tip", HANDS[TALOS][0], *T_LEFT[2:], "--tip", HANDS[TALOS][1], *T_RIGHT[2:],
                 "--solver", "dls"], "--solver does not apply to these tips: they share joints"),
        (TALOS, ["--tip", HANDS[TALOS][0], *T_LEFT[2:], "--tip", HANDS[TALOS][1], *T_RIGHT[2:],
                 "--prefer", "nearest"], "--prefer does not apply"),
        (TALOS, ["--tip", HANDS[TALOS][0], *T_LEFT[2:], "--rpy", "0", "0", "0", "--tip",
                 HANDS[TALOS][1], *T_RIGHT[2:], "--rpy", "0", "0", "0",
                 "--weights", "1", "1", "1", "1", "1", "0"], "give --bounds too"),
    ],
)  # fmt: skip
def test_bad_several_tips_exit_2_one_line(capsys, urdf, argv, message):
    code, _, err = run(capsys, "solve", urdf, *argv)
    assert code == 2 and message in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_weights_with_an_axis_per_tip_follow_the_librarys_rule(capsys):
    """--axis on every tip with --weights: the Baxter's chains take weights that hold a
    rotation, each answer's axis within its cone, and refuse a rotation weight of 0 or
    --position-only (which free it) by the library's rule, in the flags' words; TALOS's
    chains, solved together, take neither and say so by flag."""
    for urdf in (BAXTER, TALOS):
        robot = armik.load(urdf, tips=list(HANDS[urdf]))
        targets = placements(urdf, robot.joint_names, robot.random_q(5))
        flags: list[str] = []
        for tip, T in targets.items():
            flags += ["--tip", tip, "--xyz", *words(T.translation), "--axis", "0", "0", "1"]
            flags += ["--toward", *words(T.rotation[:, 2]), "--within", "0.05"]
        argv = ["solve", urdf, *flags, "--timeout", "1"]
        weighed = ["--weights", "1", "1", "1", "0.5", "0.5", "0.5"]
        code, out, err = run(capsys, *argv, *weighed, "--json")
        if urdf == TALOS:
            assert code == 2 and "--weights does not apply to these tips" in err, err
            code, _, err = run(capsys, *argv, "--position-only")
            assert code == 2 and "--position-only does not apply to these tips" in err, err
            continue
        assert code == 0, err
        r = json.loads(out)["results"][0]
        reached = placements(urdf, json.loads(out)["joints"], r["q"])
        for tip, T in targets.items():
            assert np.linalg.norm(reached[tip].translation - T.translation) <= 2 * TOL["solve"]
            cos = reached[tip].rotation[:, 2] @ T.rotation[:, 2]
            assert np.arccos(min(cos, 1.0)) <= 0.05 + TOL["solve"]
        for bad in (["--weights", "1", "1", "1", "1", "1", "0"], ["--position-only"]):
            code, _, err = run(capsys, *argv, *bad)
            assert code == 2 and f"{bad[0]}" in err and "does not go with --axis" in err, err
            assert "frees the rotation --axis measures" in err


def test_position_only_on_several_tips(capsys):
    argv, targets = hand_flags(BAXTER, 6)
    code, out, err = run(capsys, "solve", BAXTER, *argv, "--position-only", "--json")
    assert code == 0, err
    r = json.loads(out)["results"][0]
    assert r["success"] and r["orientation_error"] is None
    reached = placements(BAXTER, json.loads(out)["joints"], r["q"])
    for tip, T in targets.items():
        assert r["tips"][tip]["orientation_error"] is None
        assert np.linalg.norm(reached[tip].translation - T.translation) <= 2 * TOL["solve"]


@pytest.mark.parametrize("name", ["batch", "path", "reach", "export", "servo"])
def test_one_tip_commands_refuse_a_second_tip_by_name(capsys, name):
    # these commands work on one tip: a second --tip was silently taken in place of the first
    code, out, err = run(capsys, name, "ur5", "--tip", "tool0", "--tip", "wrist_3_link")
    assert code == 2 and out == ""
    assert "--tip given twice ('tool0', then 'wrist_3_link')" in err
    assert f"'armik {name}' works on one tip" in err and "tips=[A, B]" in err
