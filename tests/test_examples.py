"""Every example script runs headless and says what it should."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).parents[1] / "examples").glob("[0-9][0-9]_*.py"))
EXPECT = {
    "01_worked_example.py": ["elbow-up", "elbow-down", "88.209"],
    "02_elbow_branches.py": ["elbow_branches.png"],
    "03_failure_modes.py": ["too far", "inner dead zone", "singular=True"],
    "04_choosing_a_solution.py": ["picks elbow-down", "joint_limits"],
    "05_six_and_seven_dof.py": ["ur5", "panda", "unreachable", "among them: True"],
    "06_cartesian_path.py": ["100/100 points reached"],
    "07_compare.py": [
        "planar2r",
        "three_parallel",
        "spherical",
        "| panda (joint 1 locked) | elimination_6r |",
        "| random two_parallel arm | elimination_6r |",
        "| random two_intersecting arm | elimination_6r |",
        "success_vs_boundary.png",
    ],
    "08_many_targets.py": ["batch:", "no snap back", "discontinuous", "reach_panda.png"],
    "09_view.py": ["8 branches, all verified: True", "ur5_branches.png"],
    "10_collisions.py": [
        "in collision",
        "collision: in collision",
        "collision-free: True",
        "look-at with constraints: converged by tasks",
        "wrist_3 at 0.000, collision-free: True",
    ],
    "11_tolerances.py": [
        "point and direction: converged",
        "200/200 solved",
        "converged in 0 iterations",
        "a region 2 m away: unreachable",
        "so101: converged by dls",
        "ur5: converged by dls",
    ],
    "12_preferences.py": [
        "manipulability |    True",
        "by swept",
        "prefer=broken raised ValueError",
    ],
    "13_global_path.py": [
        "follow: 149/150 waypoints; at 100: discontinuous",
        "global: 150/150 waypoints",
        "a forced jump at waypoint 10: discontinuous",
    ],
    "14_two_hands.py": [
        "shared joints ['torso_1_joint', 'torso_2_joint']",
        "both poses: converged",
        "a box in both hands, lifted: converged",
        "batch: 20/20 solved",
        "a right hand 2 m away: unreachable: tip 'gripper_right_base_link'",
    ],
    "15_servo.py": [
        "jump: ['acceleration_limit', 'tracking', 'velocity_limit'] on the way",
        "s: on_target",
        "3 m away: out_of_reach, NaN: False",
        "m, on_target",
        "{'position': 0.0, 'velocity': 0.0, 'acceleration': 0.0}",
    ],
}


def test_every_example_is_listed():
    assert [p.name for p in EXAMPLES] == sorted(EXPECT)


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(script, tmp_path):
    proc = subprocess.run(
        [sys.executable, str(script), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=1200,  # a guard against a hang only: a cold compile on a busy machine is slow
        env={"MPLBACKEND": "Agg", "PATH": "", **_env()},
    )
    assert proc.returncode == 0, proc.stderr
    for words in EXPECT[script.name]:
        assert words in proc.stdout, proc.stdout
    for png in tmp_path.glob("*.png"):
        assert png.stat().st_size > 10_000


def _env() -> dict:
    import os

    return {k: v for k, v in os.environ.items() if k != "DISPLAY"}
