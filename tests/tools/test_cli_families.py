"""``armik info`` names the family of every 6R arm and, for a 7R arm, the family of the six
joints left by holding each one (and which holds make them analytic)."""

from __future__ import annotations

import re

import numpy as np

from ..conftest import write_urdf
from ..solve.test_held import iiwa_urdf
from ..solvers.closed_form.test_general_6r import random_arm_urdf
from .test_cli import run


def test_six_r_families(capsys, tmp_path):
    code, out, _ = run(capsys, "info", "ur5")
    assert code == 0 and "family: three_parallel (axes 2, 3, 4 parallel" in out
    code, out, _ = run(capsys, "info", "abb_irb120")
    assert code == 0 and "family: spherical_wrist (spherical wrist at" in out
    path = write_urdf(tmp_path, random_arm_urdf(np.random.default_rng(0)), name="g6.urdf")
    code, out, _ = run(capsys, "info", str(path), "--base", "world", "--tip", "tool")
    assert code == 0 and "family: elimination_6r (elimination with joint" in out
    assert "auto -> dls (one answer); solve_all -> elimination_6r" in out
    assert "solve_all   -> elimination_6r (closed form)" in out  # polynomial roots, no grid
    code, out, _ = run(capsys, "info", "planar_2link")
    assert code == 0 and "family:" not in out and "hold one joint" not in out


def test_seven_r_arms_name_the_joints_to_hold(capsys, tmp_path):
    code, out, _ = run(capsys, "info", "panda")
    assert code == 0
    assert re.search(r"panda_joint1 +elimination_6r \(elimination with joint \d dropped", out)
    assert re.search(r"panda_joint7 +swept_7r \(the swept solver's closed form", out)
    held = ", ".join(f"panda_joint{k}" for k in range(1, 8))
    assert f"analytic with one joint held: {held}\n" in out
    path = write_urdf(tmp_path, iiwa_urdf(), name="iiwa.urdf")
    code, out, _ = run(capsys, "info", str(path), "--base", "base", "--tip", "tool")
    assert code == 0
    assert re.search(r"\n  j3 +spherical_wrist \(spherical wrist at .*axes 1 and 2 meet\)", out)
    held = re.search(r"analytic with one joint held: (.*)\n", out).group(1).split(", ")
    assert held == ["j1", "j2", "j3", "j4", "j5", "j6", "j7"]  # j5, j6: a spherical shoulder
    # joint 7 of the xArm7 leaves an arm the elimination solves (two_intersecting, a
    # search, fits it too); a search alone is not counted as analytic
    code, out, _ = run(capsys, "info", "xarm7")
    assert re.search(r"joint7 +elimination_6r", out)
    held = ", ".join(f"joint{k}" for k in range(1, 8))
    assert f"analytic with one joint held: {held}\n" in out


def test_info_says_the_route_and_why(capsys):
    code, out, _ = run(capsys, "info", "kuka_iiwa14")
    assert code == 0
    assert "solve(_all) -> srs (closed form): SRS, axes 1-3 meet at [0.0, 0.0, 0.36] m" in out
    assert "swivel=PSI  -> srs (closed form): every branch" in out
    code, out, _ = run(capsys, "info", "panda")
    assert "solve(_all) -> dls (numeric): not SRS: axes 5, 6, 7 do not meet" in out
    assert 'applies, only when asked: solver="swept"' in out and "swivel=PSI" not in out
    code, out, _ = run(capsys, "info", "ur5")
    assert "solve(_all) -> three_parallel (closed form)" in out and "hold=" not in out


def test_solve_at_a_swivel_angle_from_the_command_line(capsys):
    args = ["solve", "kuka_iiwa14", "--xyz", "0.5", "0.1", "0.4", "--rpy", "3.1416", "0", "0"]
    code, out, _ = run(capsys, *args, "--swivel", "0.3", "--all")
    assert code == 0 and "swivel angle 0.3 rad" in out and "solution 1 of" in out
