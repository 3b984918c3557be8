"""armik servo: a demo stream through the servo, its report, and bad input refused."""

from __future__ import annotations

import re

import pytest

from tests.tools.cli_run import run


def _number(pattern: str, text: str) -> float:
    found = re.search(pattern, text)
    assert found, text
    return float(found.group(1))


def test_servo_tracks_a_circle_and_a_jump_within_every_limit(capsys):
    code, out, err = run(capsys, "servo", "ur5", "--seconds", "0.6", "--jump", "0", "0.1", "0")
    assert code == 0, err
    assert out.startswith("ur5: 6 joints, dt 2 ms")
    # started at rest on a moving circle: a transient, then tracked
    assert _number(r"circle: 300 ticks .*?last ([0-9.e+-]+) m", out) < 1e-4
    assert _number(r"jump: 750 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
    counts = re.search(r"jump: .*\n  ticks by status: (.*)", out).group(1)
    assert "on_target" in counts and "acceleration_limit" in counts
    excess = re.search(r"position ([0-9.e+-]+), velocity ([0-9.e+-]+), acceleration (\S+)", out)
    assert [float(v) for v in excess.groups()] == [0.0, 0.0, 0.0]
    assert re.search(r"tick: median \d+ us, p99 \d+ us \(1050 ticks", out)


def test_servo_takes_the_limits_and_start_it_is_given(capsys):
    q0 = ["0.3", "-1.2", "1.4", "-1.5", "-1.5", "0.2"]
    code, out, err = run(
        capsys, "servo", "ur5", "--q0", *q0, "--seconds", "0.1", "--circle", "0",
        "--velocity-limit", "0.5", "--acceleration-limit", "5", "--dt", "0.004",
    )  # fmt: skip
    assert code == 0, err
    assert "dt 4 ms; q0 0.3 -1.2 1.4 -1.5 -1.5 0.2" in out
    assert "circle: 25 ticks" in out


def test_servo_refuses_bad_input_with_one_line(capsys):
    for argv, said in [
        (["--dt", "-1"], "dt must be the tick's period"),
        (["--seconds", "0"], "--seconds must be a positive"),
        (["--circle", "-0.1"], "--circle must be a finite radius"),
        (["--q0", "1", "2"], "q0 must have 6 values"),
        (["--acceleration-limit", "-3"], "--acceleration-limit must be positive"),
        # not finite, or more ticks than the demo makes: one line, not a traceback or a hang
        (["--seconds", "inf"], "--seconds must be a positive finite number"),
        (["--hz", "inf"], "--hz must be a positive finite number"),
        (["--circle", "inf"], "--circle must be a finite radius"),
        (["--jump", "nan", "0", "0"], "--jump must be 3 finite numbers"),
        (["--dt", "1e-300"], "2e+300 ticks, more than this demo streams"),
        (["--seconds", "1e9"], "5e+11 ticks, more than this demo streams"),
    ]:
        code, out, err = run(capsys, "servo", "ur5", *argv)
        assert code == 2, (argv, out)
        assert err.startswith("armik: error:") and said in err, err
        assert len(err.strip().splitlines()) == 1


def test_servo_help_gives_a_prismatic_joints_units(capsys):
    code, out, _ = run(capsys, "servo", "--help")
    text = " ".join(out.split())  # argparse wraps the help
    assert code == 0
    assert "rad/s on every joint, m/s on a prismatic one" in text
    assert "rad/s^2 on every joint, m/s^2 on a prismatic one" in text


@pytest.mark.parametrize(
    ("flag", "value", "said"),
    [
        ("--dt", "0", "--dt must be the tick's period"),
        ("--acceleration-limit", "-1", "--acceleration-limit must be positive"),
        ("--velocity-limit", "0", "--velocity-limit must be positive"),
    ],
)
def test_a_refused_value_is_named_by_its_flag(capsys, flag, value, said):
    # the refusal began with the servo's keyword (dt, acceleration_limits, velocity_limits)
    # and gave the fix as dt=0.002, none of which the command takes
    code, _, err = run(capsys, "servo", "ur5", "--seconds", "0.01", flag, value)
    assert code == 2 and err.startswith(f"armik: error: {said}"), err
    assert "dt=" not in err and "_limits" not in err


def test_servo_on_a_planar_arm_circles_in_its_plane(capsys):
    # planar_2link moves in the base's x-y plane: the circle in the y-z plane, the tool's
    # turn held, left it (0.2 m off at its top, out_of_reach) and could never be tracked
    code, out, err = run(capsys, "servo", "planar_2link", "--seconds", "1")
    assert code == 0, err
    assert _number(r"circle: 500 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
    assert _number(r"circle: .*?largest ([0-9.e+-]+) m", out) < 0.05
    assert "orientation free" in out and "out_of_reach" not in out
    excess = re.search(r"position ([0-9.e+-]+), velocity ([0-9.e+-]+), acceleration (\S+)", out)
    assert [float(v) for v in excess.groups()] == [0.0, 0.0, 0.0]


def test_servo_on_a_two_joint_arm_in_the_y_z_plane_circles_as_positions(capsys, tmp_path):
    # in the base's y-z plane, the circle held the tool's turn, which two joints cannot
    # while the tip goes round: 0.15 m off, never tracked
    urdf = tmp_path / "yz.urdf"
    urdf.write_text(YZ_TWO_LINK)
    code, out, err = run(capsys, "servo", str(urdf), "--q0", "0.3", "0.6", "--seconds", "1")
    assert code == 0, err
    assert _number(r"circle: 500 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
    assert "orientation free" in out


YZ_TWO_LINK = """<?xml version="1.0"?>
<robot name="yz2">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 1.0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="2"/></joint>
  <joint name="t" type="fixed"><parent link="l2"/><child link="tip"/>
    <origin xyz="0 0 0.8"/></joint>
</robot>"""


def test_an_arm_without_a_bundled_start_circles_from_one_with_room(capsys):
    # the iiwa's middle is its zeros, stretched straight up: the circle started at a
    # singularity and ended 3 cm off (RMS 6.5 cm), velocity-limited
    code, out, err = run(capsys, "servo", "kuka_iiwa14", "--seconds", "1")
    assert code == 0, err
    q0 = [float(v) for v in re.search(r"q0 (.*)", out).group(1).split()]
    assert any(abs(v) > 0.1 for v in q0)  # not the middle
    assert _number(r"circle: 500 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
    assert _number(r"circle: .*?RMS ([0-9.e+-]+) m", out) < 5e-3


def test_an_arm_of_five_joints_circles_as_positions(capsys):
    # the SO-101 cannot hold the tool's full orientation round the circle: it held it, and
    # ended 6 mm off after an RMS of 7 cm, acceleration-limited on 986 of 1000 ticks
    code, out, err = run(capsys, "servo", "so101", "--seconds", "1", "--jump", "0", "0.05", "0")
    assert code == 0, err
    assert "orientation free" in out
    assert _number(r"circle: 500 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
    assert _number(r"circle: .*?RMS ([0-9.e+-]+) m", out) < 5e-3
    assert _number(r"jump: 750 ticks .*?last ([0-9.e+-]+) m", out) < 1e-5
