"""``armik solve`` with a region or a direction: ``--bounds`` on a pose (an ``armik.Pose``),
``--axis``/``--toward``/``--within`` with ``--xyz`` (``armik.Position`` and ``armik.Axis``),
each answer checked on the arm's FK; the bad spellings refused in one line, exit 2."""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest

import armik
from tests.conftest import TOL, arm
from tests.tools.cli_run import run, words


def test_bounds_on_a_pose_is_the_pose_task(capsys):
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    rpy = pin.rpy.matrixToRpy(T.rotation)
    bounds = ["0", "0", "0", "0", "0", "inf"]
    code, out, _ = run(
        capsys,
        *("solve", "ur5", "--xyz", *words(T.translation), "--rpy", *words(rpy)),
        *("--bounds", *bounds, "--json"),
    )
    assert code == 0
    got = json.loads(out)["results"][0]
    T = pin.SE3(pin.rpy.rpyToMatrix(*rpy), T.translation)  # as the flags say it
    r = ur5.solve([armik.Pose(T, bounds=(0, 0, 0, 0, 0, math.inf))])
    assert got["success"] and got["q"] == r.q.tolist() and got["solver"] == r.solver
    reached = ur5.fk(np.array(got["q"]))
    assert np.linalg.norm(reached.translation - T.translation) <= TOL["solve"]
    # the spin about the target's z is free, the z axis is held
    assert np.linalg.norm(reached.rotation[:, 2] - T.rotation[:, 2]) <= TOL["solve"]
    # a region with --weights: the weights go into the Pose with the bounds
    code, out, _ = run(
        capsys,
        *("solve", "ur5", "--xyz", *words(T.translation), "--rpy", *words(rpy)),
        *("--bounds", "0.01", "0.01", "0.01", "0", "0", "inf", "--weights", "1", "1", "1"),
        *("1", "1", "0.5", "--solver", "dls"),
    )
    assert code == 0 and "converged" in out


def test_axis_toward_within(capsys):
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    toward = T.rotation[:, 2] + np.array([0.05, 0.0, 0.0])  # 0.05 rad or so off the z axis
    argv = ["solve", "ur5", "--xyz", *words(T.translation), "--axis", "0", "0", "1"]
    argv += ["--toward", *words(toward), "--within", "0.1"]
    code, out, _ = run(capsys, *argv, "--json")
    assert code == 0
    got = json.loads(out)["results"][0]
    assert got["success"]
    assert [t["task"] for t in got["task_errors"]] == ["Position", "Axis"]
    assert all(t["within"] for t in got["task_errors"])
    reached = ur5.fk(np.array(got["q"]))
    assert np.linalg.norm(reached.translation - T.translation) <= TOL["solve"]
    z = reached.rotation[:, 2]
    angle = math.acos(np.clip(z @ toward / np.linalg.norm(toward), -1, 1))
    assert angle <= 0.1 + TOL["solve"]
    code, out, _ = run(capsys, *argv)
    assert code == 0 and "tasks    : Position" in out and "Axis" in out and "(holds)" in out
    # exactly along --toward (no --within): the point and the axis, the spin free
    code, out, _ = run(
        capsys,
        "solve",
        "so101",
        "--xyz",
        *words(arm("so101").fk(arm("so101").middle).translation),
        "--axis",
        "0",
        "0",
        "1",
        "--toward",
        *words(arm("so101").fk(arm("so101").middle).rotation[:, 2]),
    )
    assert code == 0 and "success=True" in out


def test_prefer_with_a_region_or_an_axis_is_the_librarys(capsys):
    """--prefer beside --bounds or --axis (a task list): the library's preferred answer,
    each task measured at it; --prefer was refused after the solve, exit 2."""
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    rpy = pin.rpy.matrixToRpy(T.rotation)
    T = pin.SE3(pin.rpy.rpyToMatrix(*rpy), T.translation)  # as the flags say it
    bounds = (0, 0, 0, 0, 0, math.inf)
    z = T.rotation[:, 2]
    for flags, tasks in [
        (["--rpy", *words(rpy), "--bounds", "0", "0", "0", "0", "0", "inf"],
         [armik.Pose(T, bounds=bounds)]),
        (["--axis", "0", "0", "1", "--toward", *words(z)],
         [armik.Position(T.translation), armik.Axis((0, 0, 1), z)]),
    ]:  # fmt: skip
        argv = ["solve", "ur5", "--xyz", *words(T.translation), *flags]
        code, out, err = run(capsys, *argv, "--prefer", "manipulability", "--json")
        assert code == 0, err
        got = json.loads(out)["results"][0]
        r = ur5.solve(tasks, prefer="manipulability")
        assert r.success and got["success"] and got["q"] == r.q.tolist()
        assert got["score"] == r.score and all(t["within"] for t in got["task_errors"])


def test_bounds_with_an_axis_is_a_box_for_the_position(capsys):
    """--bounds BX BY BZ 0 0 0 with --axis (--toward or --look-at): the tip's origin within
    the box (base frame), as ``armik.Position(p, bounds=...)`` beside the aim; the answer is
    the library's, measured on the arm's FK. Refused before (exit 2)."""
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    p = T.translation + np.array([0.02, 0.0, 0.0])  # the tip 2 cm off, the box 3 cm wide
    z = T.rotation[:, 2]
    box = (0.03, 0.03, 0.03)
    point = T.translation + 0.5 * z
    for flags, aim in [
        (["--toward", *words(z), "--within", "0.05"], armik.Axis((0, 0, 1), z, 0.05)),
        (["--look-at", *words(point), "--within", "0.05"], armik.LookAt(point, (0, 0, 1), 0.05)),
    ]:  # fmt: skip
        argv = ["solve", "ur5", "--xyz", *words(p), "--axis", "0", "0", "1", *flags]
        code, out, err = run(capsys, *argv, "--bounds", *words(box), "0", "0", "0", "--json")
        assert code == 0, err
        got = json.loads(out)["results"][0]
        r = ur5.solve([armik.Position(p, bounds=box), aim])
        assert r.success and got["success"] and got["q"] == r.q.tolist()
        reached = ur5.fk(np.array(got["q"]))
        assert np.all(np.abs(reached.translation - p) <= np.array(box) + TOL["solve"])
        assert [t["task"] for t in got["task_errors"]] == ["Position", type(aim).__name__]
        assert all(t["within"] for t in got["task_errors"])


def test_axis_out_of_reach_exit_1(capsys):
    code, out, _ = run(
        capsys,
        "solve",
        "ur5",
        "--xyz",
        "4",
        "0",
        "0",
        "--axis",
        "0",
        "0",
        "1",
        "--toward",
        "0",
        "0",
        "-1",
        "--within",
        "0.1",
        "--timeout",
        "0.02",
        "--json",
    )
    got = json.loads(out)["results"][0]
    assert code == 1 and not got["success"]
    assert got["task_errors"][0]["task"] == "Position" and not got["task_errors"][0]["within"]


XYZ = ["--xyz", "0.4", "0.2", "0.3"]
RPY = ["--rpy", "3.1", "0", "0"]
AXIS = ["--axis", "0", "0", "1", "--toward", "0", "0", "-1"]


@pytest.mark.parametrize(
    "argv, message",
    [
        ([*XYZ, *RPY, *AXIS], "--axis does not go with --rpy"),
        ([*XYZ, "--quat", "0", "0", "0", "1", *AXIS], "--axis does not go with --quat"),
        ([*XYZ, "--toward", "0", "0", "-1"], "--toward goes with --axis"),
        ([*XYZ, "--within", "0.1"], "--within goes with --axis"),
        ([*XYZ, "--axis", "0", "0", "1"], "--toward is given 0 time(s) for 1 --axis"),
        ([*XYZ, *AXIS, "--within", "0.1", "--within", "0.2"], "--within is given 2 time(s)"),
        ([*XYZ, "--axis", "0", "0", "0", "--toward", "0", "0", "-1"], "--axis 0 0 0 is no dir"),
        ([*XYZ, "--axis", "0", "0", "1", "--toward", "nan", "0", "1"], "--toward nan 0 1 is no"),
        ([*XYZ, *AXIS, "--within", "4"], "--within 4 is no angle"),
        ([*XYZ, *AXIS, "--within", "nan"], "--within nan is no angle"),
        ([*XYZ, *AXIS, "--bounds", "0", "0", "0", "0", "0", "inf"], "bounds 0 0 inf do not go"),
        ([*XYZ, *AXIS, "--weights", "1", "1", "1", "1", "1", "0"], "1 1 0 does not go with --axis"),
        ([*XYZ, *AXIS, "--position-only"], "--position-only does not go with --axis"),
        ([*XYZ, *RPY, "--bounds", "0", "0", "0", "0", "0", "-1"], "--bounds must be 6 numbers"),
        ([*XYZ, *RPY, "--bounds", "0", "0", "nan", "0", "0", "0"], "--bounds must be 6 numbers"),
        ([*XYZ, *XYZ], "--xyz is given 2 times for one tip"),
        ([*XYZ, *RPY, *RPY], "--rpy is given 2 times for 1 --tip"),
        ([*XYZ, "--axis", "0", "0", "1", "--toward", "0", "0"], "expected 3 arguments"),
        ([*XYZ, *AXIS, "--look-at", "1", "0", "0"], "--toward and --look-at both say"),
        ([*XYZ, "--look-at", "1", "0", "0"], "--look-at goes with --axis"),
        ([*XYZ, "--axis", "0", "0", "1", "--look-at", "nan", "0", "0"], "is no point"),
    ],
)
def test_bad_task_flags_exit_2_one_line(capsys, argv, message):
    code, _, err = run(capsys, "solve", "ur5", *argv)
    assert code == 2 and message in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_weights_with_an_axis_follow_the_librarys_rule(capsys):
    """--weights with --axis: refused where the library refuses it (a rotation weight of 0
    frees the rotation the axis measures: ``targets.aim.refuse_freed``), in the flags'
    words; other weights taken, as ``Arm.solve`` takes them, the answer's axis within its
    cone. The command line refused any --weights with --axis."""
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    argv = ["solve", "ur5", "--xyz", *words(T.translation), "--axis", "0", "0", "1"]
    argv += ["--toward", *words(T.rotation[:, 2]), "--within", "0.1", "--json"]
    code, out, err = run(capsys, *argv, "--weights", "1", "1", "1", "0.5", "0.5", "0.5")
    assert code == 0, err
    got = json.loads(out)["results"][0]
    assert got["success"] and "the tip's axis within its cone of 0.1 rad" in got["reason"]
    reached = ur5.fk(np.array(got["q"]))
    assert np.linalg.norm(reached.translation - T.translation) <= TOL["solve"]
    assert reached.rotation[:, 2] @ T.rotation[:, 2] >= math.cos(0.1 + TOL["solve"])
    for bad in (["--weights", "1", "1", "1", "0", "1", "1"], ["--position-only"]):
        with pytest.raises(armik.OptionError, match="frees a rotation the aim measures"):
            ur5.solve(
                [armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], 0.1)],
                **({"position_only": True} if len(bad) == 1 else {"weights": (1, 1, 1, 0, 1, 1)}),
            )
        code, _, err = run(capsys, *argv, *bad)
        assert code == 2 and f"{bad[0]}" in err and "does not go with --axis" in err, err
        assert "frees the rotation --axis measures" in err and len(err.strip().splitlines()) == 1


def test_a_cone_takes_a_solver_and_collisions(capsys):
    """A point with the tool in a cone is the compiled path's: ``--solver`` and
    ``--self-collision`` apply to it, its tasks measured all the same."""
    T = arm("ur5").fk(arm("ur5").middle)
    xyz = ["--xyz", *words(T.translation)]
    cone = ["--axis", "0", "0", "1", "--toward", *words(T.rotation[:, 2]), "--within", "0.1"]
    for extra in (["--solver", "qp"], ["--self-collision"]):
        code, out, _ = run(capsys, "solve", "ur5", *xyz, *cone, *extra, "--json")
        got = json.loads(out)["results"][0]
        assert code == 0 and got["success"], got
        assert [row["task"] for row in got["task_errors"]] == ["Position", "Axis"]
        assert all(row["within"] for row in got["task_errors"])


def test_axis_look_at_within(capsys):
    """``--axis`` with ``--look-at``: the tool at the point, its axis aimed at another
    within ``--within``, each task measured (``task_errors``)."""
    ur5 = arm("ur5")
    T = ur5.fk(ur5.middle)
    point = T.translation + 0.5 * T.rotation[:, 2] + np.array([0.02, 0.0, 0.0])
    xyz = ["--xyz", *words(T.translation)]
    look = ["--axis", "0", "0", "1", "--look-at", *words(point), "--within", "0.05"]
    code, out, _ = run(capsys, "solve", "ur5", *xyz, *look, "--json")
    got = json.loads(out)["results"][0]
    assert code == 0 and got["success"], got
    assert [row["task"] for row in got["task_errors"]] == ["Position", "LookAt"]
    reached = ur5.fk(np.array(got["q"]))
    sight = (point - reached.translation) / np.linalg.norm(point - reached.translation)
    angle = math.acos(np.clip(reached.rotation[:, 2] @ sight, -1, 1))
    assert angle <= 0.05 + TOL["solve"]
    assert np.linalg.norm(reached.translation - T.translation) <= TOL["solve"]


def test_held_joints_and_a_counted_budget(capsys):
    """``--hold NAME=VALUE`` (repeatable; ``NAME`` alone: q0's value) and ``--iterations``:
    a UR5's position with two wrist joints held where an answer has them, checked on the
    arm's FK; a joint held twice, or a bad value, refused in one line."""
    ur5 = arm("ur5")
    q = np.array([0.3, -1.0, 1.2, -0.5, 1.0, 0.2])
    p = ur5.fk(q).translation
    code, out, _ = run(
        capsys,
        *("solve", "ur5", "--xyz", *words(p), "--position-only", "--json"),
        *("--hold", "wrist_2_joint=1.0", "--hold", "wrist_3_joint=0.2", "--iterations", "4000"),
    )
    assert code == 0
    got = json.loads(out)["results"][0]
    assert got["success"] and got["q"][4] == 1.0 and got["q"][5] == 0.2
    assert np.linalg.norm(ur5.fk(np.array(got["q"])).translation - p) <= TOL["solve"]
    code, _, err = run(
        capsys, "solve", "ur5", "--xyz", *words(p), "--hold", "wrist_3_joint", "--hold",
        "wrist_3_joint=0.1",
    )  # fmt: skip
    assert code == 2 and "--hold gives joint 'wrist_3_joint' twice" in err
    code, _, err = run(capsys, "solve", "ur5", "--xyz", *words(p), "--hold", "wrist_3_joint=x")
    assert code == 2 and "must be a number" in err


def test_position_only_with_bounds_drops_the_rotation_on_one_tip(capsys):
    # --rpy with --bounds and --position-only on one tip was refused (exit 2) in Python's
    # words (position_only=True, armik.Position(p)); on several tips, and without --rpy, the
    # same flags solve the position within its box: so does one tip now, the box in the
    # target's frame (--bounds' help), where it was read in the base's
    ur5 = arm("ur5")
    T = ur5.fk(np.array([0.3, -1.1, 1.4, -0.6, -1.5, 0.9]))
    box = ["0.01", "0.02", "0.005", "0", "0", "0"]
    xyz = ("--xyz", *words(T.translation))
    rpy = ("--rpy", "3.0", "0.4", "-1.0")  # an orientation the answer need not have
    flags = ("--bounds", *box, "--position-only", "--json")
    code, out, err = run(capsys, "solve", "ur5", *xyz, *rpy, *flags)
    assert code == 0, err
    got = json.loads(out)["results"][0]
    R = pin.rpy.rpyToMatrix(3.0, 0.4, -1.0)
    reached = R.T @ (ur5.fk(np.array(got["q"])).translation - T.translation)  # target's axes
    assert got["success"] and np.all(np.abs(reached) <= np.array([0.01, 0.02, 0.005]) + 1e-6)


def test_look_at_the_xyz_point_is_refused_in_the_flags_words(capsys):
    # refused in Python's words: "LookAt point ... is where Position puts the frame itself
    # ... give the frame's position a box (bounds=)"
    xyz = ("--xyz", "0.4", "0.2", "0.3")
    code, _, err = run(capsys, "solve", "ur5", *xyz, "--axis", "0", "0", "1", "--look-at", *xyz[1:])
    assert code == 2 and err.count("\n") == 1
    assert "--look-at [0.4, 0.2, 0.3] is where --xyz puts the tip" in err
    assert "(--bounds BX BY BZ 0 0 0)" in err
    assert not any(w in err for w in ("LookAt", "Position", "bounds="))
