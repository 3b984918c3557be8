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


# The examples in two groups of about equal time, each run in one interpreter
# (tests/run_examples.py): a fresh Python per example paid its start, imports and robot loads
# fifteen times. Two groups, so that two workers can run them side by side; the viewer last
# in its group, as it starts a server's threads.
GROUPS = {
    "plots_and_viewer": [
        "01_worked_example.py",
        "02_elbow_branches.py",
        "03_failure_modes.py",
        "04_choosing_a_solution.py",
        "05_six_and_seven_dof.py",
        "08_many_targets.py",
        "09_view.py",
    ],
    "compare_and_the_rest": [
        "07_compare.py",
        "06_cartesian_path.py",
        "10_collisions.py",
        "11_tolerances.py",
        "12_preferences.py",
        "13_global_path.py",
        "14_two_hands.py",
        "15_servo.py",
    ],
}
RUNNER = Path(__file__).with_name("run_examples.py")


def test_every_example_is_listed():
    assert [p.name for p in EXAMPLES] == sorted(EXPECT)
    assert sorted(name for group in GROUPS.values() for name in group) == sorted(EXPECT)


@pytest.mark.parametrize("group", sorted(GROUPS))
def test_examples_run(group, tmp_path):
    scripts = [str(p) for p in EXAMPLES if p.name in GROUPS[group]]
    scripts.sort(key=lambda s: GROUPS[group].index(Path(s).name))
    proc = subprocess.run(
        [sys.executable, str(RUNNER), str(tmp_path), *scripts],
        capture_output=True,
        text=True,
        timeout=1200,  # a guard against a hang only: a cold compile on a busy machine is slow
        env={"MPLBACKEND": "Agg", "PATH": "", **_env()},
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for name in GROUPS[group]:
        stem = Path(name).stem
        stdout = (tmp_path / f"{stem}.stdout").read_text(encoding="utf-8")
        stderr = (tmp_path / f"{stem}.stderr").read_text(encoding="utf-8")
        assert (tmp_path / f"{stem}.code").read_text(encoding="utf-8") == "0", (name, stderr)
        for words in EXPECT[name]:
            assert words in stdout, (name, words, stdout)
        for png in (tmp_path / stem).glob("*.png"):
            assert png.stat().st_size > 10_000, (name, png)


def test_the_runner_reports_a_failing_example(tmp_path):
    """A script that raises, or exits non-zero, is reported so and the next still runs."""
    (tmp_path / "bad.py").write_text("print('before')\nraise RuntimeError('broken')\n")
    (tmp_path / "quit.py").write_text("import sys\nsys.exit(3)\n")
    (tmp_path / "good.py").write_text("import sys\nprint('fine', sys.argv[1:2])\n")
    out = tmp_path / "out"
    scripts = [str(tmp_path / f"{n}.py") for n in ("bad", "quit", "good")]
    proc = subprocess.run(
        [sys.executable, str(RUNNER), str(out), *scripts], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert (out / "bad.code").read_text() == "1"
    assert "RuntimeError: broken" in (out / "bad.stderr").read_text()
    assert (out / "bad.stdout").read_text() == "before\n"
    assert (out / "quit.code").read_text() == "3"
    assert (out / "good.code").read_text() == "0"
    assert (out / "good.stdout").read_text() == "fine ['--out']\n"


def _env() -> dict:
    import os

    return {k: v for k, v in os.environ.items() if k != "DISPLAY"}


def test_an_out_folder_that_cannot_be_written_is_one_line(tmp_path):
    # it was a FileNotFoundError's traceback from Path.mkdir
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    example = next(e for e in EXAMPLES if e.name.startswith("02_"))
    done = subprocess.run(
        [sys.executable, str(example), "--out", str(blocker / "figures")],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert f"--out {blocker / 'figures'}: cannot write there" in done.stderr
